#!/usr/bin/env bash
# Configures and builds kanesens into build/ (Release). Reuses an existing build tree, so a
# second call only rebuilds what changed. Extra arguments go to the CMake configure step.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${KANESENS_BUILD_DIR:-$root/build}
jobs=${KANESENS_JOBS:-$(nproc)}
# A new tree is made with Ninja where it is installed: it compiles a target's objects while the
# libraries it links are still building, which Make's per-target order does not. An existing
# tree keeps the generator it was made with.
generator=()
if [[ ! -f $build/CMakeCache.txt ]] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
if [[ ! -f $build/CMakeCache.txt || $# -gt 0 ]]; then
  cmake "${generator[@]}" -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@"
fi
cmake --build "$build" -j "$jobs"
