#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "robot_agent/slam/particle_slam.h"
#include "tests/slam/particle_test_loop.h"
#include "tests/support/test_support.h"

// The particle backends' loop-closure layer (particle_loop_closure.h) inside ParticleSlam.
namespace fleetmap {
namespace {

using testing::EndError;
using testing::IsNearPose;
using testing::LoopPoses;
using testing::NoisyOdometry;
using testing::RunLoop;
using testing::SmallRbpf;

// The largest distance between a submap's anchor and the true position of its first scan.
double WorstAnchorError(const std::vector<Submap>& submaps, const std::vector<Rigid2d>& truth) {
  double worst = 0.0;
  for (const Submap& submap : submaps) {
    if (submap.scan_poses.empty()) continue;
    const double start = submap.scan_poses.front().timestamp;
    const size_t index = static_cast<size_t>(std::lround(start / 0.1));
    const Rigid2d expected = truth.front().inverse() * truth[index];
    worst = std::max(worst, (submap.submap_in_local.translation() - expected.translation()).norm());
  }
  return worst;
}

// Takes every pending submap update, `max_count` per call, into `latest` (as an uploader
// keeps them); counts finished submaps handed out again.
void TakeUpdates(LocalSlam* slam, size_t max_count, std::map<int64_t, Submap>* latest,
                 int* republished) {
  for (std::vector<Submap> batch = slam->TakeSubmapUpdates(max_count); !batch.empty();
       batch = slam->TakeSubmapUpdates(max_count)) {
    EXPECT_LE(batch.size(), max_count);
    for (Submap& submap : batch) {
      const auto before = latest->find(submap.submap_id);
      if (before != latest->end()) {
        EXPECT_GT(submap.revision, before->second.revision);
        if (before->second.finished) ++*republished;
      }
      (*latest)[submap.submap_id] = std::move(submap);
    }
  }
}

// Three odometry-driven particles with 7 m returns lose the loop: the filter ends 1.08 m off.
// The layer over its settled keyframes closes it, and the submaps come out at the corrected
// anchors, consistent with the corrected trajectory; submaps handed out before the graph moved
// them come again with a higher revision.
TEST(RbpfSlamTest, LoopClosureLayerClosesALoopTheFilterMisses) {
  const std::vector<Rigid2d> truth = LoopPoses();
  const std::vector<Rigid2d> odometry = NoisyOdometry(truth, 3);
  ParticleSlamOptions options = SmallRbpf(1, 2);
  options.filter.particles = 3;
  // Returns up to 7 m: at 10 m the filter sees the ring's start again and closes it by itself
  // (its per-scan tracker hardly drifts here); at 5-6 m the layer's node scans are too sparse to
  // close it. With seed 1 the filter alone ends 1.08 m off, the layer 0.11 m (session 13's
  // frontend: 0.76 / 0.06 m; with seeds 2-5 the filter ends within 0.09 m by itself).
  options.max_range = 7.0f;
  // Driven by odometry (GMapping's way): driven by the tracker's motion, the default, the filter
  // alone ends 0.02 m off this small ring, with nothing to close.
  options.scan_matched_motion = false;
  // The tracker's local map in 5 cm cells, as before session 31: in 2.5 cm cells (the default)
  // the tracker hardly drifts around this small ring, and the filter alone ends 0.07 m off.
  options.tracker.local_map.grid.resolution = 0.05;
  options.tracker.local_map.grid.observed_block = 1;
  options.loop_closure.enabled = false;
  ParticleSlam filter_only(options);
  RunLoop(&filter_only, truth, odometry);
  filter_only.Finish();
  options.loop_closure.enabled = true;
  ParticleSlam closed(options);
  std::map<int64_t, Submap> latest;  // as an uploader would keep them
  int republished = 0;
  auto take_updates = [&] {
    TakeUpdates(&closed, std::numeric_limits<size_t>::max(), &latest, &republished);
  };
  int scans = 0;
  RunLoop(&closed, truth, odometry, [&] {
    if (++scans % 20 == 0) take_updates();
  });
  closed.Finish();
  take_updates();

  const double filter_error = EndError(filter_only, truth);
  EXPECT_GT(filter_error, 0.4) << filter_only.Statistics();  // else the test means nothing
  EXPECT_LT(EndError(closed, truth), 0.15) << closed.Statistics();
  EXPECT_LT(EndError(closed, truth), filter_error / 3.0);

  const std::vector<Submap> filter_submaps = filter_only.TakeSubmapUpdates();
  std::vector<Submap> submaps;
  for (const auto& [id, submap] : latest) submaps.push_back(submap);
  ASSERT_GE(submaps.size(), 3u);
  EXPECT_GT(republished, 0);
  EXPECT_GT(WorstAnchorError(filter_submaps, truth), 0.3);
  // The layer's correction is spread along the ring, so the middle keeps part of the filter's
  // drift: worst anchor 0.37 m against the filter's 1.12 m (session 13's frontend: 0.197 against
  // 1.00 m, under a bound of 0.2 m that the frontend's thinning change crossed).
  EXPECT_LT(WorstAnchorError(submaps, truth), 0.5 * WorstAnchorError(filter_submaps, truth));
  for (const Submap& submap : submaps) {
    EXPECT_TRUE(submap.finished);
    ASSERT_FALSE(submap.scan_poses.empty());
    // The anchor sits at the group's first keyframe, and the scan poses are the trajectory's.
    const Eigen::Vector2d first_scan = submap.scan_poses.front().pose.translation();
    EXPECT_LT((submap.submap_in_local.translation() - first_scan).norm(), 0.05)
        << "submap " << submap.submap_id;
    double worst = 0.0;
    for (const StampedPose& scan : submap.scan_poses) {
      const size_t index = static_cast<size_t>(std::lround(scan.timestamp / 0.1));
      const Rigid2d error = closed.trajectory()[index].pose.inverse() * scan.pose;
      worst = std::max({worst, error.translation().norm(), std::abs(error.rotation())});
    }
    EXPECT_LT(worst, 1e-9) << "submap " << submap.submap_id;
  }
  EXPECT_TRUE(closed.TakeSubmapUpdates().empty());
}

// Submaps taken one at a time (as fleetmap-slam takes them, a few at a time, so that a graph
// that moves every submap never holds two copies of the map) end the same as taken all at once.
TEST(RbpfSlamTest, LoopClosureLayerHandsOutEveryMovedSubmapOneAtATime) {
  const std::vector<Rigid2d> truth = LoopPoses();
  const std::vector<Rigid2d> odometry = NoisyOdometry(truth, 3);
  ParticleSlamOptions options = SmallRbpf(1, 2);
  options.filter.particles = 3;
  options.loop_closure.enabled = true;
  auto run = [&](size_t max_count, int* republished) {
    ParticleSlam slam(options);
    std::map<int64_t, Submap> latest;
    auto take_updates = [&] { TakeUpdates(&slam, max_count, &latest, republished); };
    int scans = 0;
    RunLoop(&slam, truth, odometry, [&] {
      if (++scans % 20 == 0) take_updates();
    });
    slam.Finish();
    take_updates();
    return latest;
  };
  int all_republished = 0, one_republished = 0;
  const std::map<int64_t, Submap> all = run(std::numeric_limits<size_t>::max(), &all_republished);
  const std::map<int64_t, Submap> one = run(1, &one_republished);
  EXPECT_GT(one_republished, 0);
  ASSERT_EQ(one.size(), all.size());
  for (const auto& [id, submap] : all) {
    const Submap& other = one.at(id);
    EXPECT_TRUE(other.finished);
    EXPECT_THAT(other.submap_in_local, IsNearPose(submap.submap_in_local, 1e-12, 1e-12)) << id;
    ASSERT_EQ(other.scan_poses.size(), submap.scan_poses.size());
    for (size_t i = 0; i < submap.scan_poses.size(); ++i) {
      EXPECT_THAT(other.scan_poses[i].pose, IsNearPose(submap.scan_poses[i].pose, 1e-12, 1e-12));
    }
    EXPECT_EQ(other.grid.log_odds(), submap.grid.log_odds()) << "submap " << id;
  }
}

// Without loop closures the layer must hand back the filter's own final trajectory, although
// the filter moved keyframes after they settled (settling at 2 keyframes old forces that): the
// graph is rebuilt from the final history.
TEST(RbpfSlamTest, LoopClosureLayerWithoutLoopsEndsWithTheFiltersTrajectory) {
  const std::vector<Rigid2d> truth = LoopPoses();
  const std::vector<Rigid2d> odometry = NoisyOdometry(truth, 5);
  ParticleSlamOptions options = SmallRbpf(1, 2);
  options.loop_closure.enabled = false;
  ParticleSlam filter_only(options);
  RunLoop(&filter_only, truth, odometry);
  filter_only.Finish();
  options.loop_closure.enabled = true;
  options.loop_closure.settle_keyframes = 2;
  options.loop_closure.graph.enabled = false;  // nodes, but no searches
  ParticleSlam layered(options);
  RunLoop(&layered, truth, odometry);
  layered.Finish();

  EXPECT_NE(layered.Statistics().find("graph rebuilt"), std::string::npos) << layered.Statistics();
  ASSERT_EQ(layered.trajectory().size(), filter_only.trajectory().size());
  for (size_t i = 0; i < layered.trajectory().size(); ++i) {
    const Rigid2d expected = filter_only.trajectory()[i].pose;
    ASSERT_THAT(layered.trajectory()[i].pose, IsNearPose(expected, 1e-6, 1e-6)) << "scan " << i;
  }
}

}  // namespace
}  // namespace fleetmap
