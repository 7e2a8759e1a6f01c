#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SUBMAPS_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SUBMAPS_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "shared/core/laser_scan.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/submap.h"

namespace fleetmap {

// Exports a particle filter's map as submaps: consecutive keyframe scans are grouped, and each
// group is rendered at the best particle's keyframe poses. When resampling changes the best
// trajectory, the groups whose poses moved are rendered again and published with a higher
// revision. Keyframe scans are kept for that (a few hundred scans for an hour of driving).
class ParticleSubmaps {
 public:
  ParticleSubmaps(std::string robot_id, int keyframes_per_submap, const OccupancyGridOptions& grid);

  // A keyframe scan (ranges already limited); its pose comes with the next SetPoses().
  void AddKeyframe(const LaserScan& scan);
  // The best particle's keyframe poses, one per keyframe added, oldest first.
  void SetPoses(const std::vector<Rigid2d>& keyframe_poses);
  // Ends input: the last group counts as finished.
  void Finish();
  // Submaps new or changed since the last call, at most `max_count` (the rest stay pending).
  std::vector<Submap> TakeUpdates(size_t max_count);
  // A submap handed out before, rendered again at the current poses (grids are not kept: the
  // scans are); empty for ids never handed out.
  std::optional<Submap> RenderPublished(int64_t submap_id) const;

 private:
  struct Group {
    std::vector<Rigid2d> published_poses;
    int64_t revision = -1;
    bool published_finished = false;
  };
  Submap Render(size_t group, bool finished) const;

  std::string robot_id_;
  int per_submap_;
  OccupancyGridOptions grid_options_;
  std::vector<LaserScan> scans_;
  std::vector<Rigid2d> poses_;
  std::vector<Group> groups_;
  bool finishing_ = false;
  bool dirty_ = false;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SUBMAPS_H_
