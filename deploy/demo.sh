#!/usr/bin/env bash
# The main job: installs dependencies, builds, starts a map server and three simulated robots
# with unknown start poses (the department_3robots scenario), waits for the merge, and prints
# a summary with the merge error against ground truth. The merged map ends up in out/demo/.
# Usage: deploy/demo.sh [launch.sh options, e.g. --scenario building_3robots]
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/install-deps.sh
BUILD_DIR=${FLEETMAP_BUILD_DIR:-build}
echo "demo: building (first time: a few minutes on 2 cores)"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)" -- --no-print-directory > "$BUILD_DIR/build.log" 2>&1 \
  || { tail -n 30 "$BUILD_DIR/build.log"; echo "demo: build failed, full log in $BUILD_DIR/build.log" >&2; exit 1; }
exec ./deploy/launch.sh --bin "$BUILD_DIR" --out out/demo --scenario department_3robots "$@"
