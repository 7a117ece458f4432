#!/usr/bin/env bash
# KANESENS_ARCH: the configure step stops with one clear message on an instruction set the
# compiler does not know (CMakeLists.txt), before it writes any build files.
# Usage: test_arch_option.sh [SOURCE_DIR]; $CMAKE names cmake (default: cmake on PATH).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
cmake=${CMAKE:-cmake}
build=$(mktemp -d)
trap 'rm -rf "$build"' EXIT
if out=$("$cmake" -S "$root" -B "$build" -DKANESENS_ARCH=no-such-arch -DKANESENS_BUILD_TESTS=OFF 2>&1); then
  echo "FAIL: KANESENS_ARCH=no-such-arch accepted" >&2
  exit 1
fi
# CMake wraps long messages: compare with the line breaks folded into spaces.
if ! tr -s ' \n' '  ' <<<"$out" | grep -q "KANESENS_ARCH=no-such-arch: .* does not accept -march=no-such-arch"; then
  echo "FAIL: refused without the message: $out" >&2
  exit 1
fi
if [[ -e $build/Makefile || -e $build/build.ninja ]]; then
  echo "FAIL: build files written for a refused KANESENS_ARCH" >&2
  exit 1
fi
echo "ok: an unknown instruction set is refused with the message"
