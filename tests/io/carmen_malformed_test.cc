// Malformed CARMEN input must give "file:line: message" errors (or be counted and skipped),
// never a crash or an out-of-bounds read.

#include <bzlib.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "shared/io/carmen_reader.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

const char kGoodFlaser[] = "FLASER 3 1 2 3 0 0 0 0 0 0 10.0 host 0\n";
const char kGoodOdom[] = "ODOM 0 0 0 0 0 0 11.0 host 0\n";

struct BadLine {
  const char* name;
  std::string line;
  const char* expected_fragment;  // must appear in the error message
};

std::vector<BadLine> BadLines() {
  return {
      {"truncated_flaser", "FLASER 3 1 2 3 0 0 0 0 0\n", "FLASER"},
      {"only_type", "FLASER\n", "FLASER"},
      {"too_few_ranges", "FLASER 180 1 2 3 0 0 0 0 0 0 10.0 host 0\n", "expected 180 ranges"},
      {"too_many_ranges", "FLASER 2 1 2 3 0 0 0 0 0 0 10.0 host 0\n", "expected 2 ranges"},
      {"non_numeric_range", "FLASER 3 1 x 3 0 0 0 0 0 0 10.0 host 0\n", "range 1 'x'"},
      {"non_numeric_count", "FLASER three 1 2 3 0 0 0 0 0 0 10.0 host 0\n", "beam count"},
      {"negative_count", "FLASER -3 1 2 3 0 0 0 0 0 0 10.0 host 0\n", "beam count"},
      {"huge_count", "FLASER 999999999999 1 2 3 0 0 0 0 0 0 10.0 host 0\n", "beam count"},
      {"overflowing_count", "FLASER 99999999999999999999999 1 0 0 0 0 0 0 1 h 0\n", "beam count"},
      {"nan_pose", "FLASER 3 1 2 3 nan 0 0 0 0 0 10.0 host 0\n", "not finite"},
      {"inf_pose", "FLASER 3 1 2 3 0 0 0 0 inf 0 10.0 host 0\n", "not finite"},
      {"huge_pose", "FLASER 3 1 2 3 0 1e999 0 0 0 0 10.0 host 0\n", "not a number"},
      {"nan_timestamp", "FLASER 3 1 2 3 0 0 0 0 0 0 nan host 0\n", "ipc_timestamp"},
      {"trailing_junk_number", "FLASER 3 1 2 3 0 0 0 0 0 0 10.0x host 0\n", "ipc_timestamp"},
      {"odom_truncated", "ODOM 0 0 0 0 0\n", "ODOM"},
      {"odom_nan", "ODOM 0 nan 0 0 0 0 11.0 host 0\n", "not finite"},
      {"odom_text", "ODOM a b c 0 0 0 11.0 host 0\n", "not a number"},
      {"robotlaser_truncated", "ROBOTLASER1 0 -1.57 3.14 0.0174 81.9 0.01 0 3 1 2\n",
       "ROBOTLASER1"},
      {"robotlaser_huge_remissions",
       "ROBOTLASER1 0 -1.57 3.14 0.0174 81.9 0.01 0 1 1 99999999 0 0 0 0 0 0 0 0 0 0 0 1 h 0\n",
       "remission count"},
      {"robotlaser_wrong_remissions",
       "ROBOTLASER1 0 -1.57 3.14 0.0174 81.9 0.01 0 1 1 3 0 0 0 0 0 0 0 0 0 0 0 1 h 0\n",
       "remissions"},
      {"robotlaser_nan_angle",
       "ROBOTLASER1 0 nan 3.14 0.0174 81.9 0.01 0 1 1 0 0 0 0 0 0 0 0 0 0 0 0 1 h 0\n",
       "not finite"},
      {"param_without_value", "PARAM lonely\n", "PARAM"},
      {"param_bad_offset", "PARAM robot_frontlaser_offset abc\n", "robot_frontlaser_offset"},
  };
}

class CarmenMalformedTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir_.path() + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  const testing::ScopedTempDir dir_{"fleetmap-carmen-malformed"};
};

