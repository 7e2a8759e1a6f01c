#include "robot_agent/agent/map_subscriber.h"

#include <chrono>
#include <utility>

#include "robot_agent/agent/internal/status_codes.h"
#include "robot_agent/agent/proto_conversions.h"
#include "shared/io/map_file.h"

namespace fleetmap {

MapSubscriber::MapSubscriber(const MapSubscriberOptions& options,
                             std::shared_ptr<grpc::ChannelInterface> channel)
    : options_(options), stub_(v1::MapService::NewStub(channel)), random_(std::random_device()()) {}

MapSubscriber::~MapSubscriber() { Stop(); }

void MapSubscriber::Start() {
  thread_ = std::thread([this] { Loop(); });
}

void MapSubscriber::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    if (active_call_) active_call_->TryCancel();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::shared_ptr<const GlobalMapView> MapSubscriber::latest() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

const std::string MapSubscriber::last_error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_error_;
}

void MapSubscriber::Loop() {
  int failures = 0;
  while (true) {
    grpc::ClientContext context;
    v1::SubscribeMapUpdatesRequest request;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
      active_call_ = &context;
      // Resume after what we have; 0 asks for the latest existing version first.
      request.set_after_version(latest_ ? latest_->version : 0);
    }
    request.set_include_grid(true);
    std::unique_ptr<grpc::ClientReader<v1::MapUpdate>> reader =
        stub_->SubscribeMapUpdates(&context, request);
    v1::MapUpdate update;
    while (reader->Read(&update)) {
      streaming_ = true;
      failures = 0;
      Apply(update);
    }
    const grpc::Status status = reader->Finish();
    streaming_ = false;
    double wait;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      active_call_ = nullptr;
      if (stop_) return;
      last_error_ = "SubscribeMapUpdates: " + internal::Describe(status);
      ++failures;
      ++reconnects_;
      wait = BackoffDelay(options_.reconnect, failures,
                          std::uniform_real_distribution<double>(0.0, 1.0)(random_));
    }
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait_for(lock, std::chrono::duration<double>(wait), [&] { return stop_; });
  }
}

void MapSubscriber::Apply(const v1::MapUpdate& update) {
  auto view = std::make_shared<GlobalMapView>();
  view->version = update.version().version();
  view->created_unix_time = update.version().created_unix_time();
  if (update.has_map() && update.map().has_grid()) {
    GridDecodeError code;
    std::string error;
    if (Decompress(agent::FromProto(update.map().grid()), GridLimits(), &view->grid, &code,
                   &error)) {
      view->has_grid = true;
    } else {
      std::lock_guard<std::mutex> lock(mutex_);
      last_error_ = "version " + std::to_string(view->version) + ": unusable grid: " + error;
    }
  }
  for (const v1::RobotPlacement& placement : update.version().placements()) {
    RobotInGlobal robot;
    robot.robot_id = placement.robot_id();
    robot.placed = placement.placed();
    if (robot.placed) robot.local_in_global = agent::FromProto(placement.local_in_global());
    view->robots.push_back(std::move(robot));
  }
  QueryRobots(view.get());
  if (!options_.file.empty() && view->has_grid) SaveFile(*view);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // Without a grid in this update, keep showing the last one we had.
    if (!view->has_grid && latest_ && latest_->has_grid) {
      view->grid = latest_->grid;
      view->has_grid = true;
    }
    latest_ = std::move(view);
  }
  ++versions_received_;
}

void MapSubscriber::QueryRobots(GlobalMapView* view) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::microseconds(static_cast<int64_t>(options_.rpc_timeout * 1e6)));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
  }
  v1::GetRobotsResponse response;
  const grpc::Status status = stub_->GetRobots(&context, v1::GetRobotsRequest(), &response);
  if (!status.ok()) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_error_ = "GetRobots: " + internal::Describe(status);
    return;  // the placements of the version itself remain
  }
  view->robots.clear();
  for (const v1::RobotInfo& info : response.robots()) {
    RobotInGlobal robot;
    robot.robot_id = info.robot_id();
    robot.placed = info.placement().placed();
    if (robot.placed) robot.local_in_global = agent::FromProto(info.placement().local_in_global());
    if (info.has_latest_pose()) {
      robot.latest_pose = StampedPose{info.latest_pose_in_global().timestamp(),
                                      agent::FromProto(info.latest_pose_in_global().pose())};
    }
    view->robots.push_back(std::move(robot));
  }
}

void MapSubscriber::SaveFile(const GlobalMapView& view) {
  std::string error;
  if (!WriteMap(options_.file, Dequantize(view.grid), &error)) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_error_ = "saving the global map: " + error;
  }
}

}  // namespace fleetmap
