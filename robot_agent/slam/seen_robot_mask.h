#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SEEN_ROBOT_MASK_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SEEN_ROBOT_MASK_H_

#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"
#include "shared/core/robot_detection.h"

namespace fleetmap {

struct SeenRobotMaskOptions {
  // The seen robot's body plus the detector's and our own pose error (metres).
  double robot_radius = 0.35;
  // How fast a seen robot may have moved on since its detection (metres per second).
  double max_speed = 1.0;
  // Detections older than this are forgotten (seconds).
  double max_age = 1.0;
  // Bodies the laser alone found (AddLaserBodies) mask this long; a body the finder misses in
  // one scan (half hidden, too few returns) stays masked from the scans before.
  double max_laser_body_age = 0.3;
  // A scan can arrive before the odometry reading that covers its time (odometry and laser at
  // different rates: in the simulator two scans in three did, and went unmasked). Up to this
  // long (seconds) after the latest reading our pose is taken as that reading's, and the disks
  // grow by max_speed times the gap for our own motion since.
  double max_odometry_gap = 0.25;
  // A body the laser alone finds masks only once it has moved: found again within
  // body_track_window seconds more than min_body_motion (metres, in our odometry frame) from
  // where it was, and no farther than max_speed allows. Pillars, door-frame ends and other
  // round things stay put and stay in the map (masking them made the demo's map worse).
  bool laser_bodies_must_move = true;
  double min_body_motion = 0.03;
  double body_track_window = 0.5;
};

// Keeps the returns off other robots out of local SLAM: a robot seen by the camera (a detection:
// its centre in our robot frame at the scan time) is carried forward by our own odometry, and
// the returns of later scans inside the disk it may occupy are masked (LaserScan::kMasked:
// neither a hit nor free space). A robot driving ahead the same way only ever moves into space
// hidden behind itself, so local SLAM's seen-free test cannot tell it from a wall; mapped, it
// becomes a trail that drags the matches. Pure: no clocks, no I/O.
class SeenRobotMask {
 public:
  explicit SeenRobotMask(const SeenRobotMaskOptions& options = SeenRobotMaskOptions());

  // Our own odometry, in time order (older readings are dropped as the window moves on).
  void AddOdometry(double time, const Rigid2d& pose);
  // The latest detection of each seen robot is kept.
  void AddDetection(const RobotDetection& detection);
  // Round bodies the laser alone found in the scan at `time` (centres in our robot frame, e.g.
  // robots outside the camera's view); replaces none of the camera's detections. With
  // laser_bodies_must_move, only those that moved since they were last found mask; needs our
  // odometry at `time`.
  void AddLaserBodies(double time, const std::vector<Eigen::Vector2d>& centers_in_robot);
  // Masks the returns of `scan` (robot frame through scan->sensor_in_robot) inside a disk
  // around each robot detected within max_age before the scan (and each laser body within
  // max_laser_body_age); returns how many.
  int Apply(LaserScan* scan) const;
  bool empty() const { return seen_.empty() && laser_bodies_.empty(); }

 private:
  // Odometry at `time` (linear between readings; the latest reading up to max_odometry_gap
  // after it); nothing before the readings kept or farther after them.
  bool OdometryAt(double time, Rigid2d* pose) const;
  // Whether a body at `center` (odometry frame) at `time` moved since an earlier sighting.
  bool Moved(double time, const Eigen::Vector2d& center) const;

  SeenRobotMaskOptions options_;
  std::deque<std::pair<double, Rigid2d>> odometry_;
  std::map<std::string, RobotDetection> seen_;  // by observed robot
  // (time, centre in our robot frame), time order.
  std::deque<std::pair<double, Eigen::Vector2d>> laser_bodies_;
  // Every body the laser found within body_track_window: (time, centre in the odometry frame).
  std::deque<std::pair<double, Eigen::Vector2d>> body_sightings_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SEEN_ROBOT_MASK_H_