TEST_F(CarmenMalformedTest, EachBadLineStopsWithFileAndLineNumber) {
  for (const BadLine& bad : BadLines()) {
    SCOPED_TRACE(bad.name);
    const std::string path = Write(std::string(bad.name) + ".clf",
                                   std::string(kGoodFlaser) + kGoodOdom + bad.line + kGoodFlaser);
    std::string error;
    auto reader = CarmenReader::Open(path, CarmenReaderOptions(), &error);
    ASSERT_NE(reader, nullptr) << error;
    CarmenRecord record;
    int records = 0;
    while (reader->Next(&record)) ++records;
    EXPECT_EQ(records, 2);
    EXPECT_EQ(reader->error().rfind(path + ":3: ", 0), 0u) << reader->error();
    EXPECT_NE(reader->error().find(bad.expected_fragment), std::string::npos) << reader->error();
    EXPECT_FALSE(reader->Next(&record));  // stays stopped
  }
}

TEST_F(CarmenMalformedTest, SkipBadLinesCountsThemAndKeepsTheRest) {
  std::string text;
  int bad_count = 0;
  for (const BadLine& bad : BadLines()) {
    text += std::string(kGoodFlaser) + bad.line;
    ++bad_count;
  }
  text += kGoodOdom;
  CarmenReaderOptions options;
  options.skip_bad_lines = true;
  std::string error;
  auto reader = CarmenReader::Open(Write("all-bad.clf", text), options, &error);
  ASSERT_NE(reader, nullptr) << error;
  CarmenRecord record;
  int lasers = 0;
  int odometry = 0;
  while (reader->Next(&record)) {
    lasers += std::holds_alternative<LaserRecord>(record) ? 1 : 0;
    odometry += std::holds_alternative<OdometryRecord>(record) ? 1 : 0;
  }
  EXPECT_TRUE(reader->error().empty()) << reader->error();
  EXPECT_EQ(lasers, bad_count);
  EXPECT_EQ(odometry, 1);
  EXPECT_EQ(reader->skipped_lines(), bad_count);
  EXPECT_NE(reader->first_skipped_error().find(":2: "), std::string::npos)
      << reader->first_skipped_error();
}

TEST_F(CarmenMalformedTest, MaxBeamsOptionRefusesLargeScans) {
  CarmenReaderOptions options;
  options.max_beams = 2;
  std::string error;
  auto reader = CarmenReader::Open(Write("wide.clf", kGoodFlaser), options, &error);
  ASSERT_NE(reader, nullptr);
  CarmenRecord record;
  EXPECT_FALSE(reader->Next(&record));
  EXPECT_NE(reader->error().find("beam count 3"), std::string::npos) << reader->error();
}

TEST_F(CarmenMalformedTest, TruncatedCompressedFileIsAnError) {
  // Compress a log, then cut the file in half.
  std::string text;
  for (int i = 0; i < 2000; ++i) text += kGoodFlaser;
  gzFile gz = gzopen((dir_.path() + "/long.clf.gz").c_str(), "wb");
  ASSERT_NE(gz, nullptr);
  gzwrite(gz, text.data(), static_cast<unsigned>(text.size()));
  gzclose(gz);
  std::vector<char> bz(text.size() + 1000);
  unsigned bz_size = static_cast<unsigned>(bz.size());
  ASSERT_EQ(BZ2_bzBuffToBuffCompress(bz.data(), &bz_size, text.data(),
                                     static_cast<unsigned>(text.size()), 9, 0, 0),
            BZ_OK);
  Write("long.clf.bz2", std::string(bz.data(), bz_size));
  for (const char* name : {"long.clf.bz2", "long.clf.gz"}) {
    SCOPED_TRACE(name);
    const std::string full = dir_.path() + "/" + std::string(name);
    const auto size = std::filesystem::file_size(full);
    std::filesystem::resize_file(full, size / 2);
    std::string error;
    auto reader = CarmenReader::Open(full, CarmenReaderOptions(), &error);
    ASSERT_NE(reader, nullptr) << error;
    CarmenRecord record;
    int records = 0;
    while (reader->Next(&record)) ++records;
    EXPECT_LT(records, 2000);
    EXPECT_NE(reader->error().find("truncated"), std::string::npos) << reader->error();
  }
}

