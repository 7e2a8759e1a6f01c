// fleetmap-agent: one robot's process (sensor source -> local SLAM or localization -> outbox ->
// server).
#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "robot_agent/agent/agent.h"
#include "robot_agent/agent/agent_config.h"

namespace {

// SIGINT/SIGTERM are taken by a dedicated thread (blocked everywhere else, so gRPC and SQLite
// threads never see them). The first asks the agent to stop and flush; a second exits at once
// (the outbox is durable, so nothing acknowledged-or-queued is lost).
void WatchSignals(const sigset_t& signals, fleetmap::Agent* agent) {
  int count = 0;
  while (true) {
    int signal = 0;
    if (sigwait(&signals, &signal) != 0) continue;
    if (signal == SIGUSR1) return;  // Run() is over
    if (++count == 1) {
      std::fprintf(stderr, "fleetmap-agent: %s received, stopping (again to exit now)\n",
                   signal == SIGINT ? "SIGINT" : "SIGTERM");
      agent->RequestStop();
    } else {
      std::fprintf(stderr, "fleetmap-agent: exiting now; queued items stay in the outbox\n");
      std::_Exit(0);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "fleetmap-agent: runs one robot's local SLAM (or, with `localization:` in its "
      "configuration, Monte Carlo localization in a known map) and uploads its submaps, "
      "trajectory and detections to a fleetmap server through a durable outbox"};
  std::string config_path;
  std::string server;
  std::string outbox;
  bool stay = false;
  app.add_option("--config", config_path, "robot configuration (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--server", server, "override server.address (host:port)");
  app.add_option("--outbox", outbox, "override outbox.path (SQLite file)");
  app.add_flag("--stay", stay,
               "keep uploading and following the global map after the source ends, until "
               "SIGINT/SIGTERM");
  CLI11_PARSE(app, argc, argv);

  fleetmap::AgentConfig config;
  std::string error;
  if (!fleetmap::LoadAgentConfig(config_path, &config, &error)) {
    std::fprintf(stderr, "fleetmap-agent: %s\n", error.c_str());
    return fleetmap::kAgentFailed;
  }
  if (!server.empty()) config.server_address = server;
  if (!outbox.empty()) config.outbox_path = outbox;
  if (!fleetmap::ValidateAgentConfig(config, &error)) {
    std::fprintf(stderr, "fleetmap-agent: %s: %s\n", config_path.c_str(), error.c_str());
    return fleetmap::kAgentFailed;
  }

  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // before any thread starts

  std::unique_ptr<fleetmap::Agent> agent = fleetmap::Agent::Create(config, &error);
  if (!agent) {
    std::fprintf(stderr, "fleetmap-agent: %s: %s\n", config_path.c_str(), error.c_str());
    return fleetmap::kAgentFailed;
  }
  std::thread watcher(WatchSignals, signals, agent.get());
  const int code = agent->Run(stay);
  pthread_kill(watcher.native_handle(), SIGUSR1);
  watcher.join();
  agent.reset();
  return code;
}
