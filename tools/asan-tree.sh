#!/usr/bin/env bash
# Makes the instrumented build tree that tools/sanitize.sh and tools/fuzz.sh share (one
# compilation of the sources serves both): clang, RelWithDebInfo at -O1 -g1 (the sanitizers'
# recommendation; -O2 -g takes far longer to build), ASan + UBSan without recovery, libFuzzer's
# coverage on every object (KANESENS_SANITIZE=ON with KANESENS_FUZZ=ON), warnings as errors,
# the engine without its multi-tangent widths 12 and 10 (KANESENS_ALL_MULTI_DUAL_WIDTHS=OFF: the
# same templates, which the Release tree's tests run at those widths), Ninja where it is
# installed. Installs clang (Debian's clang-14 ships libFuzzer) if missing.
# A tree made otherwise (another compiler or options) is made again.
# Usage: tools/asan-tree.sh BUILD_DIR
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$1

if ! command -v clang++ >/dev/null || ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' \
     | clang++ -x c++ -fsanitize=fuzzer - -o /dev/null 2>/dev/null; then
  sudo_cmd=(); [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  echo "asan-tree: installing clang (libFuzzer)"
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends clang >/dev/null \
    || { "${sudo_cmd[@]}" apt-get update -qq && DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends clang; }
fi

cache=$build/CMakeCache.txt
if [[ -f $cache ]] && ! { grep -q '^KANESENS_SANITIZE:BOOL=ON$' "$cache" && grep -q '^KANESENS_FUZZ:BOOL=ON$' "$cache" \
                          && grep -q '^KANESENS_ALL_MULTI_DUAL_WIDTHS:BOOL=OFF$' "$cache" \
                          && grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++' "$cache"; }; then
  echo "asan-tree: $build was configured otherwise; making it again"
  rm -rf "$build"
fi
if [[ ! -f $cache ]]; then
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake "${generator[@]}" -S "$root" -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DKANESENS_SANITIZE=ON -DKANESENS_FUZZ=ON -DKANESENS_WERROR=ON -DKANESENS_ALL_MULTI_DUAL_WIDTHS=OFF >/dev/null
fi
