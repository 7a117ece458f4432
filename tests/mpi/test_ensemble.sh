#!/usr/bin/env bash
# `kanesens run` under MPI: the same study on 1, 2 and 3 ranks (oversubscribed) gives bitwise
# identical datasets, with CVODES and with DOP853 (solver.method: dop853), events, extrema and
# values at events included; a stopping event's time is /stopped_at and later output times are
# NaN; xarray sees named dimensions; an existing output is not overwritten; a run
# killed with SIGKILL mid-way is finished by --resume and then equals an uninterrupted run;
# --resume refuses a file of another study.
set -euo pipefail
: "${KANESENS:?path to the kanesens executable}"
source "$(dirname "$0")/common.sh"
study="$here/ensemble_study.yaml"
run() { local np=$1; shift; mpirun --allow-run-as-root --oversubscribe -np "$np" "$KANESENS" run "$study" "$@"; }
check() { "$KANESENS_PYTHON" "$here/check_ensemble.py" "$@"; }

run 1 -o "$work/r1.h5"
run 2 -o "$work/r2.h5" --chunk 1
run 3 -o "$work/r3.h5"
check status "$work/r1.h5" 30 0 0
check same "$work/r1.h5" "$work/r2.h5"
check same "$work/r1.h5" "$work/r3.h5"
check xarray "$work/r2.h5"
check events "$work/r1.h5"
run 1 -o "$work/d1.h5" --set solver.method=dop853
run 2 -o "$work/d2.h5" --set solver.method=dop853 --chunk 1
check status "$work/d1.h5" 30 0 0
check same "$work/d1.h5" "$work/d2.h5"

# Refuses to overwrite; the file is untouched.
before=$(md5sum < "$work/r1.h5")
if run 1 -o "$work/r1.h5" 2>"$work/err.txt"; then echo "FAIL: overwrote an existing output"; exit 1; fi
grep -q "already exists" "$work/err.txt"
[[ "$before" == "$(md5sum < "$work/r1.h5")" ]]

# Killed mid-run (kill -9 of rank 0 after its 4th sample), then resumed.
if KANESENS_FAULT_KILL_AFTER_SAMPLES=4 run 2 -o "$work/killed.h5" --chunk 1 >/dev/null 2>&1; then
  echo "FAIL: the run was expected to die"; exit 1
fi
"$KANESENS_PYTHON" - "$work/killed.h5" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    s = f["status"][()]
    done = int(np.sum(s == 1))
    assert 4 <= done < 30, done
    assert np.all(np.isfinite(f["states"][np.flatnonzero(s == 1), 0]))  # later times: NaN after a stop
    print(f"killed run left {done} complete samples")
PY
run 2 -o "$work/killed.h5" --resume
check same "$work/r1.h5" "$work/killed.h5"

# --resume of a file written for another study (different --set) is refused.
if run 1 -o "$work/r1.h5" --resume --set m1=2 2>"$work/err.txt"; then echo "FAIL: resumed another study's file"; exit 1; fi
grep -qi "study_hash" "$work/err.txt"
echo "test_ensemble: ok"
