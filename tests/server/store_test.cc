#include <gtest/gtest.h>
#include <sqlite3.h>

#include <functional>
#include <optional>

#include "map_server/store/memory_map_store.h"
#include "map_server/store/sqlite_map_store.h"
#include "map_server/store/sqlite_schema.h"
#include "tests/server/server_test_util.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

Submap MakeSubmap(const std::string& robot, int64_t id, int64_t revision) {
  Submap submap;
  submap.robot_id = robot;
  submap.submap_id = id;
  submap.revision = revision;
  submap.submap_in_local = Rigid2d(1.0, 2.0, 0.5);
  submap.scan_poses = {StampedPose{3.0, Rigid2d(1.0, 2.0, 0.5)}};
  submap.grid = testing::MakeRoomGrid(10);
  return submap;
}

class StoreTest : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    if (!GetParam()) {
      store_ = std::make_unique<MemoryMapStore>(RetentionOptions{2});
      return;
    }
    dir_.emplace("store_test");
    SqliteMapStoreOptions options;
    options.path = dir_->path() + "/map.db";
    options.retention.keep_version_grids = 2;
    std::string error;
    store_ = SqliteMapStore::Open(options, &error);
    ASSERT_TRUE(store_) << error;
  }
  void Register(const std::string& id) {
    bool existed;
    std::string error;
    RobotRecord robot;
    robot.robot_id = id;
    ASSERT_TRUE(store_->PutRobot(robot, &existed, &error)) << error;
  }

  std::optional<testing::ScopedTempDir> dir_;  // Sqlite only; outlives store_
  std::unique_ptr<MapStore> store_;
};

TEST_P(StoreTest, SubmapsAreIdempotentAndOrdered) {
  int64_t seq = 0;
  std::string error;
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 0, 0), 1.0, &seq, &error), PutOutcome::kUnknownRobot);
  Register("r1");
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 0, 0), 1.0, &seq, &error), PutOutcome::kInserted);
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 0, 0), 1.0, &seq, &error), PutOutcome::kDuplicate);
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 0, 2), 1.0, &seq, &error), PutOutcome::kInserted);
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 0, 1), 1.0, &seq, &error), PutOutcome::kOutOfOrder);
  // A retry of an old revision that was stored is still a duplicate, not an error.
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 0, 0), 1.0, &seq, &error), PutOutcome::kDuplicate);
  EXPECT_EQ(store_->PutSubmap(MakeSubmap("r1", 1, 0), 1.0, &seq, &error), PutOutcome::kInserted);
  EXPECT_EQ(store_->CountSubmapRevisions("r1"), 3);
  EXPECT_EQ(store_->CountSubmapIds("r1"), 2);
  EXPECT_EQ(store_->MaxSubmapSeq(), seq);
  const auto latest = store_->LatestSubmaps("");
  ASSERT_EQ(latest.size(), 2u);
  EXPECT_EQ(latest[0].submap.revision, 2);
  const auto loaded = store_->GetSubmap(SubmapKey{"r1", 0, 2});
  ASSERT_TRUE(loaded);
  EXPECT_THAT(loaded->submap.submap_in_local, testing::IsNearPose(Rigid2d(1, 2, 0.5), 1e-9, 1e-9));
  EXPECT_EQ(loaded->submap.grid.width(), 10);
  EXPECT_NEAR(loaded->submap.grid.LogOdds(CellIndex(2, 9)), 3.0f, 0.05f);
}

TEST_P(StoreTest, TrajectoriesAndDetections) {
  std::string error;
  Register("r1");
  TrajectoryRecord t{"r1", 1, 0.0, {StampedPose{1.0, Rigid2d(1, 0, 0)}}};
  EXPECT_EQ(store_->PutTrajectory(t, &error), PutOutcome::kInserted);
  EXPECT_EQ(store_->PutTrajectory(t, &error), PutOutcome::kDuplicate);
  t.revision = 0;
  EXPECT_EQ(store_->PutTrajectory(t, &error), PutOutcome::kOutOfOrder);
  ASSERT_TRUE(store_->LatestTrajectory("r1"));
  EXPECT_EQ(store_->LatestTrajectory("r1")->revision, 1);

  DetectionRecord d;
  d.detection_id = 7;
  d.detection.observer_id = "r1";
  d.detection.observed_id = "not-yet-registered";
  d.detection.relative_heading = 0.25;
  int64_t seq = 0;
  EXPECT_EQ(store_->PutDetection(d, &seq, &error), PutOutcome::kInserted);
  EXPECT_EQ(store_->PutDetection(d, &seq, &error), PutOutcome::kDuplicate);
  const auto all = store_->DetectionsAfter(0);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].detection.observed_id, "not-yet-registered");
  EXPECT_DOUBLE_EQ(*all[0].detection.relative_heading, 0.25);
}

