#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz) in the instrumented tree that tools/sanitize.sh
# uses (tools/asan-tree.sh: clang, ASan, UBSan, libFuzzer's coverage; build-asan/), and runs
# each for a bounded time over a copy of its seed corpus:
#   fuzz_scene   scene text -> what `check` does (model build, constraints, forces, initial state);
#                seeds tests/fuzz/corpus/scene/ and the shipped configs/, dictionary yaml.dict,
#                number/name mutations of tests/fuzz/yaml_mutator.hpp
#   fuzz_study   study text -> study::setup_study (everything simulate and run check); the same
#   fuzz_expr    expression text -> compile + evaluate + gradient (the same value)
#   fuzz_resume  edits of a real run file -> RunFile::open_for_resume + rows written
# Exits non-zero on any finding; the input is left in build-asan/fuzz/artifacts/<target>/ (it
# then becomes a row of tests/unit/test_bad_input.cpp or tests/unit/test_run_file.cpp with the
# fix). Prints, per target, the executions and the coverage reached (libFuzzer's cov: edges,
# ft: features).
#   FUZZ_SECONDS=20 (per target)   FUZZ_TARGETS="fuzz_scene fuzz_study fuzz_expr fuzz_resume"
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${KANESENS_ASAN_BUILD_DIR:-$root/build-asan}
seconds=${FUZZ_SECONDS:-20}
targets=(${FUZZ_TARGETS:-fuzz_scene fuzz_study fuzz_expr fuzz_resume})

start=$(date +%s)
bash "$root/tools/asan-tree.sh" "$build"
cmake --build "$build" -j "${KANESENS_JOBS:-$(nproc)}" --target "${targets[@]}"
echo "fuzz: build $(( $(date +%s) - start )) s"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # fuzz_resume starts MPI (a singleton)

status=0
for t in "${targets[@]}"; do
  name=${t#fuzz_}
  work="$build/fuzz/corpus-work/$name" artifacts="$build/fuzz/artifacts/$name"
  mkdir -p "$work" "$artifacts"
  options=(-max_len=4096)
  seeds=("$root/tests/fuzz/corpus/$name")
  case $name in
    scene | study) options=(-max_len=16384 -dict="$root/tests/fuzz/yaml.dict"); seeds+=("$root/configs") ;;
    # MPI_Init's process-lifetime allocations would be reported as leaks and attributing them
    # needs the slow unwinder (a third of the speed): leaks of the io code are checked by
    # test_run_file under LeakSanitizer (tools/sanitize.sh); here ASan looks for memory errors.
    resume) options=(-max_len=64); export ASAN_OPTIONS=detect_leaks=0 ;;
  esac
  # -rss_limit/-timeout: a slow or memory-hungry input is a finding too (kanesens runs unattended).
  if "$build/tests/fuzz/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 "${options[@]}" \
       -print_final_stats=1 -artifact_prefix="$artifacts/" "$work" "${seeds[@]}" >"$build/fuzz/$t.log" 2>&1; then
    runs=$(grep -m1 '^stat::number_of_executed_units' "$build/fuzz/$t.log" | awk '{print $2}')
    unset ASAN_OPTIONS
    cov=$(grep -E '^#[0-9]+' "$build/fuzz/$t.log" | grep -o 'cov: [0-9]* ft: [0-9]*' | tail -1)
    echo "fuzz: $t ok: ${runs:-?} executions in ${seconds} s, ${cov:-cov: ?}, corpus $(ls "$work" | wc -l) inputs"
  else
    unset ASAN_OPTIONS
    status=1
    echo "fuzz: $t FOUND A PROBLEM (input in $artifacts/):"
    grep -E "ERROR|SUMMARY|not an InputError|unexpected exception|Test unit written" "$build/fuzz/$t.log" | head -10 || true
  fi
done
echo "fuzz: total $(( $(date +%s) - start )) s"
exit $status
