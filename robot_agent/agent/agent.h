#ifndef FLEETMAP_ROBOT_AGENT_AGENT_AGENT_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_AGENT_H_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "robot_agent/agent/agent_config.h"
#include "robot_agent/agent/density_exchange.h"
#include "robot_agent/agent/map_subscriber.h"
#include "robot_agent/agent/mapping_pipeline.h"
#include "robot_agent/agent/outbox.h"
#include "robot_agent/agent/sensor_source.h"
#include "robot_agent/agent/uploader.h"
#include "robot_agent/localization/mcl_localizer.h"

namespace fleetmap {

// Exit codes of fleetmap-agent.
enum AgentExitCode {
  kAgentOk = 0,             // source done and everything acknowledged, or stopped by a signal
  kAgentFailed = 1,         // a fatal error (outbox unusable, source unreadable)
  kAgentDrainTimedOut = 3,  // source done, but the server did not take everything in time
};

// One robot's agent: sensor source -> local SLAM -> outbox -> uploader -> server, plus the
// subscription to the global map. Owns its threads (uploader, subscriber, status lines); the
// sensor loop runs on the caller's thread in Run().
class Agent {
 public:
  // Opens the outbox, the sensor source and the SLAM backend; nullptr + `error` when any of
  // them is unusable.
  static std::unique_ptr<Agent> Create(const AgentConfig& config, std::string* error);
  ~Agent();

  // Processes the source until it ends (then drains the outbox) or until RequestStop() (then
  // flushes for at most upload.flush_timeout). With `stay`, keeps uploading and following the
  // map after the source ends, until RequestStop(). Returns an AgentExitCode.
  int Run(bool stay);
  // Thread-safe; e.g. from the signal thread.
  void RequestStop();

  std::string StatusLine() const;

 private:
  Agent(const AgentConfig& config, std::unique_ptr<Outbox> outbox,
        std::unique_ptr<SensorSource> source);
  // The sensor pipeline around `slam` (the SLAM backend or the localizer).
  void StartPipeline(std::unique_ptr<LocalSlam> slam);
  // Localizing in the server's map: waits for it (localization.map_wait), then starts the
  // pipeline. False on a timeout (said in the log) or a stop request.
  bool WaitForServerMap();
  // Localizing in the server's map: moves the filter to a newer version once one has arrived.
  void FollowServerMap();
  // Localization mode: the pipeline around the filter, which shares what the robot sees.
  void StartLocalization(std::unique_ptr<MclLocalizer> localizer);
  // Collaborative localization: what other robots said about this one, into the filter.
  void ApplyReceivedDensities();
  // The filter's state for the status lines (read on another thread).
  void NoteLocalization();
  bool stop_requested() const;
  // Sleeps until `seconds` from now or a stop request; false when stopped.
  bool SleepFor(double seconds);
  // Waits for the outbox to empty within `timeout` (0 = not at all), or a stop request.
  bool Drain(double timeout, bool stop_ends_wait);
  void StatusLoop();
  void Log(const std::string& line) const;

  const AgentConfig config_;
  const double start_wall_;
  std::unique_ptr<Outbox> outbox_;
  std::unique_ptr<SensorSource> source_;
  std::unique_ptr<DetectionStage> detection_;   // until the pipeline takes it
  std::unique_ptr<MappingPipeline> pipeline_;   // null until the localization map is there
  MclLocalizer* localizer_ = nullptr;           // localization mode; owned by pipeline_
  bool follows_server_map_ = false;             // localizing in the server's map, not a file
  std::unique_ptr<DensityExchange> densities_;  // localization mode with share_detections
  std::atomic<int64_t> server_map_version_{0};  // the version it localizes in (status lines)
  std::atomic<bool> converged_{false};          // the filter's estimate converged
  std::atomic<bool> globally_localizing_{false};  // ... from a global start, not confirmed
  std::atomic<double> localization_std_{0.0};     // metres, its largest position std
  std::unique_ptr<Uploader> uploader_;
  std::unique_ptr<MapSubscriber> subscriber_;

  mutable std::mutex mutex_;  // guards stop_ and done_
  std::condition_variable stop_cv_;
  bool stop_ = false;
  bool done_ = false;  // Run() is over: the status thread ends
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_AGENT_H_
