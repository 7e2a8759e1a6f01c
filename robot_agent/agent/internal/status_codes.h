#ifndef FLEETMAP_ROBOT_AGENT_AGENT_INTERNAL_STATUS_CODES_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_INTERNAL_STATUS_CODES_H_

#include <grpcpp/grpcpp.h>

#include <string>

namespace fleetmap::internal {

// Codes after which the same item may succeed later (the server is down, overloaded, or lost
// the robot). The others are the server's final word on the item: malformed, too large, or
// older than what it holds.
inline bool IsRetryable(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::OUT_OF_RANGE:
      return false;
    default:
      return true;
  }
}

inline std::string Describe(const grpc::Status& status) {
  return "status " + std::to_string(static_cast<int>(status.error_code())) + ": " +
         status.error_message();
}

}  // namespace fleetmap::internal

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_INTERNAL_STATUS_CODES_H_
