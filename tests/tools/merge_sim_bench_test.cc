// Runs fleetmap-merge-sim-bench (found under FLEETMAP_BINARY_DIR) as a process: the program
// docs/BENCHMARKS.md's merge figures come from, on the department with detections and with its
// twin diagnostic (--twins), and on a scenario file that does not exist.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using ::testing::HasSubstr;

int RunBench(const std::string& args, const std::string& dir, std::string* output) {
  const int code =
      testing::RunProgram("map_server/bench/fleetmap-merge-sim-bench", args, dir + "/bench.log");
  *output = testing::ReadWholeFile(dir + "/bench.log");
  return code;
}

// With detections the department's two robots are merged; at their true anchors their maps
// still admit the half-turned twin (docs/BENCHMARKS.md, issue 8, session 46), which the
// detections, not the maps, rule out.
TEST(MergeSimBenchTest, MergesTheDepartmentAndFindsItsHalfTurnedTwin) {
  const testing::ScopedTempDir temp("merge-sim-bench");
  std::string output;
  ASSERT_EQ(RunBench("department_2robots --detections-only --seeds 1 --search-threads 1 --twins",
                     temp.path(), &output),
            0)
      << output;
  EXPECT_THAT(output, HasSubstr("merged pairs 1/1, false merges 0"));
  EXPECT_THAT(output,
              HasSubstr("pair twins (the maps' symmetries, at the true anchors): centroid"));
  EXPECT_THAT(output, HasSubstr("/ 180 deg off"));
  EXPECT_THAT(output, HasSubstr(": stands"));
}

TEST(MergeSimBenchTest, AScenarioFileThatIsNotThereIsAClearError) {
  const testing::ScopedTempDir temp("merge-sim-bench");
  std::string output;
  EXPECT_EQ(RunBench(temp.path() + "/missing.yaml --seeds 1", temp.path(), &output), 1) << output;
  EXPECT_THAT(output, HasSubstr("fleetmap-merge-sim-bench: "));
  EXPECT_THAT(output, HasSubstr("cannot open scenario file " + temp.path() + "/missing.yaml"));
}

}  // namespace
}  // namespace fleetmap
