#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_MRCLAM_READER_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_MRCLAM_READER_H_

#include <map>
#include <string>
#include <vector>

#include "robot_agent/localization/landmark_model.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// The UTIAS MRCLAM data set in the resampled form (sampleMRCLAMdataSet.m output: every robot on
// the same 0.02 s grid starting at 0): per robot `newRobotN_{Odometry,Measurement,Groundtruth}.txt`,
// plus Barcodes.dat (subject -> barcode; subjects 1-5 are the robots) and
// Landmark_Groundtruth.dat (barcode x y sx sy).
struct MrclamOdometry {
  double time = 0.0;
  double v = 0.0;  // m/s
  double w = 0.0;  // rad/s
};

struct MrclamMeasurement {
  double time = 0.0;
  int barcode = 0;
  double range = 0.0;
  double bearing = 0.0;
};

struct MrclamGroundTruth {
  double time = 0.0;
  Rigid2d robot_in_map;
};

struct MrclamRobot {
  int barcode = 0;
  std::vector<MrclamOdometry> odometry;
  std::vector<MrclamMeasurement> measurements;
  std::vector<MrclamGroundTruth> ground_truth;
};

struct MrclamDataset {
  LandmarkMap landmarks;              // by barcode
  std::map<int, int> robot_by_barcode;  // barcode -> index into robots
  std::vector<MrclamRobot> robots;      // robot 1 at index 0
};

// Reads robots 1..robot_count from `directory`. Fills `error` and returns false on a missing
// file or a malformed line (with file name and line number).
bool ReadMrclam(const std::string& directory, int robot_count, MrclamDataset* dataset,
                std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_MRCLAM_READER_H_
