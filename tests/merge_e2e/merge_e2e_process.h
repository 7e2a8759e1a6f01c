#ifndef FLEETMAP_TESTS_MERGE_E2E_MERGE_E2E_PROCESS_H_
#define FLEETMAP_TESTS_MERGE_E2E_MERGE_E2E_PROCESS_H_

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace fleetmap::testing {

// A program run by the merge end-to-end test, output appended to `log_path`. Killed with
// SIGKILL if still running when destroyed.
class E2eProcess {
 public:
  E2eProcess(const std::string& program, const std::vector<std::string>& args,
             const std::string& log_path);
  ~E2eProcess();
  E2eProcess(const E2eProcess&) = delete;
  E2eProcess& operator=(const E2eProcess&) = delete;

  bool started() const { return pid_ > 0; }
  bool Running();
  void Signal(int signal);
  // The exit code (128 + signal when killed), or nothing when still running after `seconds`.
  std::optional<int> Wait(double seconds);

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
};

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_MERGE_E2E_MERGE_E2E_PROCESS_H_
