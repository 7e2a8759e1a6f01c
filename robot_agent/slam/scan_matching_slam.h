#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SCAN_MATCHING_SLAM_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SCAN_MATCHING_SLAM_H_

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "robot_agent/slam/local_match_map.h"
#include "robot_agent/slam/local_slam.h"
#include "robot_agent/slam/loop_closure.h"
#include "robot_agent/slam/odometry_buffer.h"
#include "robot_agent/slam/submap_builder.h"
#include "shared/matching/scan_matcher.h"

namespace fleetmap {

struct ScanMatchingSlamOptions {
  std::string robot_id = "robot";
  // Returns farther than this are left out of matching and mapping (metres).
  float max_range = 20.0f;
  // Returns within this distance (metres) of the laser's horizon (the smaller of the scan's
  // range_max and max_range) are mapped but not matched. The map's walls end where earlier
  // scans' horizon cut them, just behind the new scan's horizon; those last points would land
  // past the map's wall ends and pull the match back towards the previous pose (in a corridor,
  // ~0.5 m lost as its far end comes into range).
  float match_range_margin = 1.0f;
  // Matching uses every k-th beam where returns are closer together than this (metres;
  // ThinBeams), so that near walls do not outvote far ones. It was one return per 5 cm voxel,
  // which picks returns by their range noise and turned the matches: the simulated building lap
  // ended 1.7-4.8 m off with voxels of 4.9 to 10 cm, and 0.0-0.7 m with 5 cm by luck; now
  // 0.0-0.4 m (docs/BENCHMARKS.md, issue 8, session 14).
  float match_beam_spacing = 0.05f;
  // The loop closure's node scans keep one return per voxel of this size (metres). Thinned like
  // the matched returns instead they read the same on the simulator's scenarios (8 seeds); the
  // logs' loop closures were not measured that way, so they keep the voxels (session 14).
  float node_voxel_size = 0.05f;
  LocalMatchMapOptions local_map;
  // Every scan is refined against the local map from the odometry prediction. When the refined
  // score is below `search_below_score`, a correlative search over matcher.search's window runs
  // first (bad odometry, e.g. a wheel slip in a turn).
  ScanMatcherOptions matcher = DefaultMatcherOptions();
  double search_below_score = 0.75;
  // Each match is refined a second time without the points on surfaces the local map has not
  // seen (seen_surface_filter.h), judged at the first match: farther than this (metres) from
  // every mapped surface, in cells no scan observed. A box's far face coming into view as the
  // robot turns round it was pulled onto the face beside it, and the map turned by ~1 degree per
  // box. New faces a few centimetres from a mapped wall pull as well (a door jamb's side as the
  // door comes into view, a wall seen through a door): at 7.5 cm even noise-free simulated scans
  // turned the department's local maps by 0.1-0.3 degrees. 3 cm is three times the simulator's
  // range noise, so that a mapped wall's own returns stay (docs/BENCHMARKS.md, issue 8, session
  // 28). Judged at the odometry prediction instead, poor odometry (aces) dropped points of mapped
  // walls. 0 turns the second refinement off; without odometry it does not run.
  double max_unseen_surface_distance = 0.03;
  // A featureless corridor: where less than this share of the scan's surface normals (see
  // NormalScatter) faces a direction, the match keeps the odometry's translation along it.
  // 0 disables the check.
  double min_observed_normals = 0.03;
  // Without odometry the search always runs, over this window.
  CorrelativeSearchOptions no_odometry_search = NoOdometrySearchOptions();
  // Motion filter: a scan enters the local map and the submap only when the robot moved this far
  // (metres / radians) or this long (seconds) since the last inserted scan.
  double insert_min_translation = 0.1;
  double insert_min_rotation = 0.087;
  double insert_max_interval = 10.0;
  SubmapOptions submaps;
  // Off, the backend only tracks: every scan is matched against the local map and nothing goes
  // into submaps or loop closure (the particle backends' per-scan tracker, see ParticleSlam).
  bool build_submaps = true;
  // Global SLAM on top: loop closures against finished submaps and a pose graph.
  LoopClosureOptions loop_closure;

  static ScanMatcherOptions DefaultMatcherOptions();
  static CorrelativeSearchOptions NoOdometrySearchOptions();
};

// Incremental maximum-likelihood mapping (Hähnel et al.): every scan is matched against the map
// of recent scans, starting from the odometry prediction, and inserted when the robot moved.
// The matcher runs in a local frame that drifts; LoopClosure corrects it (Cartographer-style),
// and every output pose and submap is corrected. A graph optimisation that moves poses bumps
// trajectory_revision() and re-publishes the finished submaps it moved.
class ScanMatchingSlam : public LocalSlam {
 public:
  explicit ScanMatchingSlam(const ScanMatchingSlamOptions& options = ScanMatchingSlamOptions());

  bool AddOdometry(const StampedPose& odometry, std::string* error) override;
  bool AddScan(const LaserScan& scan, std::string* error) override;
  Rigid2d CurrentPose() const override;
  const Trajectory& trajectory() const override { return trajectory_; }
  int64_t trajectory_revision() const override { return revision_; }
  using LocalSlam::TakeSubmapUpdates;
  std::vector<Submap> TakeSubmapUpdates(size_t max_count) override;
  void Finish() override;
  std::string Statistics() const override;

  struct Counters {
    int64_t scans = 0;
    int64_t no_return_scans = 0;
    int64_t matched = 0;
    int64_t searched = 0;
    int64_t failed = 0;  // carried by odometry because the match was too poor
    int64_t inserted = 0;
    int64_t degenerate = 0;  // kept the odometry's translation along an unobserved direction
  };
  const Counters& counters() const { return counters_; }

 private:
  // `points` in beam order: the corridor test (NormalScatter) takes normals from neighbours.
  Rigid2d Match(const std::vector<Eigen::Vector2f>& points, const Rigid2d& predicted);
  bool ShouldInsert(const Rigid2d& pose, double timestamp) const;
  // After a graph optimisation: re-derives every scan's corrected pose.
  void ApplyCorrections();
  // Moves a submap snapshot (in the local frame) into the corrected frame.
  void ToCorrected(const Rigid2d& local_anchor, const Trajectory& local_poses, Submap* submap) const;

  // A finished submap already handed out, kept to re-publish it when the graph moves it.
  struct Published {
    Rigid2d local_anchor;
    Trajectory local_scan_poses;
    Submap submap;  // as last published (corrected frame)
  };

  const ScanMatchingSlamOptions options_;
  OdometryBuffer odometry_;
  LocalMatchMap local_map_;
  SubmapBuilder submaps_;
  LoopClosure loop_closure_;
  Trajectory trajectory_;           // corrected poses, one per scan
  std::vector<Rigid2d> local_poses_;  // the frontend's poses, one per scan
  Rigid2d current_pose_;            // the frontend's (local) pose at the latest scan
  int64_t revision_ = 0;
  bool submaps_moved_ = false;      // corrections changed since the last TakeSubmapUpdates
  std::map<int64_t, Published> published_;
  std::optional<Rigid2d> last_odometry_;  // at the previous scan
  std::optional<StampedPose> last_inserted_;
  double last_time_ = -1e300;
  Counters counters_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SCAN_MATCHING_SLAM_H_
