#!/usr/bin/env bash
# Configures and builds kanesens into build/ (Release). Reuses an existing build tree, so a
# second call only rebuilds what changed. Extra arguments go to the CMake configure step.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${KANESENS_BUILD_DIR:-$root/build}
jobs=${KANESENS_JOBS:-$(nproc)}
if [[ ! -f $build/CMakeCache.txt || $# -gt 0 ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@"
fi
cmake --build "$build" -j "$jobs"
