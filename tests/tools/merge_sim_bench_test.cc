// Runs fleetmap-merge-sim-bench (found under FLEETMAP_BINARY_DIR) as a process: the program
// docs/BENCHMARKS.md's merge figures come from, on the department with detections and with its
// twin diagnostic (--twins), and on a scenario file that does not exist.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using ::testing::HasSubstr;

// The bench: FLEETMAP_BINARY_DIR, or found from this test binary's own place in the build tree
// (<build>/tests/tools/merge_sim_bench_test) when the variable is not set.
std::string Bench() {
  const std::string relative = "/map_server/bench/fleetmap-merge-sim-bench";
  const std::string from_env = testing::BinaryDir() + relative;
  if (std::filesystem::exists(from_env)) return from_env;
  std::error_code code;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", code);
  if (code) return from_env;
  return self.parent_path().parent_path().parent_path().string() + relative;
}

int RunBench(const std::string& args, const std::string& dir, std::string* output) {
  const std::string log = dir + "/bench.log";
  const int status = std::system((Bench() + " " + args + " > " + log + " 2>&1").c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  *output = text.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
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
