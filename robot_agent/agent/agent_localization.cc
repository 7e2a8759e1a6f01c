// The agent's localization mode: the filter in the server's map (waited for, then followed) or a
// map file, and pose densities shared with the robots it sees.
#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "robot_agent/agent/agent.h"
#include "robot_agent/agent/localizer_factory.h"

namespace fleetmap {
namespace {

std::string FormatSeconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g s", seconds);
  return text;
}

}  // namespace

void Agent::StartLocalization(std::unique_ptr<MclLocalizer> localizer) {
  localizer_ = localizer.get();
  StartPipeline(std::move(localizer));
  if (densities_) {
    pipeline_->SetDetectionListener([this](const RobotDetection& detection) {
      if (const std::optional<PoseDensity> density = localizer_->DensityOfSeenRobot(detection)) {
        densities_->Send(*density);
      }
    });
  }
}

void Agent::ApplyReceivedDensities() {
  if (!densities_ || !localizer_) return;
  for (const PoseDensity& density : densities_->TakeReceived()) localizer_->ApplyDensity(density);
}

bool Agent::WaitForServerMap() {
  const double wait = config_.localization.map_wait;
  Log("localization: waiting up to " + FormatSeconds(wait) + " for the server's global map");
  const double deadline = UnixNow() + wait;
  double next_progress = UnixNow() + 5.0;
  while (true) {
    const std::shared_ptr<const GlobalMapView> view = subscriber_->latest();
    // A version before any robot mapped a wall has nothing to localize against.
    if (view && view->has_grid &&
        std::any_of(view->grid.cells.begin(), view->grid.cells.end(),
                    [](int8_t cell) { return cell > 0; })) {
      const OccupancyGrid map = Dequantize(view->grid);
      Log("localization: map version " + std::to_string(view->version) + " (" +
          std::to_string(map.width()) + " x " + std::to_string(map.height()) + " cells)");
      follows_server_map_ = true;
      server_map_version_ = view->version;
      StartLocalization(CreateLocalizer(config_.localization, map));
      return true;
    }
    if (UnixNow() >= deadline) {
      const std::string why = !subscriber_->streaming()
                                  ? "not connected (" + subscriber_->last_error() + ")"
                              : view ? "its map has no walls yet"
                                     : "no map version yet";
      Log("error: localization: no global map from the server within " + FormatSeconds(wait) +
          ": " + why + "; give localization.map a map file, or start the mapping robots first");
      return false;
    }
    if (UnixNow() >= next_progress) {
      next_progress += 5.0;
      Log(std::string("localization: still waiting for the global map (server ") +
          (subscriber_->streaming() ? "connected" : "not connected") + ")");
    }
    if (!SleepFor(0.2)) return false;
  }
}

void Agent::FollowServerMap() {
  if (!follows_server_map_) return;
  const std::shared_ptr<const GlobalMapView> view = subscriber_->latest();
  if (!view || view->version <= server_map_version_ || !view->has_grid) return;
  server_map_version_ = view->version;
  localizer_->SetMap(Dequantize(view->grid));
}

void Agent::NoteLocalization() {
  if (!localizer_) return;
  converged_ = localizer_->estimate().converged;
  globally_localizing_ = localizer_->filter().globally_localizing();
  localization_std_ = MaxPositionStd(localizer_->estimate().covariance);
}

}  // namespace fleetmap