TEST_P(StoreTest, VersionsKeepProvenanceAndRetention) {
  std::string error;
  QuantizedGrid grid;
  grid.geometry.width = 2;
  grid.geometry.height = 1;
  grid.cells = {5, -5};
  for (int i = 1; i <= 3; ++i) {
    VersionRecord v;
    v.created_unix_time = 100.0 * i;
    v.trigger = "submaps";
    v.trigger_robot_ids = {"r1"};
    v.new_submaps = {SubmapKey{"r1", i, 0}};
    v.quality["robots_placed"] = 1;
    v.placements = {
        RobotPlacementRecord{"r1", true, Rigid2d(1, 2, 0), std::nullopt, "registration", ""}};
    if (i == 2) v.placements[0].start_in_global = Rigid2d(0.5, 2, 0.1);
    EXPECT_EQ(store_->PutVersion(v, Compress(grid), &error), i) << error;
  }
  EXPECT_EQ(store_->LatestVersion()->version, 3);
  EXPECT_EQ(store_->VersionAtTime(250.0)->version, 2);
  EXPECT_FALSE(store_->VersionAtTime(50.0));
  const auto v2 = store_->GetVersion(2);
  ASSERT_TRUE(v2);
  ASSERT_EQ(v2->new_submaps.size(), 1u);
  EXPECT_EQ(v2->new_submaps[0].submap_id, 2);
  EXPECT_EQ(v2->placements.at(0).source, "registration");
  ASSERT_TRUE(v2->placements.at(0).start_in_global);
  EXPECT_THAT(*v2->placements.at(0).start_in_global,
              testing::IsNearPose(Rigid2d(0.5, 2, 0.1), 1e-12, 1e-12));
  EXPECT_FALSE(store_->GetVersion(3)->placements.at(0).start_in_global);
  EXPECT_DOUBLE_EQ(v2->quality.at("robots_placed"), 1.0);
  // keep_version_grids = 2: version 1 keeps its metadata but not its grid.
  EXPECT_FALSE(store_->GetVersionGrid(1));
  EXPECT_FALSE(store_->GetVersion(1)->grid_available);
  ASSERT_TRUE(store_->GetVersionGrid(3));
  EXPECT_EQ(store_->ListVersions(10, 0).size(), 3u);
  EXPECT_EQ(store_->ListVersions(10, 3).front().version, 2);
}

