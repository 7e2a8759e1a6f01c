#include "robot_agent/localization/mcl_localizer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/localization/localization_world.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::AsymmetricRoom;
using testing::IsNearPose;
using testing::MassNear;
using testing::Room;
using testing::SimulateScan;
using testing::SymmetricRoom;
using testing::SymmetricTwin;

MclLocalizerOptions SmallOptions(uint32_t seed) {
  MclLocalizerOptions options;
  options.mcl.kld.max_particles = 3000;
  options.mcl.kld.min_particles = 500;
  options.mcl.seed = seed;
  return options;
}

// Drives around a circle (0.08 m and 0.1 rad per 0.1 s), feeding odometry in a frame of its
// own (offset from the map by `odometry_in_map`) and then the scan at the same time, as the
// agent's pipeline does. Returns the true poses, one per scan.
std::vector<StampedPose> Drive(const Room& room, Rigid2d robot_in_map, int steps,
                               const Rigid2d& odometry_in_map, MclLocalizer* localizer,
                               double start_time = 0.0) {
  const Rigid2d step(0.08, 0.0, 0.1);
  std::vector<StampedPose> truth;
  std::string error;
  for (int i = 0; i < steps; ++i) {
    const double t = start_time + 0.1 * i;
    if (i > 0) robot_in_map = robot_in_map * step;
    EXPECT_TRUE(localizer->AddOdometry({t, odometry_in_map.inverse() * robot_in_map}, &error))
        << error;
    LaserScan scan = SimulateScan(room.walls, robot_in_map);
    scan.timestamp = t;
    EXPECT_TRUE(localizer->AddScan(scan, &error)) << error;
    truth.push_back({t, robot_in_map});
  }
  return truth;
}

TEST(MclLocalizerTest, AKnownStartIsTrackedInTheMapFrameWithOnePosePerScan) {
  const Room room = AsymmetricRoom();
  MclLocalizerOptions options = SmallOptions(3);
  const Rigid2d start(2.0, 2.2, 0.3);
  // Off by 0.2 m and 0.1 rad, within the stated uncertainty.
  options.initial_pose = Rigid2d(2.15, 2.05, 0.4);
  MclLocalizer localizer(room.grid, options);
  const std::vector<StampedPose> truth =
      Drive(room, start, 40, Rigid2d(-7.0, 3.0, 2.0), &localizer);
  ASSERT_EQ(localizer.trajectory().size(), truth.size());
  for (size_t i = 10; i < truth.size(); ++i) {
    EXPECT_DOUBLE_EQ(localizer.trajectory()[i].timestamp, truth[i].timestamp);
    EXPECT_THAT(localizer.trajectory()[i].pose, IsNearPose(truth[i].pose, 0.1, 0.05)) << i;
  }
  EXPECT_TRUE(localizer.estimate().converged);
  EXPECT_THAT(localizer.CurrentPose(), IsNearPose(truth.back().pose, 0.1, 0.05));
  // Localization builds no map and never revises a reported pose.
  EXPECT_TRUE(localizer.TakeSubmapUpdates().empty());
  EXPECT_EQ(localizer.trajectory_revision(), 0);
}

TEST(MclLocalizerTest, AUniformStartConvergesAndSaysWhen) {
  const Room room = AsymmetricRoom();
  MclLocalizer localizer(room.grid, SmallOptions(7));
  EXPECT_FALSE(localizer.estimate().converged);
  EXPECT_LT(localizer.time_to_converge(), 0.0);
  const std::vector<StampedPose> truth =
      Drive(room, Rigid2d(2.0, 2.2, 0.0), 60, Rigid2d(), &localizer, 100.0);
  EXPECT_TRUE(localizer.estimate().converged);
  EXPECT_THAT(localizer.CurrentPose(), IsNearPose(truth.back().pose, 0.15, 0.08));
  EXPECT_GE(localizer.time_to_converge(), 0.0);
  EXPECT_LE(localizer.time_to_converge(), 5.9);
  EXPECT_THAT(localizer.Statistics(), ::testing::HasSubstr("first converged after"));
}

