#include "shared/io/map_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

class MapFileTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return dir_.path() + "/" + name; }
  void WriteText(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name)) << text;
  }
  const testing::ScopedTempDir dir_{"fleetmap-map-file"};
};

OccupancyGrid MakeRoomGrid() {
  OccupancyGridOptions options;
  options.resolution = 0.1;
  OccupancyGrid grid(options, Eigen::Vector2d(-1.0, 2.0), 30, 20);
  for (int x = 0; x < 30; ++x) {
    for (int y = 0; y < 20; ++y) {
      const bool wall = x == 0 || y == 0 || x == 29 || y == 19;
      if (x < 25) grid.SetLogOdds(CellIndex(x, y), wall ? 3.0f : -3.0f);
    }
  }
  return grid;
}

TEST_F(MapFileTest, PgmYamlRoundTripKeepsCellsAndGeometry) {
  const OccupancyGrid grid = MakeRoomGrid();
  std::string error;
  ASSERT_TRUE(WriteMap(Path("room"), grid, &error, /*crop=*/false)) << error;
  OccupancyGrid read;
  ASSERT_TRUE(ReadMap(Path("room.yaml"), &read, &error)) << error;
  EXPECT_DOUBLE_EQ(read.resolution(), 0.1);
  EXPECT_EQ(read.width(), grid.width());
  EXPECT_EQ(read.height(), grid.height());
  EXPECT_NEAR((read.origin() - grid.origin()).norm(), 0.0, 1e-6);
  for (int x = 0; x < 30; ++x) {
    for (int y = 0; y < 20; ++y) {
      const CellIndex c(x, y);
      EXPECT_EQ(read.IsKnown(c), grid.IsKnown(c)) << x << "," << y;
      if (grid.IsKnown(c)) {
        EXPECT_EQ(read.Probability(c) > 0.5f, grid.Probability(c) > 0.5f);
      }
    }
  }
}

TEST_F(MapFileTest, CropKeepsWorldCoordinates) {
  OccupancyGrid grid;
  grid.SetLogOdds(grid.CellAt({3.02, -4.02}), 3.0f);
  grid.SetLogOdds(grid.CellAt({5.02, -2.02}), -3.0f);
  std::string error;
  ASSERT_TRUE(WriteMap(Path("crop"), grid, &error)) << error;
  OccupancyGrid read;
  ASSERT_TRUE(ReadMap(Path("crop.yaml"), &read, &error)) << error;
  EXPECT_EQ(read.width(), 41);
  EXPECT_EQ(read.height(), 41);
  EXPECT_GT(read.Probability(read.CellAt({3.02, -4.02})), 0.6f);
  EXPECT_LT(read.Probability(read.CellAt({5.02, -2.02})), 0.4f);
  EXPECT_FALSE(read.IsKnown(read.CellAt({4.0, -3.0})));
}

TEST_F(MapFileTest, PngWriteAndReadBack) {
  const OccupancyGrid grid = MakeRoomGrid();
  std::string error;
  ASSERT_TRUE(WriteMapPng(Path("room.png"), grid, &error, false)) << error;
  GreyImage image;
  ASSERT_TRUE(ReadPng(Path("room.png"), &image, &error)) << error;
  EXPECT_EQ(image.width, 30);
  EXPECT_EQ(image.height, 20);
  EXPECT_EQ(image.pixels[0], 0);             // top-left corner is wall
  EXPECT_EQ(image.pixels[30 * 1 + 5], 254);   // row 1, column 5: interior
  EXPECT_EQ(image.pixels[30 * 5 + 27], 205);  // unknown strip on the right
  // A yaml pointing at a PNG image loads too.
  WriteText("png.yaml", "image: room.png\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  OccupancyGrid read;
  ASSERT_TRUE(ReadMap(Path("png.yaml"), &read, &error)) << error;
  EXPECT_EQ(read.width(), 30);
}

TEST_F(MapFileTest, BadFilesGiveErrors) {
  OccupancyGrid grid;
  std::string error;
  EXPECT_FALSE(ReadMap(Path("missing.yaml"), &grid, &error));
  EXPECT_NE(error.find("missing.yaml"), std::string::npos);

  WriteText("no_image.yaml", "resolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_FALSE(ReadMap(Path("no_image.yaml"), &grid, &error));
  EXPECT_NE(error.find("image"), std::string::npos);

  WriteText("bad_res.yaml", "image: x.pgm\nresolution: -1\norigin: [0, 0, 0]\n");
  EXPECT_FALSE(ReadMap(Path("bad_res.yaml"), &grid, &error));

  WriteText("bad_origin.yaml", "image: x.pgm\nresolution: 0.05\norigin: [0, 0]\n");
  EXPECT_FALSE(ReadMap(Path("bad_origin.yaml"), &grid, &error));

  WriteText("not_yaml.yaml", "image: [unterminated\n");
  EXPECT_FALSE(ReadMap(Path("not_yaml.yaml"), &grid, &error));

  WriteText("truncated.pgm", "P5\n10 10\n255\nabc");
  WriteText("trunc.yaml", "image: truncated.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_FALSE(ReadMap(Path("trunc.yaml"), &grid, &error));
  EXPECT_NE(error.find("truncated"), std::string::npos);

  WriteText("huge.pgm", "P5\n999999999 999999999\n255\n");
  GreyImage image;
  EXPECT_FALSE(ReadPgm(Path("huge.pgm"), &image, &error));
  EXPECT_FALSE(ReadPgm(Path("trunc.yaml"), &image, &error));

  WriteText("fake.png", "\x89PNG\r\n\x1a\n garbage garbage");
  EXPECT_FALSE(ReadPng(Path("fake.png"), &image, &error));
  EXPECT_FALSE(WritePng(Path("x.png"), 2, 2, 1, {1, 2, 3}, &error));
}

TEST_F(MapFileTest, AsciiPgmIsRead) {
  WriteText("ascii.pgm", "P2\n# comment\n3 2\n15\n0 15 7\n15 0 15\n");
  GreyImage image;
  std::string error;
  ASSERT_TRUE(ReadPgm(Path("ascii.pgm"), &image, &error)) << error;
  EXPECT_EQ(image.width, 3);
  EXPECT_EQ(image.pixels[1], 255);
  EXPECT_EQ(image.pixels[2], 119);
}

}  // namespace
}  // namespace fleetmap