INSTANTIATE_TEST_SUITE_P(MemoryAndSqlite, StoreTest, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Sqlite" : "Memory"; });

TEST(SqliteStoreTest, RefusesDatabaseFromNewerSchema) {
  const testing::ScopedTempDir temp("store_schema");
  const std::string& dir = temp.path();
  SqliteMapStoreOptions options;
  options.path = dir + "/map.db";
  std::string error;
  ASSERT_TRUE(SqliteMapStore::Open(options, &error)) << error;
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(options.path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE schema_version SET version = 99", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  EXPECT_FALSE(SqliteMapStore::Open(options, &error));
  EXPECT_NE(error.find("newer"), std::string::npos) << error;
}

// A database written before schema version 2 (no start_in_global column) opens, migrates, and
// keeps its versions; their placements then have no start.
TEST(SqliteStoreTest, MigratesVersionOneAlignments) {
  const testing::ScopedTempDir temp("store_migrate");
  SqliteMapStoreOptions options;
  options.path = temp.path() + "/map.db";
  std::string error;
  VersionRecord v;
  v.created_unix_time = 100.0;
  v.trigger = "submaps";
  v.placements = {
      RobotPlacementRecord{"r1", true, Rigid2d(1, 2, 0.3), Rigid2d(1, 2.5, 0.2), "reference", ""}};
  QuantizedGrid grid;
  grid.geometry.width = 2;
  grid.geometry.height = 1;
  grid.cells = {5, -5};
  {
    auto store = SqliteMapStore::Open(options, &error);
    ASSERT_TRUE(store) << error;
    ASSERT_EQ(store->PutVersion(v, Compress(grid), &error), 1) << error;
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(options.path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(db,
                   "ALTER TABLE alignments DROP COLUMN start_x; ALTER TABLE alignments DROP COLUMN "
                   "start_y; ALTER TABLE alignments DROP COLUMN start_theta; ALTER TABLE robots "
                   "DROP COLUMN localization_only; UPDATE schema_version SET version = 1",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  sqlite3_close(db);
  auto store = SqliteMapStore::Open(options, &error);
  ASSERT_TRUE(store) << error;
  const auto old = store->GetVersion(1);
  ASSERT_TRUE(old);
  ASSERT_EQ(old->placements.size(), 1u);
  EXPECT_THAT(old->placements[0].local_in_global,
              testing::IsNearPose(Rigid2d(1, 2, 0.3), 1e-12, 1e-12));
  EXPECT_FALSE(old->placements[0].start_in_global);
  ASSERT_EQ(store->PutVersion(v, Compress(grid), &error), 2) << error;
  ASSERT_TRUE(store->GetVersion(2)->placements.at(0).start_in_global);
  EXPECT_THAT(*store->GetVersion(2)->placements.at(0).start_in_global,
              testing::IsNearPose(Rigid2d(1, 2.5, 0.2), 1e-12, 1e-12));
}

// A database written before schema version 3 (no localization_only column) opens and its robots
// read as mapping robots; the flag then round-trips.
TEST(SqliteStoreTest, MigratesVersionTwoRobotsAndKeepsLocalizationOnly) {
  const testing::ScopedTempDir temp("store_migrate_robots");
  SqliteMapStoreOptions options;
  options.path = temp.path() + "/map.db";
  std::string error;
  bool existed = false;
  {
    auto store = SqliteMapStore::Open(options, &error);
    ASSERT_TRUE(store) << error;
    RobotRecord robot;
    robot.robot_id = "mapper";
    ASSERT_TRUE(store->PutRobot(robot, &existed, &error)) << error;
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(options.path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "ALTER TABLE robots DROP COLUMN localization_only; UPDATE schema_version "
                         "SET version = 2",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  auto store = SqliteMapStore::Open(options, &error);
  ASSERT_TRUE(store) << error;
  ASSERT_TRUE(store->GetRobot("mapper"));
  EXPECT_FALSE(store->GetRobot("mapper")->localization_only);
  RobotRecord localizer;
  localizer.robot_id = "localizer";
  localizer.localization_only = true;
  ASSERT_TRUE(store->PutRobot(localizer, &existed, &error)) << error;
  store.reset();
  store = SqliteMapStore::Open(options, &error);
  ASSERT_TRUE(store) << error;
  EXPECT_TRUE(store->GetRobot("localizer")->localization_only);
  EXPECT_FALSE(store->GetRobot("mapper")->localization_only);
}

TEST(SqliteStoreTest, DataSurvivesReopen) {
  const testing::ScopedTempDir temp("store_reopen");
  const std::string& dir = temp.path();
  SqliteMapStoreOptions options;
  options.path = dir + "/map.db";
  std::string error;
  {
    auto store = SqliteMapStore::Open(options, &error);
    ASSERT_TRUE(store) << error;
    bool existed;
    RobotRecord robot;
    robot.robot_id = "r1";
    robot.local_in_global = Rigid2d(1, 2, 3);
    ASSERT_TRUE(store->PutRobot(robot, &existed, &error));
    int64_t seq;
    ASSERT_EQ(store->PutSubmap(MakeSubmap("r1", 0, 0), 1.0, &seq, &error), PutOutcome::kInserted);
  }
  auto store = SqliteMapStore::Open(options, &error);
  ASSERT_TRUE(store) << error;
  ASSERT_TRUE(store->GetRobot("r1"));
  EXPECT_THAT(*store->GetRobot("r1")->local_in_global,
              testing::IsNearPose(Rigid2d(1, 2, 3), 1e-9, 1e-9));
  EXPECT_EQ(store->CountSubmapRevisions("r1"), 1);
}

}  // namespace
}  // namespace fleetmap