// The same scan again from a robot standing still is not new evidence: after a global start the
// laser corrects only once the robot moves; from a known start, once a second.
TEST(MclLocalizerTest, AStandingRobotIsCorrectedOnlyOnceItMovesOrOnceASecondWhenTracking) {
  const Room room = AsymmetricRoom();
  const Rigid2d at(2.0, 2.2, 0.0);
  LaserScan scan = SimulateScan(room.walls, at);
  std::string error;
  MclLocalizerOptions known_start = SmallOptions(6);
  known_start.initial_pose = at;
  for (const bool global : {true, false}) {
    MclLocalizer localizer(room.grid, global ? SmallOptions(6) : known_start);
    for (int i = 0; i < 30; ++i) {  // 3 s at 10 Hz
      scan.timestamp = 0.1 * i;
      ASSERT_TRUE(localizer.AddOdometry({scan.timestamp, Rigid2d(5.0, 5.0, 1.0)}, &error));
      ASSERT_TRUE(localizer.AddScan(scan, &error));
    }
    EXPECT_THAT(localizer.Statistics(),
                ::testing::HasSubstr(global ? "30 scans (1 laser corrections)"
                                            : "30 scans (3 laser corrections)"));
  }
}

// Between corrections odometry carries the reported pose.
TEST(MclLocalizerTest, BetweenCorrectionsOdometryCarriesThePose) {
  const Room room = AsymmetricRoom();
  MclLocalizerOptions options = SmallOptions(8);
  options.initial_pose = Rigid2d(2.0, 2.2, 0.3);
  options.update_min_translation = 0.3;  // every fourth scan of 0.08 m
  options.update_min_rotation = 1.0;
  MclLocalizer localizer(room.grid, options);
  const std::vector<StampedPose> truth =
      Drive(room, *options.initial_pose, 40, Rigid2d(1.0, -2.0, 0.5), &localizer);
  EXPECT_THAT(localizer.Statistics(), ::testing::HasSubstr("40 scans (10 laser corrections)"));
  for (size_t i = 5; i < truth.size(); ++i) {
    EXPECT_THAT(localizer.trajectory()[i].pose, IsNearPose(truth[i].pose, 0.1, 0.05)) << i;
  }
}

TEST(MclLocalizerTest, RefusesInputOutOfOrderOrNotFiniteAndKeepsItsState) {
  const Room room = AsymmetricRoom();
  MclLocalizerOptions options = SmallOptions(5);
  options.initial_pose = Rigid2d(2.0, 2.2, 0.0);
  MclLocalizer localizer(room.grid, options);
  Drive(room, *options.initial_pose, 3, Rigid2d(), &localizer, 10.0);
  const Rigid2d before = localizer.CurrentPose();
  std::string error;
  LaserScan old_scan = SimulateScan(room.walls, *options.initial_pose);
  old_scan.timestamp = 10.1;
  EXPECT_FALSE(localizer.AddScan(old_scan, &error));
  EXPECT_THAT(error, ::testing::HasSubstr("older"));
  EXPECT_FALSE(localizer.AddOdometry({10.05, Rigid2d()}, &error));
  EXPECT_FALSE(localizer.AddOdometry({11.0, Rigid2d(NAN, 0.0, 0.0)}, &error));
  EXPECT_THAT(error, ::testing::HasSubstr("non-finite"));
  EXPECT_EQ(localizer.trajectory().size(), 3u);
  EXPECT_THAT(localizer.CurrentPose(), IsNearPose(before, 1e-12, 1e-12));
}

// A newer map version (the server's global map grows as robots map): the filter moves to it
// between scans and keeps tracking.
TEST(MclLocalizerTest, ANewerMapReplacesTheOldOneAndTrackingGoesOn) {
  const Room room = AsymmetricRoom();
  // The first version knows only the room's west half.
  OccupancyGrid west = room.grid;
  for (int y = 0; y < west.height(); ++y) {
    for (int x = 0; x < west.width(); ++x) {
      const CellIndex cell(x, y);
      if (west.CellCenter(cell).x() > 4.0) west.SetLogOdds(cell, 0.0f);
    }
  }
  MclLocalizerOptions options = SmallOptions(9);
  options.initial_pose = Rigid2d(2.0, 2.2, 0.0);
  MclLocalizer localizer(west, options);
  std::vector<StampedPose> truth = Drive(room, *options.initial_pose, 20, Rigid2d(), &localizer);
  const double west_area = localizer.filter().free_space().area();
  localizer.SetMap(room.grid);
  EXPECT_GT(localizer.filter().free_space().area(), 1.5 * west_area);
  EXPECT_EQ(localizer.trajectory().size(), 20u) << "the map changes, not the poses";
  const std::vector<StampedPose> more =
      Drive(room, truth.back().pose * Rigid2d(0.08, 0.0, 0.1), 40, Rigid2d(), &localizer, 2.0);
  ASSERT_EQ(localizer.trajectory().size(), 60u);
  for (size_t i = 0; i < more.size(); ++i) {
    EXPECT_THAT(localizer.trajectory()[20 + i].pose, IsNearPose(more[i].pose, 0.1, 0.05)) << i;
  }
}

