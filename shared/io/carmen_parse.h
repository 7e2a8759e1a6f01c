#ifndef FLEETMAP_SHARED_IO_CARMEN_PARSE_H_
#define FLEETMAP_SHARED_IO_CARMEN_PARSE_H_

// Internal to the CARMEN reader and writer: tokenising and parsing one message line.

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "shared/io/carmen_log.h"

namespace fleetmap {
namespace carmen {

using Tokens = std::vector<std::string_view>;

// Splits on spaces, tabs and '\r' (logs written on Windows end lines with "\r\n").
void SplitTokens(std::string_view line, Tokens* tokens);

// Strict numbers: the whole token must parse ("1.5x" is an error); a leading '+' is accepted.
bool ParseDouble(std::string_view token, double* value);
bool ParseInt(std::string_view token, long* value);

// FLASER has no angle fields (SOURCES.md): 180 degrees starting at -90 degrees. An even beam
// count n covers [-90, 90) at 180/n degrees (180 -> 1 degree, 360 -> 0.5); an odd count covers
// both ends, [-90, +90] at 180/(n-1) degrees (181 -> 1, 361 -> 0.5).
constexpr double kFlaserAngleMin = -M_PI / 2;
double FlaserAngleIncrement(int beams);

// What earlier lines (PARAM) say about the ones that follow.
struct LogState {
  double max_range = 50.0;  // readings at or above it are no-return
  bool has_frontlaser_offset = false;
  double frontlaser_offset = 0.0;  // PARAM robot_frontlaser_offset, metres along robot x
};

// Each parser takes the tokens of one line (tokens[0] is the message type) and returns false
// with a message (no file or line number) when the line is malformed.
bool ParseOdometry(const Tokens& tokens, OdometryRecord* record, std::string* error);
bool ParseFlaser(const Tokens& tokens, const LogState& state, int max_beams, LaserRecord* record,
                 std::string* error);
bool ParseRobotLaser(const Tokens& tokens, const LogState& state, int max_beams,
                     LaserRecord* record, std::string* error);
bool ParseParam(const Tokens& tokens, ParamRecord* record, std::string* error);

}  // namespace carmen
}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_CARMEN_PARSE_H_
