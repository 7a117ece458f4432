#!/usr/bin/env bash
# Builds kanesens with AddressSanitizer + UndefinedBehaviorSanitizer (clang, warnings as errors)
# into build-asan/ (tools/asan-tree.sh; the same tree builds tools/fuzz.sh's harnesses) and runs
# the unit tests there (ctest -L unit), with LeakSanitizer on: the CVODES wrappers
# (test_integrator) and the HDF5 wrappers (test_run_file, test_hdf5_text) must not leak.
# tests/lsan.supp suppresses leaks inside third-party internals only (Open MPI / PMIx / hwloc
# start-up); kanesens's own handles are never suppressed.
# Only the unit-test targets are built (see docs/explanation/reliability.md for the CI time budget).
# Extra arguments go to ctest, e.g. tools/sanitize.sh -R BadInput
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${KANESENS_ASAN_BUILD_DIR:-$root/build-asan}
start=$(date +%s)
bash "$root/tools/install-deps.sh" >/dev/null
bash "$root/tools/asan-tree.sh" "$build"
# The unit-test programs (tests/CMakeLists.txt: unit_tests and the standalone ones) and what they link.
cmake --build "$build" -j "${KANESENS_JOBS:-$(nproc)}" --target unit_test_programs
built=$(date +%s)
# The programs that start MPI add fast_unwind_on_malloc=0 to ASAN_OPTIONS for their tests
# (tests/CMakeLists.txt): full leak stacks through libraries built without frame pointers
# (otherwise Open MPI's leaks show as "<unknown module>" and cannot be attributed or suppressed);
# Open MPI must keep its MCA plugins loaded for the same reason.
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export OMPI_MCA_mca_base_component_disable_dlclose=1
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$build"
ctest -L unit --output-on-failure -j "${KANESENS_JOBS:-$(nproc)}" "$@"
echo "sanitize: build $((built - start)) s, tests $(( $(date +%s) - built )) s"