// Without scan-to-map seeding, so that the belief is still split between the twins.
TEST(MclLocalizerTest, AnotherRobotsDensityPicksTheRightModeInASymmetricRoom) {
  const Room room = SymmetricRoom();
  MclLocalizerOptions options = SmallOptions(2);
  options.seeding.enabled = false;
  MclLocalizer localizer(room.grid, options);
  const std::vector<StampedPose> truth =
      Drive(room, Rigid2d(1.5, 0.8, 0.0), 20, Rigid2d(), &localizer);
  const Rigid2d& at = truth.back().pose;
  ASSERT_GT(MassNear(localizer.filter().particles(), SymmetricTwin(room, at)), 0.1);
  ASSERT_FALSE(localizer.estimate().converged);

  // What a focused observer would send: the robot's position within 5 cm, no heading.
  PoseDensity density;
  density.observer_id = "robot2";
  density.observed_id = "robot1";
  density.timestamp = truth.back().timestamp;
  PoseDensityKernel kernel;
  kernel.weight = 1.0;
  kernel.mean = at.translation();
  kernel.covariance = 0.05 * 0.05 * Eigen::Matrix2d::Identity();
  density.kernels.push_back(kernel);
  ASSERT_TRUE(localizer.ApplyDensity(density));
  EXPECT_GT(MassNear(localizer.filter().particles(), at), 0.8);
  EXPECT_THAT(localizer.CurrentPose(), IsNearPose(at, 0.15, 0.1));
  EXPECT_THAT(localizer.Statistics(),
              ::testing::HasSubstr("applied 1, refused 0, too soon 0, stale 0"));

  // The same robot again a moment later is mostly the same information: not applied.
  density.timestamp += 0.1;
  EXPECT_FALSE(localizer.ApplyDensity(density));
  // An empty density is refused and changes nothing.
  PoseDensity empty;
  empty.timestamp = truth.back().timestamp;
  EXPECT_FALSE(localizer.ApplyDensity(empty));
  // One from 5 s ago says where the robot was, not where it is.
  PoseDensity old = density;
  old.observer_id = "robot3";
  old.timestamp -= 5.0;
  EXPECT_FALSE(localizer.ApplyDensity(old));
  EXPECT_THAT(localizer.Statistics(),
              ::testing::HasSubstr("applied 1, refused 1, too soon 1, stale 1"));
}

// The search itself: a scan anywhere in the asymmetric room, at any heading, is found where it
// was taken; Seed moves the given share of the particles there.
TEST(ScanSeederTest, FindsAScanAnywhereInTheMapAndSeedsAShareOfTheParticles) {
  const Room room = AsymmetricRoom();
  const ScanSeeder seeder(room.grid, ScanSeedingOptions());
  for (const Rigid2d& at :
       {Rigid2d(2.0, 2.2, 0.3), Rigid2d(6.8, 1.0, -2.5), Rigid2d(4.5, 3.9, 3.0)}) {
    const std::optional<CorrelativeMatch> match =
        seeder.Search(ToPointsInRobotFrame(SimulateScan(room.walls, at)));
    ASSERT_TRUE(match.has_value());
    EXPECT_THAT(match->pose, IsNearPose(at, 0.15, 0.05));
  }
  std::vector<Particle> particles(1000, Particle{Rigid2d(0.5, 0.5, 0.0), 0.002});
  std::mt19937 rng(3);
  seeder.Seed(Rigid2d(4.0, 2.0, 1.0), &particles, rng);
  const double moved = MassNear(particles, Rigid2d(4.0, 2.0, 1.0), 0.5, 0.3);
  EXPECT_GT(moved, 0.15);  // 20 % drawn with replacement: about 18 % distinct
  EXPECT_LT(moved, 0.21);
}

