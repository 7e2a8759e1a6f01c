#include "robot_agent/slam/loop_closure.h"

#include <limits>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "robot_agent/slam/scan_matching_slam.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

constexpr double kDegree = M_PI / 180.0;

// A 20 m x 15 m corridor ring, 2 m wide, with boxes of different sizes at irregular places, so
// that every stretch looks different (no period a match could slip by).
testing::SegmentWorld IrregularRing() {
  testing::SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(-10.0, -7.5), Eigen::Vector2d(10.0, 7.5));
  testing::AddBox(Eigen::Vector2d(-8.0, -5.5), Eigen::Vector2d(8.0, 5.5), &world);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> gap(1.2, 3.0), size(0.2, 0.6);
  for (double x = -8.0; x < 7.5; x += gap(rng)) {
    testing::AddBox(Eigen::Vector2d(x, -7.5), Eigen::Vector2d(x + size(rng), -7.5 + size(rng)), &world);
    const double x2 = x + 0.5 * gap(rng);
    testing::AddBox(Eigen::Vector2d(x2, 7.5 - size(rng)), Eigen::Vector2d(x2 + size(rng), 7.5), &world);
  }
  for (double y = -5.0; y < 4.5; y += gap(rng)) {
    testing::AddBox(Eigen::Vector2d(-10.0, y), Eigen::Vector2d(-10.0 + size(rng), y + size(rng)), &world);
    const double y2 = y + 0.5 * gap(rng);
    testing::AddBox(Eigen::Vector2d(10.0 - size(rng), y2), Eigen::Vector2d(10.0, y2 + size(rng)), &world);
  }
  return world;
}

// Poses along the ring's centre line (0.2 m steps, turning on the spot at corners) for `laps`.
std::vector<Rigid2d> RingPoses(double laps) {
  const std::vector<Eigen::Vector2d> corners = {{-9.0, -6.5}, {9.0, -6.5}, {9.0, 6.5}, {-9.0, 6.5}};
  std::vector<Rigid2d> poses;
  double heading = 0.0;
  const int legs = static_cast<int>(4 * laps);
  for (int leg = 0; leg < legs; ++leg) {
    const Eigen::Vector2d a = corners[static_cast<size_t>(leg % 4)], b = corners[static_cast<size_t>((leg + 1) % 4)];
    const int steps = static_cast<int>((b - a).norm() / 0.2);
    for (int i = 0; i < steps; ++i) poses.emplace_back(a + (b - a) * (static_cast<double>(i) / steps), heading);
    for (int i = 1; i <= 6; ++i) poses.emplace_back(b, heading + i * 15.0 * kDegree);
    heading += M_PI / 2;
  }
  return poses;
}

std::vector<Eigen::Vector2f> PointsAt(const testing::SegmentWorld& world, const Rigid2d& pose) {
  return ToPointsInRobotFrame(testing::SimulateScan(world, pose, 181, static_cast<float>(-M_PI / 2),
                                                    static_cast<float>(M_PI / 180), 10.0f));
}

// What a drifting local frontend reports along `truth`: 2 % too long and 0.1 degree per metre
// to the left.
std::vector<Rigid2d> DriftingFrontend(const std::vector<Rigid2d>& truth) {
  std::vector<Rigid2d> local = {truth.front()};
  for (size_t i = 1; i < truth.size(); ++i) {
    const Rigid2d step = truth[i - 1].inverse() * truth[i];
    const double d = step.translation().norm();
    local.push_back(local.back() * Rigid2d(1.02 * step.translation(), step.rotation() + 0.1 * kDegree * d));
  }
  return local;
}

TEST(LoopClosureTest, RemovesDriftOnASyntheticLoop) {
  const testing::SegmentWorld world = IrregularRing();
  const std::vector<Rigid2d> truth = RingPoses(1.5);
  const std::vector<Rigid2d> local = DriftingFrontend(truth);
  LoopClosure loop_closure;
  int64_t submap_id = -1;
  Rigid2d submap_in_local;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i % 40 == 0) {  // a new submap every 40 nodes, anchored like SubmapBuilder does
      ++submap_id;
      submap_in_local = Rigid2d(local[i].translation(), 0.0);
    }
    loop_closure.AddNode(static_cast<double>(i), PointsAt(world, truth[i]), local[i], submap_id, submap_in_local);
  }
  loop_closure.Finish();
  EXPECT_GT(loop_closure.loop_constraints(), 0);
  EXPECT_GT(loop_closure.optimizations(), 0);

  // What loop closure fixes: where the second lap passes the first one, both must agree (the
  // relations metric's view). Absolute poses keep a share of the scale drift, spread over the lap.
  const size_t lap = RingPoses(1.0).size();
  double worst_drift = 0.0, worst_corrected = 0.0, worst_rotation = 0.0;
  for (size_t i = 0; i + lap < truth.size(); ++i) {
    const size_t j = i + lap;
    const Rigid2d expected = truth[i].inverse() * truth[j];
    const Rigid2d drifted = local[i].inverse() * local[j];
    const Rigid2d corrected = (loop_closure.CorrectionAt(static_cast<double>(i)) * local[i]).inverse() *
                              (loop_closure.CorrectionAt(static_cast<double>(j)) * local[j]);
    worst_drift = std::max(worst_drift, (drifted.translation() - expected.translation()).norm());
    worst_corrected = std::max(worst_corrected, (corrected.translation() - expected.translation()).norm());
    worst_rotation = std::max(worst_rotation, std::abs(NormalizeAngle(corrected.rotation() - expected.rotation())));
  }
  EXPECT_GT(worst_drift, 1.0);  // the test means something only if the frontend drifts
  EXPECT_LT(worst_corrected, 0.05) << "uncorrected: " << worst_drift;
  EXPECT_LT(worst_rotation, 1.0 * kDegree);
  // Interpolated corrections between nodes stay between their neighbours'.
  EXPECT_TRUE(loop_closure.CorrectionAt(10.5).IsFinite());
}

