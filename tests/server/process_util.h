#ifndef FLEETMAP_TESTS_SERVER_PROCESS_UTIL_H_
#define FLEETMAP_TESTS_SERVER_PROCESS_UTIL_H_

#include <sys/types.h>

#include <string>
#include <vector>

namespace fleetmap::testing {

// A fleetmap-server child process on a loopback port.
struct ServerProcess {
  pid_t pid = -1;
  int port = 0;
  std::string address() const { return "127.0.0.1:" + std::to_string(port); }
};

// Starts build/map_server/server/fleetmap-server on `db` (output to `log`); waits until it
// listens. pid < 0 or port 0 on failure.
ServerProcess StartServerProcess(const std::string& db, const std::string& work_dir,
                                 const std::string& log);
// Sends `signal` and waits for the process; returns its exit status (or 128 + signal).
int StopProcess(pid_t pid, int signal);

// Runs fleetmapctl with `args`; returns its exit code and fills `output` (stdout + stderr).
int RunCtl(const std::string& args, std::string* output);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_SERVER_PROCESS_UTIL_H_
