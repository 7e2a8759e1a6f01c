#include "robot_agent/localization/tool/mrclam_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace fleetmap {
namespace {

// Reads whitespace-separated numeric rows with at least `columns` values; skips blank lines and
// '#' comments (the raw MRCLAM files have a header).
bool ReadRows(const std::string& path, size_t columns, std::vector<std::vector<double>>* rows,
              std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open " + path;
    return false;
  }
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    double value;
    while (fields >> value) row.push_back(value);
    if (row.size() < columns || !std::all_of(row.begin(), row.end(), [](double v) {
          return std::isfinite(v);
        })) {
      *error = path + ":" + std::to_string(number) + ": expected " + std::to_string(columns) +
               " numbers, got \"" + line + "\"";
      return false;
    }
    rows->push_back(row);
  }
  return true;
}

}  // namespace

bool ReadMrclam(const std::string& directory, int robot_count, MrclamDataset* dataset,
                std::string* error) {
  *dataset = MrclamDataset();
  std::vector<std::vector<double>> rows;
  if (!ReadRows(directory + "/Barcodes.dat", 2, &rows, error)) return false;
  std::map<int, int> barcode_of_subject;
  for (const auto& row : rows) barcode_of_subject[static_cast<int>(row[0])] = static_cast<int>(row[1]);
  rows.clear();
  if (!ReadRows(directory + "/Landmark_Groundtruth.dat", 3, &rows, error)) return false;
  for (const auto& row : rows) {
    dataset->landmarks[static_cast<int>(row[0])] = Eigen::Vector2d(row[1], row[2]);
  }
  for (int r = 1; r <= robot_count; ++r) {
    MrclamRobot robot;
    const auto it = barcode_of_subject.find(r);
    if (it == barcode_of_subject.end()) {
      *error = directory + "/Barcodes.dat has no barcode for robot " + std::to_string(r);
      return false;
    }
    robot.barcode = it->second;
    const std::string stem = directory + "/newRobot" + std::to_string(r) + "_";
    rows.clear();
    if (!ReadRows(stem + "Odometry.txt", 3, &rows, error)) return false;
    for (const auto& row : rows) robot.odometry.push_back({row[0], row[1], row[2]});
    rows.clear();
    if (!ReadRows(stem + "Measurement.txt", 4, &rows, error)) return false;
    for (const auto& row : rows) {
      robot.measurements.push_back({row[0], static_cast<int>(row[1]), row[2], row[3]});
    }
    rows.clear();
    if (!ReadRows(stem + "Groundtruth.txt", 4, &rows, error)) return false;
    for (const auto& row : rows) robot.ground_truth.push_back({row[0], Rigid2d(row[1], row[2], row[3])});
    if (robot.odometry.empty() || robot.ground_truth.empty()) {
      *error = stem + "*: no odometry or ground truth";
      return false;
    }
    dataset->robot_by_barcode[robot.barcode] = r - 1;
    dataset->robots.push_back(std::move(robot));
  }
  return true;
}

}  // namespace fleetmap
