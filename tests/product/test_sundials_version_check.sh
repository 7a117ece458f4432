#!/usr/bin/env bash
# The configure step accepts SUNDIALS 6.x and stops with one clear message on any other version
# (cmake/sundials_version.cmake, run as a script on made-up versions).
# Usage: test_sundials_version_check.sh [SOURCE_DIR]; $CMAKE names cmake (default: cmake on PATH).
set -euo pipefail
root=${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
cmake=${CMAKE:-cmake}
module=$root/cmake/sundials_version.cmake
fail=0
for v in 6.0.0 6.4.1 6.7.0; do
  if ! out=$("$cmake" -DVERSION="$v" -P "$module" 2>&1); then
    echo "FAIL: SUNDIALS $v refused: $out" >&2
    fail=1
  fi
done
for v in 5.8.0 7.0.0 7.1.1 ""; do
  if out=$("$cmake" -DVERSION="$v" -P "$module" 2>&1); then
    echo "FAIL: SUNDIALS '$v' accepted" >&2
    fail=1
  elif ! grep -q "kanesens needs SUNDIALS 6.x" <<<"$out"; then
    echo "FAIL: SUNDIALS '$v' refused without the message: $out" >&2
    fail=1
  fi
done
[[ $fail == 0 ]] && echo "ok: 6.x accepted; 5.x, 7.x and an unknown version refused with the message"
exit $fail
