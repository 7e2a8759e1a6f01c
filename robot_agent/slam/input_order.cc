#include "robot_agent/slam/input_order.h"

#include <cmath>
#include <sstream>

namespace fleetmap {

bool CheckInputTime(double timestamp, double last_time, const char* what, std::string* error) {
  if (!std::isfinite(timestamp)) {
    if (error) *error = std::string(what) + " with a non-finite timestamp";
    return false;
  }
  if (timestamp < last_time) {
    std::ostringstream message;
    message.precision(17);
    message << what << " at time " << timestamp << " is older than the previous input (time "
            << last_time << "): inputs must come in time order";
    if (error) *error = message.str();
    return false;
  }
  return true;
}

}  // namespace fleetmap