TEST_F(CarmenMalformedTest, CorruptCompressedDataIsAnError) {
  // A bzip2 magic followed by garbage, and a gzip magic followed by garbage.
  for (const std::string& text :
       {std::string("BZh9garbage garbage garbage\n"), std::string("\x1f\x8bgarbage\n")}) {
    std::string error;
    auto reader = CarmenReader::Open(Write("corrupt", text), CarmenReaderOptions(), &error);
    ASSERT_NE(reader, nullptr) << error;
    CarmenRecord record;
    EXPECT_FALSE(reader->Next(&record));
    EXPECT_NE(reader->error().find("corrupt"), std::string::npos) << reader->error();
  }
}

TEST_F(CarmenMalformedTest, EveryPrefixOfAValidLineParsesOrFailsCleanly) {
  const std::string lines[] = {
      "FLASER 3 1.5 2.5 3.5 0.1 0.2 0.3 0.4 0.5 0.6 976052857.337530 nohost 0.000246",
      "ROBOTLASER1 0 -1.57 3.14 0.0174 81.9 0.01 0 2 1 2 1 7 0.2 0 0 0 0 0 0 0 0 0 0 "
      "1232658478.161285 zoidberg2 -0.055208",
      "ODOM 1 2 0.5 0.3 0.1 0 976052857.337284 nohost 0",
      "PARAM robot_frontlaser_offset -0.04 1071078718.462495 merci 1071078718.462494"};
  std::string text;
  long prefixes = 0;
  long known_type = 0;  // prefixes that hold the whole message type
  for (const std::string& line : lines) {
    for (size_t length = 1; length < line.size(); ++length) {
      text += line.substr(0, length) + "\n";
      ++prefixes;
      if (length >= line.find(' ')) ++known_type;
    }
  }
  CarmenReaderOptions options;
  options.skip_bad_lines = true;
  std::string error;
  auto reader = CarmenReader::Open(Write("prefixes.clf", text), options, &error);
  ASSERT_NE(reader, nullptr) << error;
  CarmenRecord record;
  long records = 0;
  while (reader->Next(&record)) ++records;
  EXPECT_EQ(reader->error(), "");
  EXPECT_EQ(reader->line_number(), prefixes);
  // Each is a record (a few prefixes are valid lines, e.g. cut inside the last number) or a
  // counted bad line; shorter ones ("FLAS") are unknown types, skipped silently.
  EXPECT_EQ(records + reader->skipped_lines(), known_type);
  EXPECT_GT(reader->skipped_lines(), prefixes / 2);
}

TEST_F(CarmenMalformedTest, EndlessLineIsRefusedNotBuffered) {
  // 9 MB without a newline: more than DecompressingStream::kMaxLineBytes.
  std::string text = kGoodOdom;
  text += "FLASER ";
  text.append(size_t{9} << 20, '7');
  std::string error;
  auto reader = CarmenReader::Open(Write("endless.clf", text), CarmenReaderOptions(), &error);
  ASSERT_NE(reader, nullptr) << error;
  CarmenRecord record;
  EXPECT_TRUE(reader->Next(&record));
  EXPECT_FALSE(reader->Next(&record));
  EXPECT_NE(reader->error().find(":2: line longer than 8 MB"), std::string::npos)
      << reader->error();
}

TEST_F(CarmenMalformedTest, BinaryGarbageNeverCrashes) {
  // Deterministic pseudo-random bytes, with some real message types sprinkled in.
  std::string text;
  uint32_t state = 12345;
  const char* words[] = {"FLASER ", "ODOM ", "ROBOTLASER1 ", "PARAM ",  "nan ",
                         "1e308 ",  "\n",    "-5 ",          "100000 ", "3 "};
  for (int i = 0; i < 200000; ++i) {
    state = state * 1664525u + 1013904223u;
    if ((state >> 24) < 40) {
      text += words[(state >> 8) % 10];
    } else {
      text += static_cast<char>(state >> 16);
    }
  }
  CarmenReaderOptions options;
  options.skip_bad_lines = true;
  std::string error;
  auto reader = CarmenReader::Open(Write("garbage", text), options, &error);
  ASSERT_NE(reader, nullptr) << error;
  CarmenRecord record;
  while (reader->Next(&record)) {
  }
  EXPECT_GT(reader->line_number(), 0);
}

}  // namespace
}  // namespace fleetmap
