#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "robot_agent/sim/laser_model.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world_builder.h"
#include "robot_agent/sim/world_designs.h"
#include "robot_agent/sim/world_io.h"
#include "shared/io/map_file.h"
#include "tests/support/test_support.h"

namespace fleetmap::sim {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(WorldTest, LaserRangesInAKnownRoomMatchTheGeometry) {
  WorldBuilder builder("room", 0.05, Eigen::Vector2d(10.0, 6.0));
  builder.Carve({0.2, 0.2}, {9.8, 5.8});
  const World world = builder.Build();
  const testing::SegmentWorld truth =
      testing::BoxWorld(Eigen::Vector2d(0.2, 0.2), Eigen::Vector2d(9.8, 5.8));
  const Rigid2d robot(3.1, 2.3, 0.4);
  LaserOptions options;
  options.dropout_probability = 0.0;
  const LaserModel laser(options);
  const LaserScan expected = testing::SimulateScan(truth, robot);

  const LaserScan exact = laser.Scan(world, robot, {}, 0.0, nullptr);
  Rng rng(7);
  const LaserScan noisy = laser.Scan(world, robot, {}, 0.0, &rng);
  ASSERT_EQ(exact.size(), 181);
  int compared = 0;
  for (int i = 0; i < exact.size(); ++i) {
    if (!expected.IsReturn(i)) {
      EXPECT_FALSE(exact.IsReturn(i)) << "beam " << i;
      continue;
    }
    EXPECT_NEAR(exact.ranges[i], expected.ranges[i], 1e-4) << "beam " << i;
    EXPECT_NEAR(noisy.ranges[i], expected.ranges[i], 5 * options.range_noise) << "beam " << i;
    ++compared;
  }
  EXPECT_GT(compared, 150);
}

TEST(WorldTest, RectangleWallsMeasure21Point3By17MetresInTheWrittenMap) {
  const testing::ScopedTempDir temp("sim_rectangle");
  const std::string& dir = temp.path();
  std::string error;
  ASSERT_TRUE(SaveWorld(dir, MakeRectangleWorld(), &error)) << error;
  OccupancyGrid grid;
  ASSERT_TRUE(ReadMap(dir + "/rectangle.yaml", &grid, &error)) << error;
  Eigen::Vector2d min(1e9, 1e9), max(-1e9, -1e9);
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (grid.LogOdds(CellIndex(x, y)) <= 0.0f) continue;
      const Eigen::Vector2d center = grid.CellCenter(CellIndex(x, y));
      min = min.cwiseMin(center);
      max = max.cwiseMax(center);
    }
  }
  // Outer faces: cell centres +- half a cell.
  const Eigen::Vector2d size = max - min + Eigen::Vector2d::Constant(grid.resolution());
  EXPECT_NEAR(size.x(), 21.3, 1e-6);
  EXPECT_NEAR(size.y(), 17.0, 1e-6);
}

TEST(WorldTest, ShippedWorldFilesEqualTheGenerator) {
  const testing::ScopedTempDir temp("sim_worlds");
  const std::string& dir = temp.path();
  for (const std::string& name : DesignedWorldNames()) {
    World world;
    ASSERT_TRUE(MakeWorldByName(name, &world));
    std::string error;
    ASSERT_TRUE(SaveWorld(dir, world, &error)) << error;
    for (const std::string suffix : {".pgm", ".yaml", ".world.yaml"}) {
      EXPECT_EQ(ReadAll(dir + "/" + name + suffix), ReadAll(ShippedWorldsDir() + "/" + name + suffix))
          << name << suffix << " differs: run fleetmap-sim-worldgen";
    }
  }
}

TEST(WorldTest, LoadedWorldKeepsCellsAndMetadata) {
  World world;
  std::string error;
  ASSERT_TRUE(LoadWorld(ShippedWorldsDir() + "/department.world.yaml", &world, &error)) << error;
  const World designed = MakeDepartmentWorld();
  ASSERT_EQ(world.width(), designed.width());
  ASSERT_EQ(world.height(), designed.height());
  int differences = 0;
  for (int y = 0; y < world.height(); ++y) {
    for (int x = 0; x < world.width(); ++x) differences += world.State(x, y) != designed.State(x, y);
  }
  EXPECT_EQ(differences, 0);
  EXPECT_TRUE(world.FindPlace("Lab_1").has_value());
  EXPECT_TRUE(world.FindPlace("Lab_2").has_value());
  EXPECT_EQ(world.patches.size(), designed.patches.size());
}

}  // namespace
}  // namespace fleetmap::sim
