#ifndef FLEETMAP_TESTS_AGENT_CHILD_PROCESS_H_
#define FLEETMAP_TESTS_AGENT_CHILD_PROCESS_H_

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace fleetmap::testing {

// A program run by a test, its output (stdout + stderr) going to `log_path`. Killed with
// SIGKILL if still running when destroyed.
class ChildProcess {
 public:
  ChildProcess(const std::string& program, const std::vector<std::string>& args,
               const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  void Signal(int signal);
  // The exit code, or nullopt when it did not exit within `seconds` (or died of a signal: then
  // 128 + signal).
  std::optional<int> Wait(double seconds);
  std::string Output() const;

 private:
  pid_t pid_ = -1;
  std::string log_path_;
  std::optional<int> exit_code_;
};

// Reads a whole file ("" when absent).
std::string ReadFile(const std::string& path);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_AGENT_CHILD_PROCESS_H_
