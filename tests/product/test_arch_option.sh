#!/usr/bin/env bash
# KANESENS_ARCH (CMakeLists.txt): the configure step stops with one clear message on an
# instruction set the compiler does not know, before it writes any build files; the default,
# `auto`, builds for the build machine's processor (-march=native) and falls back to the
# compiler's baseline, with a message, when the compiler does not accept -march=native.
# Usage: test_arch_option.sh [SOURCE_DIR]; $CMAKE names cmake (default: cmake on PATH).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
cmake=${CMAKE:-cmake}
build=$(mktemp -d)
trap 'rm -rf "$build"' EXIT
if out=$("$cmake" -S "$root" -B "$build/bad" -DKANESENS_ARCH=no-such-arch -DKANESENS_BUILD_TESTS=OFF 2>&1); then
  echo "FAIL: KANESENS_ARCH=no-such-arch accepted" >&2
  exit 1
fi
# CMake wraps long messages: compare with the line breaks folded into spaces.
if ! tr -s ' \n' '  ' <<<"$out" | grep -q "KANESENS_ARCH=no-such-arch: .* does not accept -march=no-such-arch"; then
  echo "FAIL: refused without the message: $out" >&2
  exit 1
fi
if [[ -e $build/bad/Makefile || -e $build/bad/build.ninja ]]; then
  echo "FAIL: build files written for a refused KANESENS_ARCH" >&2
  exit 1
fi
echo "ok: an unknown instruction set is refused with the message"

# The default, with a compiler that accepts -march=native and with one that does not (the
# system's C++ compiler behind a wrapper that refuses that flag).
cxx=$(command -v c++ || command -v g++)
printf '#!/bin/sh\nfor a in "$@"; do [ "$a" = -march=native ] && { echo "unknown -march=native" >&2; exit 1; }; done\nexec %s "$@"\n' \
  "$cxx" >"$build/refuses-native"
chmod +x "$build/refuses-native"
for case in accepts refuses; do
  compiler=$cxx
  [[ $case == refuses ]] && compiler=$build/refuses-native
  if ! out=$("$cmake" -S "$root" -B "$build/$case" -DCMAKE_CXX_COMPILER="$compiler" -DKANESENS_BUILD_TESTS=OFF 2>&1); then
    echo "FAIL: the default KANESENS_ARCH does not configure with a compiler that $case -march=native: $out" >&2
    exit 1
  fi
  arch=$(sed -n 's/^#define KANESENS_ARCH "\(.*\)"$/\1/p' "$build/$case/generated/kanesens/version_config.hpp")
  flags=$(grep -h -o -- '-march=[^ ]*' "$build/$case"/CMakeFiles/*.dir/flags.make "$build/$case"/build.ninja 2>/dev/null | sort -u || true)
  if [[ $case == accepts ]]; then
    if [[ $arch != native || $flags != "-march=native" ]]; then
      echo "FAIL: KANESENS_ARCH=auto with a compiler that accepts -march=native: arch '$arch', flags '$flags'" >&2
      exit 1
    fi
  else
    if [[ -n $arch || -n $flags ]] || ! tr -s ' \n' '  ' <<<"$out" | grep -q "KANESENS_ARCH=auto: .* does not accept -march=native; building for its baseline instruction set"; then
      echo "FAIL: KANESENS_ARCH=auto with a compiler that refuses -march=native: arch '$arch', flags '$flags': $out" >&2
      exit 1
    fi
  fi
done
echo "ok: KANESENS_ARCH=auto builds for the build machine, or for the baseline with a message"