// Scan-to-map seeding after a global start: in the asymmetric room the first search puts
// particles at the truth, and the filter is there from its first corrections.
TEST(MclLocalizerTest, ScanSeedingLocalizesAGlobalStartAtOnce) {
  const Room room = AsymmetricRoom();
  for (const bool seeding : {true, false}) {
    MclLocalizerOptions options = SmallOptions(1);  // seed 1 settles on the twin without seeding
    options.seeding.enabled = seeding;
    MclLocalizer localizer(room.grid, options);
    const std::vector<StampedPose> truth =
        Drive(room, Rigid2d(2.0, 2.2, 0.3), 30, Rigid2d(), &localizer);
    int near = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
      near +=
          (localizer.trajectory()[i].pose.translation() - truth[i].pose.translation()).norm() < 0.1;
    }
    if (seeding) {
      EXPECT_GE(near, 27) << localizer.Statistics();
      EXPECT_THAT(localizer.Statistics(), ::testing::HasSubstr("scan-to-map seeds"));
    } else {
      EXPECT_LT(near, 15) << "the case the seeding is for";
    }
  }
}

// In a symmetric room the search cannot tell the twins apart and seeds one of them: the filter
// converges there, right or wrong; another robot's detection (a position, no heading) still
// moves it to the truth, and the next scans find the heading there.
TEST(MclLocalizerTest, InASymmetricRoomASeededTwinStillYieldsToADetection) {
  const Room room = SymmetricRoom();
  // What a focused observer would send: the robot's position within 5 cm, no heading.
  auto detection_at = [](const StampedPose& pose) {
    PoseDensity density;
    density.observer_id = "robot2";
    density.observed_id = "robot1";
    density.timestamp = pose.timestamp;
    PoseDensityKernel kernel;
    kernel.weight = 1.0;
    kernel.mean = pose.pose.translation();
    kernel.covariance = 0.05 * 0.05 * Eigen::Matrix2d::Identity();
    density.kernels.push_back(kernel);
    return density;
  };
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    MclLocalizer localizer(room.grid, SmallOptions(seed));
    std::vector<StampedPose> truth = Drive(room, Rigid2d(1.5, 0.8, 0.0), 20, Rigid2d(), &localizer);
    // The first detection leaves the robot at the right place with every heading; the next,
    // 2.1 s later (past the DetectionGate), finds where it drove.
    for (int detection = 0; detection < 2; ++detection) {
      ASSERT_TRUE(localizer.ApplyDensity(detection_at(truth.back()))) << localizer.Statistics();
      EXPECT_LT((localizer.CurrentPose().translation() - truth.back().pose.translation()).norm(),
                0.15);
      truth = Drive(room, truth.back().pose * Rigid2d(0.08, 0.0, 0.1), 21, Rigid2d(), &localizer,
                    truth.back().timestamp + 0.1);
    }
    EXPECT_THAT(localizer.CurrentPose(), IsNearPose(truth.back().pose, 0.15, 0.1))
        << "seed " << seed;
  }
}

// Observer side: a focused robot says where the robot it sees is; a lost one keeps quiet.
TEST(MclLocalizerTest, OnlyAFocusedRobotSaysWhereTheRobotItSeesIs) {
  const Room room = AsymmetricRoom();
  MclLocalizerOptions options = SmallOptions(4);
  options.initial_pose = Rigid2d(2.0, 2.2, 0.0);
  MclLocalizer focused(room.grid, options);
  const std::vector<StampedPose> truth =
      Drive(room, *options.initial_pose, 10, Rigid2d(), &focused);
  ASSERT_TRUE(focused.estimate().converged);
  RobotDetection detection;
  detection.observer_id = "robot2";
  detection.observed_id = "robot1";
  detection.timestamp = truth.back().timestamp;
  detection.position_in_observer = Eigen::Vector2d(2.0, 0.5);
  detection.covariance = 0.02 * 0.02 * Eigen::Matrix2d::Identity();
  const std::optional<PoseDensity> density = focused.DensityOfSeenRobot(detection);
  ASSERT_TRUE(density.has_value());
  EXPECT_EQ(density->observed_id, "robot1");
  EXPECT_FALSE(density->has_heading);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const PoseDensityKernel& kernel : density->kernels) mean += kernel.weight * kernel.mean;
  EXPECT_LT((mean - truth.back().pose * detection.position_in_observer).norm(), 0.1);
  EXPECT_THAT(focused.Statistics(), ::testing::HasSubstr("densities of robots it saw: 1"));

  MclLocalizer lost(room.grid, SmallOptions(4));
  EXPECT_FALSE(lost.DensityOfSeenRobot(detection).has_value());
}

}  // namespace
}  // namespace fleetmap
