#!/usr/bin/env bash
# io::RunFile under MPI: 3 ranks write interleaved samples of one file (run_file_writer); h5py
# and xarray (engine="h5netcdf") read it back. Then a run killed with SIGKILL must leave a
# readable file with its completed samples intact, and --resume must finish it.
set -euo pipefail
: "${RUN_FILE_WRITER:?path to the run_file_writer test driver}"
source "$(dirname "$0")/common.sh"
mpirun_() { mpirun --allow-run-as-root --oversubscribe -np 3 "$@"; }
check() { "$KANESENS_PYTHON" "$here/check_run_file.py" "$@"; }

# 1. A complete run.
mpirun_ "$RUN_FILE_WRITER" "$work/full.h5"
check complete "$work/full.h5" 3

# 2. Refuses to overwrite, naming the path and the flags.
if mpirun_ "$RUN_FILE_WRITER" "$work/full.h5" 2>"$work/err.txt"; then
  echo "FAIL: an existing file was overwritten"; exit 1
fi
grep -q "full.h5' already exists; pass --overwrite" "$work/err.txt"

# 3. Killed (kill -9) after rank 0's second sample; then resumed.
if mpirun_ "$RUN_FILE_WRITER" "$work/killed.h5" --kill-after 2 >/dev/null 2>&1; then
  echo "FAIL: the writer was expected to die"; exit 1
fi
check killed "$work/killed.h5" 3 2
mpirun_ "$RUN_FILE_WRITER" "$work/killed.h5" --resume
check complete "$work/killed.h5" 3

# 4. Resuming with another study's hash is refused.
if mpirun_ "$RUN_FILE_WRITER" "$work/killed.h5" --resume --study-hash other 2>"$work/err.txt"; then
  echo "FAIL: resumed a file of another study"; exit 1
fi
grep -q "study_hash hash-1 differs from this study's other" "$work/err.txt"
echo "test_run_file_parallel: ok"