// Only a few finished submaps keep their search targets in memory; the others are rebuilt from
// their scans when a search comes back to them, and must find exactly what the kept ones find.
TEST(LoopClosureTest, RebuildsDroppedTargetsExactly) {
  const testing::SegmentWorld world = IrregularRing();
  const std::vector<Rigid2d> truth = RingPoses(1.5);
  const std::vector<Rigid2d> local = DriftingFrontend(truth);
  auto run = [&](int max_cached_targets) {
    LoopClosureOptions options;
    options.max_cached_targets = max_cached_targets;
    auto loop_closure = std::make_unique<LoopClosure>(options);
    int64_t submap_id = -1;
    Rigid2d submap_in_local;
    int most_cached = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
      if (i % 40 == 0) {
        ++submap_id;
        submap_in_local = Rigid2d(local[i].translation(), 0.0);
      }
      loop_closure->AddNode(static_cast<double>(i), PointsAt(world, truth[i]), local[i], submap_id, submap_in_local);
      most_cached = std::max(most_cached, loop_closure->cached_targets());
    }
    loop_closure->Finish();
    return std::make_pair(std::move(loop_closure), most_cached);
  };
  const auto [all, all_cached] = run(0);
  const auto [one, one_cached] = run(1);
  EXPECT_GT(all_cached, 5);
  EXPECT_EQ(all->target_rebuilds(), 0);
  EXPECT_EQ(one_cached, 1);
  EXPECT_GT(one->target_rebuilds(), 0);
  ASSERT_GT(all->loop_constraints(), 0);
  EXPECT_EQ(one->loop_constraints(), all->loop_constraints());
  EXPECT_EQ(one->searches(), all->searches());
  for (size_t i = 0; i < truth.size(); ++i) {
    const double t = static_cast<double>(i);
    EXPECT_THAT(one->CorrectionAt(t), testing::IsNearPose(all->CorrectionAt(t), 1e-12, 1e-12)) << "node " << i;
  }
}

// Runs the irregular ring through the scan-matching backend, taking submap updates every 20
// scans `max_count` at a time until none are left, and checks what a keeper of the latest
// submaps ends with.
void ExpectRevisionsFollowTheGraph(size_t max_count) {
  const testing::SegmentWorld world = IrregularRing();
  const std::vector<Rigid2d> truth = RingPoses(1.25);
  ScanMatchingSlamOptions options;
  options.submaps.max_scans = 40;
  ScanMatchingSlam slam(options);
  std::string error;
  std::map<int64_t, Submap> latest;
  int republished = 0;
  int64_t seen_revision = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double t = 0.2 * static_cast<double>(i);
    ASSERT_TRUE(slam.AddOdometry({t, truth[i]}, &error)) << error;
    LaserScan scan = testing::SimulateScan(world, truth[i], 181, static_cast<float>(-M_PI / 2),
                                           static_cast<float>(M_PI / 180), 10.0f);
    scan.timestamp = t;
    ASSERT_TRUE(slam.AddScan(scan, &error)) << error;
    if (i % 20 == 0 || i + 1 == truth.size()) {
      if (i + 1 == truth.size()) slam.Finish();
      for (std::vector<Submap> batch = slam.TakeSubmapUpdates(max_count); !batch.empty();
           batch = slam.TakeSubmapUpdates(max_count)) {
        EXPECT_LE(batch.size(), max_count);
        for (Submap& submap : batch) {
          auto found = latest.find(submap.submap_id);
          if (found != latest.end() && found->second.finished) {
            ++republished;
            EXPECT_GT(submap.revision, found->second.revision);
          }
          latest[submap.submap_id] = std::move(submap);
        }
      }
      EXPECT_GE(slam.trajectory_revision(), seen_revision);
      seen_revision = slam.trajectory_revision();
    }
  }
  EXPECT_GT(slam.trajectory_revision(), 0);
  EXPECT_GT(republished, 0);
  // Every scan pose in the latest submaps agrees with the (corrected) trajectory.
  std::map<double, Rigid2d> by_time;
  for (const StampedPose& pose : slam.trajectory()) by_time[pose.timestamp] = pose.pose;
  for (const auto& [id, submap] : latest) {
    for (const StampedPose& pose : submap.scan_poses) {
      EXPECT_THAT(pose.pose, testing::IsNearPose(by_time.at(pose.timestamp), 1e-6, 1e-6)) << "submap " << id;
    }
  }
  const Rigid2d end = truth.front().inverse() * truth.back();
  EXPECT_THAT(slam.CurrentPose(), testing::IsNearPose(end, 0.1, 1.0 * kDegree));
}

TEST(LoopClosureTest, PublishesRevisionsWhenTheGraphMovesPoses) {
  ExpectRevisionsFollowTheGraph(std::numeric_limits<size_t>::max());
}

// One submap per call: the ones the graph moved that did not fit come with the next calls.
TEST(LoopClosureTest, PublishesEveryRevisionOneSubmapAtATime) { ExpectRevisionsFollowTheGraph(1); }

}  // namespace
}  // namespace fleetmap
