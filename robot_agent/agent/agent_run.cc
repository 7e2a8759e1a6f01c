// The agent's main loop: replay or live sensor data into the pipeline, then drain or flush.
#include <chrono>
#include <cstdio>
#include <sstream>
#include <thread>

#include "robot_agent/agent/agent.h"

namespace fleetmap {

int Agent::Run(bool stay) {
  const LocalizationConfig& localization = config_.localization;
  const std::string mode = !localization.enabled ? "SLAM: " + config_.slam.algorithm
                           : localization.map.empty()
                               ? std::string("localization (MCL) in the server's global map")
                               : "localization (MCL) in " + localization.map;
  Log("fleetmap-agent: robot " + config_.robot_id + ", source: " + source_->Describe() + ", " +
      mode + ", server " + config_.server_address + ", outbox " + outbox_->path());
  uploader_->Start();
  if (subscriber_) subscriber_->Start();
  if (densities_) densities_->Start();
  if (!pipeline_ && !WaitForServerMap()) {
    uploader_->Stop();
    if (subscriber_) subscriber_->Stop();
    if (densities_) densities_->Stop();
    return stop_requested() ? kAgentOk : kAgentFailed;
  }
  std::thread status([this] { StatusLoop(); });

  int exit_code = kAgentOk;
  std::string error;
  SensorEvent event;
  // Replay pacing: sensor time maps to wall time through the first event.
  double first_sensor_time = 0.0;
  double first_wall_time = 0.0;
  bool first = true;
  while (!stop_requested() && source_->Next(&event)) {
    if (config_.source.speed > 0.0) {
      if (first) {
        first_sensor_time = event.timestamp;
        first_wall_time = UnixNow();
      }
      const double due =
          first_wall_time + (event.timestamp - first_sensor_time) / config_.source.speed;
      if (!SleepFor(due - UnixNow())) break;
    }
    first = false;
    FollowServerMap();
    ApplyReceivedDensities();
    if (!pipeline_->Process(event, &error)) {
      Log("error: " + error);
      exit_code = kAgentFailed;
      break;
    }
    NoteLocalization();
  }
  if (!source_->error().empty()) {
    Log("error: " + source_->error());
    exit_code = kAgentFailed;
  }
  // Whatever ended the input, what was mapped so far goes to the outbox.
  if (exit_code == kAgentOk || !source_->error().empty()) {
    if (!pipeline_->Finish(&error)) {
      Log("error: " + error);
      exit_code = kAgentFailed;
    }
  }
  const bool stopped = stop_requested();
  if (!stopped) {
    Log("source finished: " + std::to_string(pipeline_->counters().scans.load()) + " scans; " +
        pipeline_->slam().Statistics());
  }
  if (stopped) {
    Log("stopping: flushing the outbox for at most " +
        std::to_string(config_.upload.flush_timeout) + " s");
    Drain(config_.upload.flush_timeout, /*stop_ends_wait=*/false);
  } else if (stay) {
    Log("source finished; staying until SIGINT/SIGTERM");
    while (SleepFor(3600.0)) {
    }
    Drain(config_.upload.flush_timeout, /*stop_ends_wait=*/false);
  } else if (!Drain(config_.upload.drain_timeout, /*stop_ends_wait=*/true)) {
    if (stop_requested()) {
      Drain(config_.upload.flush_timeout, /*stop_ends_wait=*/false);
    } else if (exit_code == kAgentOk) {
      exit_code = kAgentDrainTimedOut;
    }
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
  }
  stop_cv_.notify_all();
  status.join();
  uploader_->Stop();
  if (subscriber_) subscriber_->Stop();
  if (densities_) densities_->Stop();
  OutboxCounts counts;
  outbox_->Counts(&counts, &error);
  Log(StatusLine());
  if (counts.pending > 0) {
    Log(std::to_string(counts.pending) +
        " items stay in the outbox and will be sent on the next start");
  }
  return exit_code;
}

std::string Agent::StatusLine() const {
  if (!pipeline_) return "waiting for the server's global map to localize in";
  const PipelineCounters& counters = pipeline_->counters();
  const UploaderStats stats = uploader_->stats();
  OutboxCounts counts;
  std::string error;
  outbox_->Counts(&counts, &error);
  std::ostringstream line;
  line.setf(std::ios::fixed);
  line.precision(1);
  line << "t=" << UnixNow() - start_wall_ << "s scans=" << counters.scans
       << " submaps queued=" << counters.submaps_queued << " sent=" << stats.acked_submaps
       << " pending=" << counts.pending_submaps
       << " | trajectories sent=" << stats.acked_trajectories
       << " pending=" << counts.pending_trajectories
       << " | detections queued=" << counters.detections_queued
       << " sent=" << stats.acked_detections
       << " pending=" << counts.pending_detections << " masked returns=" << counters.masked_returns
       << " laser bodies=" << counters.laser_bodies
       << " | rejected=" << counts.rejected
       << " duplicates=" << stats.duplicates << " | server " << ConnectionStateName(stats.state);
  if (stats.state == ConnectionState::kDisconnected && !stats.last_error.empty()) {
    line << " (" << stats.last_error << ")";
  }
  if (const DetectionStage* detection = pipeline_->detection_stage()) {
    line << " (frames=" << detection->counters().frames
         << " unpaired=" << detection->counters().unpaired_frames
         << " unusable=" << detection->counters().unusable_frames << ")";
  }
  if (subscriber_) {
    const auto map = subscriber_->latest();
    line << " | map " << (subscriber_->streaming() ? "streaming" : "not streaming");
    if (map) line << " v" << map->version;
  }
  if (localizer_) {
    line << " | MCL " << (converged_ ? "converged" : "not converged") << " (std "
         << localization_std_.load() << " m";
    // After a global start the filter can converge on a look-alike place (docs/BENCHMARKS.md,
    // issue 10, session 35) until another robot's detection confirms it.
    if (globally_localizing_) line << ", global start not confirmed by a detection";
    line << ")";
  }
  if (follows_server_map_) line << " in map v" << server_map_version_;
  if (densities_) {
    const DensityExchangeStats d = densities_->stats();
    line << " | densities " << (densities_->subscribed() ? "listening" : "not listening")
         << " sent=" << d.sent << " delivered=" << d.delivered << " failed=" << d.send_failed
         << " received=" << d.received << " dropped=" << d.dropped;
  }
  return line.str();
}

}  // namespace fleetmap
