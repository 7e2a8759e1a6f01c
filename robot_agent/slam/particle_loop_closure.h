#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_LOOP_CLOSURE_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_LOOP_CLOSURE_H_

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot_agent/slam/loop_closure.h"
#include "robot_agent/slam/particle_filter.h"
#include "shared/core/rigid2d.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

struct ParticleLoopClosureOptions {
  // Off, the particle filter reports its best particle's poses and maps unchanged. On by
  // default: it helps where the filter does not close loops (RBPF aces 0.048-0.097 m ->
  // 0.044-0.045 m over seeds 1-3; FastSLAM intel 0.14-0.86 m -> 0.06 m, aces, rectangle) and
  // leaves intel's errors as they were. It costs time (intel RBPF 13-22 s -> 30 s wall, with
  // Rbpf()'s sparser nodes) and memory (the targets of a few submaps and every node's returns:
  // 118 MiB peak for fleetmap-slam on intel, within GMapping's 149 MiB only since the tool keeps
  // its submaps packed).
  bool enabled = true;
  // A keyframe goes to the pose graph once every particle descends from it (no resampling can
  // change it any more) or, at the latest, once it is this many keyframes old. Resampling keeps
  // rewriting the best particle's history; a pose graph node cannot follow that, and the layer
  // ignores what the filter changes in a keyframe after it settled. The RBPF's particles often
  // share nothing for 150-200 keyframes (intel, building); at 20 the filter later moved about a
  // third of the settled keyframes (aces 120 of 420, worst 0.24 m; rectangle_1lap's end, which
  // the filter closes itself by resampling, went from 0.15 m to 0.82 m); at 50, aces 17 of 420
  // (worst 0.06 m), rectangle_1lap 0, and aces/intel errors equal those of waiting for sharing.
  int settle_keyframes = 50;
  // Scans between keyframes become graph nodes when the robot moved this far since the previous
  // node (the scan-matching backend's insertion filter, which LoopClosure's defaults are tuned
  // for); keyframe scans always do.
  double node_min_translation = 0.1;
  double node_min_rotation = 0.087;
  // At the end of input, when the filter moved settled keyframes, the pose graph is built again
  // from the best particle's final history (the graph's work once more, the node scans kept
  // meanwhile): the settled chain drifts from the filter's final answer by every change it
  // ignored (RBPF building_1lap, seed 2: 2.8 m without the layer, 5.2 m with it and no loop
  // closure at all, 125 settled keyframes moved by up to 1.5 m).
  bool rebuild_at_finish = true;
  LoopClosureOptions graph;
};

// The newest keyframe index (>= `from`) that every particle's history shares, -1 when none: no
// resampling can change that keyframe, or any before it, any more.
int64_t NewestSharedKeyframe(const std::vector<Particle>& particles, int64_t from);

// Cartographer-style global loop closure (LoopClosure) over a particle filter's best trajectory.
// The filter revises its best particle's recent history when it resamples, so keyframes reach
// the pose graph only once they settled (see ParticleLoopClosureOptions::settle_keyframes).
// Settled keyframes form the layer's local chain; keyframes after the newest settled one follow
// it by the filter's current relative poses. Reported poses are the graph's correction applied
// to that chain; submaps (groups of keyframes_per_submap keyframes, as ParticleSubmaps cuts
// them) are re-anchored at the graph's submap poses.
class ParticleLoopClosure {
 public:
  ParticleLoopClosure(const ParticleLoopClosureOptions& options, int keyframes_per_submap);

  // A scan's returns (robot frame), its pose being `offset` in keyframe `keyframe`'s frame; kept
  // until that keyframe settles. `keyframe` must not have settled yet.
  void AddScan(double timestamp, size_t keyframe, const Rigid2d& offset,
               std::vector<Eigen::Vector2f> points);
  // The best particle's keyframe poses (oldest first) after a filter update: settles the
  // keyframes that became final or old enough (never the newest), given `shared_up_to` (see
  // NewestSharedKeyframe), and feeds their scans to the graph. Returns true when the graph's
  // corrections changed.
  bool Update(const std::vector<Rigid2d>& filter_poses, int64_t shared_up_to);
  // End of input: settles every keyframe and closes the graph. Returns true when corrections
  // changed.
  bool Finish(const std::vector<Rigid2d>& filter_poses);

  // The layer's local pose of keyframe `keyframe` given the filter's current poses.
  Rigid2d LocalKeyframePose(size_t keyframe, const std::vector<Rigid2d>& filter_poses) const;
  // LocalKeyframePose for every keyframe: what the submaps are rendered at.
  std::vector<Rigid2d> LocalKeyframePoses(const std::vector<Rigid2d>& filter_poses) const;
  // A local pose (LocalKeyframePose * offset) at `timestamp`, corrected by the graph.
  Rigid2d Corrected(double timestamp, const Rigid2d& local) const {
    return closure_->CorrectionAt(timestamp) * local;
  }

  // Moves a submap rendered at LocalKeyframePoses into the corrected frame and numbers its
  // revision (every hand-out of a submap gets a higher one).
  void CorrectSubmap(Submap* submap);
  // Submaps handed out whose correction changed since: to be rendered again and corrected. Only
  // their poses are kept here, not their grids (two copies of every grid took 340 MB on intel).
  std::vector<int64_t> TakeMovedSubmaps();

  size_t settled() const { return settled_.size(); }
  std::string Statistics() const;

 private:
  struct PendingScan {
    double timestamp;
    size_t keyframe;
    Rigid2d offset;
    std::vector<Eigen::Vector2f> points;
  };
  void Settle(size_t keyframe, const std::vector<Rigid2d>& filter_poses);
  // Starts the graph again: every scan fed so far waits for its keyframe to settle anew.
  void Restart();
  // Counts settled keyframes the filter has since moved (how often settling was premature).
  void CountRevisions(const std::vector<Rigid2d>& filter_poses);
  struct Placement {
    Rigid2d submap_in_local;
    Trajectory scan_poses;
  };
  Placement ToCorrected(int64_t submap_id, const Placement& local) const;
  // Whether the anchor or a scan pose moved by more than what rounding could explain.
  static bool Moved(const Placement& before, const Placement& after);

  struct Published {
    Placement local;      // as ParticleSubmaps rendered it
    Placement corrected;  // as last handed out
    int64_t revision = -1;
  };

  const ParticleLoopClosureOptions options_;
  const size_t per_submap_;
  std::unique_ptr<LoopClosure> closure_;
  std::deque<PendingScan> pending_;
  std::vector<PendingScan> nodes_;         // fed to the graph; kept for rebuild_at_finish
  std::vector<Rigid2d> settled_;           // the layer's local keyframe poses
  std::vector<Rigid2d> filter_at_settle_;  // the filter's pose of each when it settled
  std::vector<bool> revised_;
  std::optional<Rigid2d> last_node_;
  bool corrections_changed_ = false;  // during the current Update or Finish
  bool submaps_moved_ = false;        // corrections changed since the last TakeMovedSubmaps
  std::map<int64_t, Published> published_;
  int64_t settled_shared_ = 0;  // keyframes settled because every particle shares them
  int64_t revised_count_ = 0;
  bool rebuilt_ = false;
  double worst_revision_ = 0.0;  // metres
  size_t worst_lag_ = 0;         // keyframes not yet settled, at most
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_LOOP_CLOSURE_H_
