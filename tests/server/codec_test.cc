#include <gtest/gtest.h>

#include "shared/codec/grid_codec.h"
#include "shared/codec/zstd_codec.h"
#include "tests/server/server_test_util.h"

namespace fleetmap {
namespace {

TEST(ZstdCodecTest, RoundTripsAndChecksSize) {
  const std::string data(1000, 'x');
  const std::string compressed = ZstdCompress(data.data(), data.size());
  std::string out, error;
  ASSERT_TRUE(ZstdDecompress(compressed, data.size(), &out, &error)) << error;
  EXPECT_EQ(out, data);
  EXPECT_FALSE(ZstdDecompress(compressed, 999, &out, &error));
  EXPECT_FALSE(ZstdDecompress("not zstd at all", 10, &out, &error));
  EXPECT_FALSE(ZstdDecompress(compressed.substr(0, compressed.size() / 2), 1000, &out, &error));
}

TEST(GridCodecTest, RoundTripKeepsClassesAndGeometry) {
  OccupancyGrid grid = testing::MakeRoomGrid(20);
  const EncodedGrid encoded = EncodeGrid(grid);
  EXPECT_EQ(encoded.geometry.width, 20);
  OccupancyGrid decoded;
  GridDecodeError code;
  std::string error;
  ASSERT_TRUE(DecodeGrid(encoded, GridLimits(), OccupancyGridOptions(), &decoded, &code, &error));
  ASSERT_EQ(decoded.width(), 20);
  EXPECT_NEAR(decoded.LogOdds(CellIndex(3, 19)), 3.0f, 0.05f);
  EXPECT_NEAR(decoded.LogOdds(CellIndex(3, 3)), -2.0f, 0.05f);
}

TEST(GridCodecTest, RefusesCorruptAndAbsurdGrids) {
  EncodedGrid encoded = EncodeGrid(testing::MakeRoomGrid(20));
  QuantizedGrid out;
  GridDecodeError code;
  std::string error;
  EncodedGrid corrupt = encoded;
  corrupt.compressed[corrupt.compressed.size() / 2] ^= 0x5a;
  corrupt.compressed.resize(corrupt.compressed.size() - 3);
  EXPECT_FALSE(Decompress(corrupt, GridLimits(), &out, &code, &error));
  EXPECT_EQ(code, GridDecodeError::kInvalid);

  EncodedGrid huge = encoded;
  huge.geometry.width = 1 << 30;
  huge.geometry.height = 1 << 30;
  EXPECT_FALSE(Decompress(huge, GridLimits(), &out, &code, &error));
  EXPECT_EQ(code, GridDecodeError::kTooLarge);

  EncodedGrid liar = encoded;  // claims fewer cells than the frame holds
  liar.geometry.height = 10;
  EXPECT_FALSE(Decompress(liar, GridLimits(), &out, &code, &error));
  EXPECT_EQ(code, GridDecodeError::kInvalid);

  EncodedGrid bad_resolution = encoded;
  bad_resolution.geometry.resolution = -1.0;
  EXPECT_FALSE(Decompress(bad_resolution, GridLimits(), &out, &code, &error));
}

}  // namespace
}  // namespace fleetmap
