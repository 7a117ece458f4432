#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz: scene parser + model build, expression parser,
# study sampling/vary parser + Design) with clang, ASan and UBSan into build-fuzz/, and runs each
# for a bounded time over a copy of the committed seed corpus tests/fuzz/corpus/<target>/.
# Installs clang (Debian's clang-14 ships libFuzzer) if missing. Exits non-zero on any finding;
# the crashing input is left in build-fuzz/artifacts/<target>/ (add it to
# tests/unit/test_fuzz_regressions.cpp with the fix).
#   FUZZ_SECONDS=20 (per target)   FUZZ_TARGETS="fuzz_scene fuzz_expr fuzz_study"
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${KANESENS_FUZZ_BUILD_DIR:-$root/build-fuzz}
seconds=${FUZZ_SECONDS:-20}
targets=(${FUZZ_TARGETS:-fuzz_scene fuzz_expr fuzz_study})

if ! command -v clang++ >/dev/null || ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' \
     | clang++ -x c++ -fsanitize=fuzzer - -o /dev/null 2>/dev/null; then
  sudo_cmd=(); [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  echo "fuzz: installing clang (libFuzzer)"
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends clang >/dev/null \
    || { "${sudo_cmd[@]}" apt-get update -qq && DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends clang; }
fi

start=$(date +%s)
if [[ ! -f $build/CMakeCache.txt ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DKANESENS_FUZZ=ON -DKANESENS_BUILD_TESTS=OFF >/dev/null
fi
cmake --build "$build" -j "${KANESENS_JOBS:-$(nproc)}" --target "${targets[@]}"
echo "fuzz: build $(( $(date +%s) - start )) s"

status=0
for t in "${targets[@]}"; do
  name=${t#fuzz_}
  work="$build/corpus-work/$name" artifacts="$build/artifacts/$name"
  mkdir -p "$work" "$artifacts"
  # -rss_limit/-timeout: a slow or memory-hungry input is a finding too (kanesens runs unattended).
  if "$build/tests/fuzz/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=4096 \
       -print_final_stats=1 -artifact_prefix="$artifacts/" "$work" "$root/tests/fuzz/corpus/$name" \
       >"$build/$t.log" 2>&1; then
    runs=$(grep -m1 '^stat::number_of_executed_units' "$build/$t.log" | awk '{print $2}')
    echo "fuzz: $t ok: ${runs:-?} executions in ${seconds} s, corpus $(ls "$work" | wc -l) inputs"
  else
    status=1
    echo "fuzz: $t FOUND A PROBLEM (input in $artifacts/):"
    grep -E "ERROR|SUMMARY|not an InputError|Test unit written" "$build/$t.log" | head -10 || true
  fi
done
echo "fuzz: total $(( $(date +%s) - start )) s"
exit $status
