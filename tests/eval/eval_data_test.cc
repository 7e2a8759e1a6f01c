// The relations metric on the raw odometry of the public benchmark logs (skipped when absent).

#include <gtest/gtest.h>

#include "shared/eval/relations_file.h"
#include "shared/eval/relations_metric.h"
#include "shared/io/carmen_trajectory.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

RelationsResult EvaluateRawOdometry(const std::string& log, const std::string& relations_path) {
  Trajectory trajectory;
  std::string error;
  EXPECT_TRUE(ReadOdometryTrajectory(log, CarmenReaderOptions(), &trajectory, &error)) << error;
  std::vector<Relation> relations;
  EXPECT_TRUE(ReadRelations(relations_path, &relations, &error)) << error;
  return EvaluateRelations(trajectory, relations);
}

TEST(EvalDataTest, IntelRawOdometryUsesAll2984Relations) {
  FLEETMAP_REQUIRE_DATA(log, "intel-lab/intel.clf.bz2");
  FLEETMAP_REQUIRE_DATA(relations, "intel-lab/intel.relations");
  const RelationsResult result = EvaluateRawOdometry(log, relations);
  EXPECT_EQ(result.used, 2984);
  EXPECT_EQ(result.skipped, 0);
  // Raw odometry: small for short relations, tens of metres for long loops (SOURCES.md).
  EXPECT_GT(result.translation.mean, 0.05);
  EXPECT_GT(result.translation.max, 10.0);
}

TEST(EvalDataTest, AcesRawOdometryUsesAll1279Relations) {
  FLEETMAP_REQUIRE_DATA(log, "aces/aces.clf.bz2");
  FLEETMAP_REQUIRE_DATA(relations, "aces/aces.relations");
  const RelationsResult result = EvaluateRawOdometry(log, relations);
  EXPECT_EQ(result.used, 1279);
  EXPECT_EQ(result.skipped, 0);
  EXPECT_GT(result.translation.max, 5.0);
}

}  // namespace
}  // namespace fleetmap
