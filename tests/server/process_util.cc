#include "tests/server/process_util.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "tests/support/test_support.h"

namespace fleetmap::testing {

ServerProcess StartServerProcess(const std::string& db, const std::string& work_dir,
                                 const std::string& log) {
  const std::string binary = TestBuildDir() + "/map_server/server/fleetmap-server";
  const std::string port_file = work_dir + "/port";
  std::remove(port_file.c_str());
  ServerProcess server;
  server.pid = fork();
  if (server.pid == 0) {
    FILE* out = std::freopen(log.c_str(), "a", stdout);
    if (out) dup2(fileno(stdout), fileno(stderr));
    execl(binary.c_str(), binary.c_str(), "--db", db.c_str(), "--listen", "127.0.0.1:0",
          "--port-file", port_file.c_str(), "--version-interval", "0.05",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int i = 0; i < 500 && server.pid > 0; ++i) {
    std::ifstream in(port_file);
    if (in >> server.port && server.port > 0) return server;
    int status;
    if (waitpid(server.pid, &status, WNOHANG) == server.pid) {
      server.pid = -1;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  server.port = 0;
  return server;
}

int StopProcess(pid_t pid, int signal) {
  if (pid <= 0) return -1;
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

int RunCtl(const std::string& args, std::string* output) {
  const std::string command = TestBuildDir() + "/map_server/ctl/fleetmapctl " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  output->clear();
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) output->append(buffer, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace fleetmap::testing
