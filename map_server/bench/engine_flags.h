#ifndef FLEETMAP_MAP_SERVER_BENCH_ENGINE_FLAGS_H_
#define FLEETMAP_MAP_SERVER_BENCH_ENGINE_FLAGS_H_

#include <CLI/CLI.hpp>

#include "map_server/merge/merge_engine.h"

namespace fleetmap {

// The merge engine's settings that the bench tools (fleetmap-merge-sim-bench,
// fleetmap-merge-replay) let a run change, each defaulting to the engine's own.
void AddEngineFlags(CLI::App* app, MergeEngineOptions* options);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_ENGINE_FLAGS_H_
