#include "robot_agent/agent/agent.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <thread>
#include <utility>

#include "robot_agent/agent/detection_factory.h"
#include "robot_agent/agent/localizer_factory.h"
#include "robot_agent/agent/proto_conversions.h"
#include "robot_agent/agent/slam_factory.h"
#ifdef FLEETMAP_AGENT_HAVE_SIM
#include "robot_agent/agent/sim_source.h"
#endif

namespace fleetmap {
namespace {

// gRPC's own reconnect backoff grows to 2 minutes by default; keep it within ours so that a
// server that comes back is seen within a few seconds.
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& address,
                                           const BackoffOptions& backoff) {
  grpc::ChannelArguments args;
  const int max_ms = static_cast<int>(std::clamp(backoff.max, 0.1, 5.0) * 1000.0);
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, std::min(max_ms, 200));
  args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, std::min(max_ms, 200));
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, max_ms);
  args.SetMaxReceiveMessageSize(256 << 20);  // global maps can be large
  return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
}

}  // namespace

std::unique_ptr<Agent> Agent::Create(const AgentConfig& config, std::string* error) {
  std::unique_ptr<Outbox> outbox = Outbox::Open(config.outbox_path, error);
  if (!outbox) return nullptr;
  std::unique_ptr<SensorSource> source = OpenSensorSource(config.source, error);
  if (!source) return nullptr;
  // Mapping: the SLAM backend. Localizing in a map file: the filter. Localizing in the server's
  // map: the filter once the map has arrived (Run).
  std::unique_ptr<LocalSlam> slam;
  std::unique_ptr<MclLocalizer> localizer;
  if (!config.localization.enabled) {
    slam = CreateLocalSlam(config.slam, config.robot_id, error);
    if (!slam) return nullptr;
  } else if (!config.localization.map.empty()) {
    OccupancyGrid map;
    if (!ReadLocalizationMap(config.localization, &map, error)) return nullptr;
    localizer = CreateLocalizer(config.localization, map);
  }
  std::unique_ptr<Agent> agent(new Agent(config, std::move(outbox), std::move(source)));
  if (config.detection.enabled) {
    agent->detection_ = CreateDetectionStage(config, *agent->source_, error);
    if (!agent->detection_) return nullptr;
  }

  auto channel = MakeChannel(config.server_address, config.upload.uploader.backoff);
  v1::RegisterRobotRequest registration;
  registration.set_robot_id(config.robot_id);
  registration.set_name(config.robot_name.empty() ? config.robot_id : config.robot_name);
  registration.set_sensor_description(agent->source_->Describe());
  registration.set_algorithm(config.localization.enabled ? "mcl" : config.slam.algorithm);
  // Localizing: poses are in the known map's frame, which start_pose places in the global frame
  // (the server's own map needs no placement).
  registration.set_localization_only(config.localization.enabled);
  if (config.start_pose)
    *registration.mutable_local_in_global() = agent::ToProto(*config.start_pose);
  agent->uploader_ = std::make_unique<Uploader>(config.upload.uploader, agent->outbox_.get(),
                                                channel, registration);
  if (config.map.subscribe) {
    MapSubscriberOptions options;
    options.reconnect = config.map.reconnect;
    options.file = config.map.file;
    agent->subscriber_ = std::make_unique<MapSubscriber>(options, channel);
  }
  if (config.localization.enabled && config.localization.share_detections) {
    DensityExchangeOptions options;
    options.robot_id = config.robot_id;
    options.reconnect = config.map.reconnect;
    agent->densities_ = std::make_unique<DensityExchange>(options, channel);
  }
  if (slam) agent->StartPipeline(std::move(slam));
  if (localizer) agent->StartLocalization(std::move(localizer));
  return agent;
}

void Agent::StartPipeline(std::unique_ptr<LocalSlam> slam) {
  MappingPipelineOptions pipeline;
  pipeline.robot_id = config_.robot_id;
  pipeline.trajectory_period = config_.upload.trajectory_period;
  pipeline.active_submap_period = config_.upload.active_submap_period;
  pipeline.mask_seen_robots = config_.detection.mask_seen_robots;
  if (config_.detection.mask_laser_bodies) {
    pipeline.laser_body_radius = config_.detection.marker.body_radius;
    pipeline.laser_bodies.fusion.range_noise = config_.detection.laser_range_noise;
#ifdef FLEETMAP_AGENT_HAVE_SIM
    if (const auto* sim = dynamic_cast<const SimSource*>(source_.get())) {
      pipeline.laser_body_radius = sim->simulation().scenario().body.radius;
    }
#endif
  }
  Uploader* uploader = uploader_.get();
  pipeline_ = std::make_unique<MappingPipeline>(pipeline, std::move(slam), outbox_.get(), UnixNow,
                                                [uploader] { uploader->Notify(); });
  if (detection_) pipeline_->SetDetectionStage(std::move(detection_));
}

Agent::Agent(const AgentConfig& config, std::unique_ptr<Outbox> outbox,
             std::unique_ptr<SensorSource> source)
    : config_(config),
      start_wall_(UnixNow()),
      outbox_(std::move(outbox)),
      source_(std::move(source)) {}

Agent::~Agent() {
  if (densities_) densities_->Stop();
  if (subscriber_) subscriber_->Stop();
  if (uploader_) uploader_->Stop();
}

void Agent::RequestStop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  stop_cv_.notify_all();
}

bool Agent::stop_requested() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stop_;
}

bool Agent::SleepFor(double seconds) {
  std::unique_lock<std::mutex> lock(mutex_);
  return !stop_cv_.wait_for(lock, std::chrono::duration<double>(std::max(0.0, seconds)),
                            [&] { return stop_; });
}

void Agent::Log(const std::string& line) const {
  std::printf("[%s] %s\n", config_.robot_id.c_str(), line.c_str());
  std::fflush(stdout);
}

bool Agent::Drain(double timeout, bool stop_ends_wait) {
  const double deadline = UnixNow() + timeout;
  while (true) {
    const double left = deadline - UnixNow();
    if (uploader_->WaitUntilEmpty(std::clamp(left, 0.0, 0.2))) return true;
    if (left <= 0.0 || (stop_ends_wait && stop_requested())) return false;
  }
}

void Agent::StatusLoop() {
  if (config_.status_period <= 0.0) return;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_cv_.wait_for(lock, std::chrono::duration<double>(config_.status_period),
                            [&] { return done_; })) {
    lock.unlock();
    Log(StatusLine());
    lock.lock();
  }
}

}  // namespace fleetmap
