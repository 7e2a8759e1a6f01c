#ifndef FLEETMAP_ROBOT_AGENT_SLAM_RETURN_PERSISTENCE_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_RETURN_PERSISTENCE_H_

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "shared/matching/scan_segments.h"

namespace fleetmap {

struct ReturnPersistenceOptions {
  // A return persists when it lies this close (metres) to the surface the previous scan saw:
  // above the range noise of the lasers we map with (1-2 cm), below what a robot at walking
  // pace moves between two scans (6-8 cm at 0.6-0.8 m/s and 10 Hz). 0 lets every return through.
  double tolerance = 0.03;
  // Consecutive returns of the previous scan closer than this (metres) are joined into a piece
  // of surface: the beams hit a surface at other spots from a new pose.
  double max_join = 0.2;
  // Farther apart, they are joined when they lie on one surface (JoinConsecutiveReturns): far
  // down a wall seen at a shallow angle the returns are tens of centimetres apart.
  ScanSegmentOptions segments;
};

// Tells returns off surfaces that stay where they are from returns off something moving. Another
// robot driving ahead the same way is seen at the same distance scan after scan, always stepping
// into space hidden behind itself: it is never "seen free", so the moved-object test cannot
// catch it, and in the map it leaves a trail whose front end holds the follower back (its scan
// matches it as a fixed landmark and the path comes out metres short). Judged against the
// previous scan only, so a static surface first seen is held back for one scan, not longer.
class ReturnPersistence {
 public:
  explicit ReturnPersistence(const ReturnPersistenceOptions& options = ReturnPersistenceOptions());

  // Records the returns of one scan (one frame for the whole run, in beam order, seen from
  // `origin`; call it for every scan), and says for each whether it persisted: the previous
  // scan saw a surface within `tolerance` of it. The first call lets every return through: with
  // no map yet there is nothing to protect, and a robot without odometry only moves once it has
  // a map.
  std::vector<bool> Observe(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin);
  // What Observe would say of `points`, without recording them (e.g. at a predicted pose,
  // before the scan is matched).
  std::vector<bool> Persisted(const std::vector<Eigen::Vector2d>& points) const;

 private:
  struct Segment {
    Eigen::Vector2d a, b;
  };
  double Distance(const Eigen::Vector2d& point) const;  // to the previous scan's surface
  void Add(const Eigen::Vector2d& a, const Eigen::Vector2d& b);
  static uint64_t Key(int64_t x, int64_t y);

  ReturnPersistenceOptions options_;
  bool first_call_ = true;
  std::vector<Segment> segments_;  // the previous scan's surface
  // (cell of max_join, segment) for every cell a segment passes, sorted: a cell's neighbours in
  // y are neighbours in this order, so a 3 x 3 block is three ranges (a hash map of buckets,
  // rebuilt for every scan, took 6 % of intel's run).
  std::vector<std::pair<uint64_t, uint32_t>> cells_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_RETURN_PERSISTENCE_H_
