#!/usr/bin/env bash
# Runtime faults never lose computed samples:
#  1. per-sample faults are recorded and the run goes on: a lognormal draw that overflows to inf
#     (status -100), a singular mass matrix (CVODES CV_FIRST_RHSFUNC_ERR), a force that blows up
#     (error-test failures, CV_TOO_MUCH_WORK; every sample fails: exit 5);
#  2. SIGTERM to mpirun (2 ranks) and SIGINT to a lone kanesens: the ranks stop claiming samples,
#     finish the ones in flight, close the file and say how to --resume (kanesens exits 130/143);
#     --resume completes the file, which then equals an uninterrupted run bitwise;
#  3. a full disk (a 1 MiB / 8 MiB tmpfs; skipped when mount is not permitted): the pre-check
#     refuses a run that cannot fit; HDF5's own ENOSPC (pre-check skipped) gives a clear error and
#     leaves no file; a disk that fills up after the file was created loses nothing (space is
#     allocated at creation) and an interrupted run is --resume'd on the full disk.
set -euo pipefail
: "${KANESENS:?path to the kanesens executable}"
source "$(dirname "$0")/common.sh"
mnt="$work/small"
cleanup() { mountpoint -q "$mnt" 2>/dev/null && umount "$mnt"; rm -rf "$work"; }
trap cleanup EXIT
cd "$work"
run() { mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run "$@"; }
check() { "$KANESENS_PYTHON" "$here/check_ensemble.py" "$@"; }
py() { "$KANESENS_PYTHON" - "$@"; }

# ---- 1. per-sample faults -------------------------------------------------------------------
cat > faults.yaml <<'YAML'
kanesens: 1
scene:
  name: faults
  gravity: [0, -9.81, 0]
  parameters: {m: 1, r: 0.5, F: 0}
  bodies:
    - {name: ball, mass: m, inertia: {shape: point}}
  joints:
    - {name: hinge, type: revolute, parent: ground, child: ball, axis: [0, 0, 1], child_point: [r, 0, 0], q0: 0.3}
  forces:
    - {type: force, name: kick, body: ball, vector: ["F/(t-0.5)^2", 0, 0]}
time: {end: 1, outputs: 11}
sampling: {method: grid, levels: 3}
vary:
  m: {dist: lognormal, mu: 705, sigma: 10}
YAML
# exp(705 ± 9.7): the upper grid point overflows to inf.
run faults.yaml -o lognormal.h5 >/dev/null
check status lognormal.h5 2 1 0
py lognormal.h5 <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    s, m, p = f["status"][()], f["message"][()], f["parameters"][()][:, 0]
    assert s[2] == -100 and np.isinf(p[2]) and b"not finite" in m[2], (s, m, p)
PY
# r on the grid -1/3, 0, 1/3: a point mass on its own hinge axis has M = 0.
sed 's/m: {dist: lognormal, mu: 705, sigma: 10}/r: {dist: uniform, low: -0.5, high: 0.5}/' faults.yaml > singular.yaml
run singular.yaml -o singular.h5 >/dev/null
check status singular.h5 2 1 0
py singular.h5 <<'PY'
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    s, m = f["status"][()], f["message"][()]
    # Recoverable (+1) at every trial state, so CVODES gives up at the first call.
    assert s[1] == -9 and b"CV_FIRST_RHSFUNC_ERR" in m[1] and b"mass matrix is not positive definite" in m[1], (s, m)
PY
# A sampled initial value where the constraint constrains nothing (d(q^2 - 1)/dq = 0 at q0 = 0):
# that sample fails with status -100 naming the constraint; the others run.
cat > degenerate.yaml <<'YAML'
kanesens: 1
scene:
  name: degenerate
  bodies: [{name: b, mass: 1, inertia: {shape: point}}]
  joints: [{name: j, type: prismatic, parent: ground, child: b, axis: [1, 0, 0], q0: 1}]
  constraints: [{name: g, type: general, position: "j.q^2 - 1"}]
time: {end: 1, outputs: 3}
sampling: {method: grid, levels: 3}
vary:
  j.q0: {dist: uniform, low: -1.5, high: 1.5}
YAML
run degenerate.yaml -o degenerate.h5 >/dev/null
py degenerate.h5 <<'PY'
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    s, m = f["status"][()], f["message"][()]
    assert list(s) == [1, -100, 1] and b"constraint 'g' constrains nothing" in m[1], (s, m)
PY
# F/(t - 0.5)^2: CVODES's error test fails again and again near t = 0.5; every sample fails.
sed 's/m: {dist: lognormal, mu: 705, sigma: 10}/F: {dist: uniform, low: 0.5, high: 2}/' faults.yaml > blowup.yaml
set +e; run blowup.yaml -o blowup.h5 >/dev/null 2>&1; rc=$?; set -e
[[ $rc -eq 5 ]] || { echo "FAIL: blow-up run exit $rc, expected 5"; exit 1; }
py blowup.h5 <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    s, m, etf = f["status"][()], f["message"][()], f["solver_stats/error_test_fails"][()]
    assert np.all(s < 0) and np.all(etf > 100), (s, etf)
    assert all(b"at t = 0.5" in x or b"at t = 0.4" in x for x in m), m
PY
echo "per-sample faults: ok"

# ---- 2. SIGTERM / SIGINT ----------------------------------------------------------------------
cat > long.yaml <<YAML
kanesens: 1
scene: $configs/double_pendulum.yaml
time: {end: 20.0, outputs: 41}
solver: {rtol: 1.0e-10, atol: 1.0e-12}
sampling: {method: lhs, samples: 400, seed: 11}
vary:
  m2: {dist: uniform, low: 0.8, high: 1.2}
  elbow.q0: {dist: normal, mean: 0.2, std: 0.1}
sensitivities: [m2, L1]
YAML
run long.yaml -o reference.h5 --chunk 1 >/dev/null

# wait_for FILE: until it exists (the run created it), at most 60 s.
wait_for() { for _ in $(seq 600); do [[ -e $1 ]] && return 0; sleep 0.1; done; echo "FAIL: $1 never appeared"; exit 1; }
interrupted_ok() {  # FILE: readable, some samples complete and intact, some not run, nothing failed
  py "$1" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    s = f["status"][()]
    done, notrun = int(np.sum(s == 1)), int(np.sum(s == 0))
    assert done > 0 and notrun > 0 and done + notrun == len(s), (done, notrun)
    assert np.all(np.isfinite(f["states"][np.flatnonzero(s == 1)]))
    print(f"interrupted file: {done} complete, {notrun} not run")
PY
}

mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run long.yaml -o term.h5 --chunk 1 >/dev/null 2>term.err &
pid=$!  # mpirun itself: it forwards the SIGTERM to both ranks
wait_for term.h5; sleep 1
kill -TERM $pid
set +e; wait $pid; rc=$?; set -e
cat term.err
[[ $rc -ne 0 ]] || { echo "FAIL: interrupted mpirun exited 0"; exit 1; }
grep -q "^kanesens: interrupted by SIGTERM: .* kanesens run long.yaml -o term.h5 --resume" term.err
[[ ! -e term.h5.partial ]]
interrupted_ok term.h5
run long.yaml -o term.h5 --resume >/dev/null
check status term.h5 400 0 0
check same reference.h5 term.h5

"$KANESENS" run long.yaml -o int.h5 --chunk 1 --json >int.json 2>int.err &
pid=$!
wait_for int.h5; sleep 1
kill -INT $pid
set +e; wait $pid; rc=$?; set -e
[[ $rc -eq 130 ]] || { echo "FAIL: SIGINT exit code $rc, expected 130"; cat int.err; exit 1; }
grep -q "interrupted by SIGINT" int.err
interrupted_ok int.h5
# The summary of a stopped run: the rate counts the samples finished, not those it set out to run.
py int.json <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["attempted"] == 400 and 0 < s["ok"] + s["failed"] < 400, s
rate = (s["ok"] + s["failed"]) / s["wall_seconds"]
assert abs(s["samples_per_second"] - rate) <= 1e-4 * rate, s
PY
"$KANESENS" run long.yaml -o int.h5 --resume >/dev/null
check same reference.h5 int.h5
echo "signals: ok"

# ---- 3. full disk -------------------------------------------------------------------------------
mkdir -p "$mnt"
if ! mount -t tmpfs -o size=1m tmpfs "$mnt" 2>/dev/null; then
  echo "test_runtime_faults: ok (full-disk checks skipped: cannot mount a tmpfs here)"; exit 0
fi
# (a) the pre-check: 400 samples need ~2.5 MiB with metadata (~1.6 MiB of rows), the tmpfs has 1.
set +e; run long.yaml -o "$mnt/a.h5" >/dev/null 2>a.err; rc=$?; set -e
[[ $rc -eq 2 ]] && grep -q "sampling.samples: the output would need about .* but the file system of '$mnt' has" a.err \
  || { echo "FAIL: pre-check (exit $rc)"; cat a.err; exit 1; }
[[ -z $(ls -A "$mnt") ]]
# (b) HDF5 itself runs out of space: clear error naming the file, no file left behind.
set +e
KANESENS_FAULT_IGNORE_FREE_SPACE=1 mpirun -x KANESENS_FAULT_IGNORE_FREE_SPACE --allow-run-as-root --oversubscribe \
  -np 2 "$KANESENS" run long.yaml -o "$mnt/b.h5" >/dev/null 2>b.err
rc=$?; set -e
grep "^kanesens" b.err
[[ $rc -ne 0 ]] && grep -q "creating '$mnt/b.h5' failed: the disk is full" b.err \
  || { echo "FAIL: ENOSPC not reported (exit $rc)"; cat b.err; exit 1; }
[[ -z $(ls -A "$mnt") ]] || { echo "FAIL: left files on the full disk:"; ls -la "$mnt"; exit 1; }
# (c) space freed (grown to 8 MiB): the run is started again; stopped mid-way; the disk then
#     fills up completely; --resume still completes it (rows were allocated at creation).
mount -o remount,size=8m "$mnt"
mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run long.yaml -o "$mnt/c.h5" --chunk 1 >/dev/null 2>c.err &
pid=$!
wait_for "$mnt/c.h5"; sleep 1
dd if=/dev/zero of="$mnt/filler" bs=64k 2>/dev/null || true   # until ENOSPC
kill -TERM $pid
set +e; wait $pid; set -e
df -h "$mnt" | tail -1
interrupted_ok "$mnt/c.h5"
run long.yaml -o "$mnt/c.h5" --resume >/dev/null
check same reference.h5 "$mnt/c.h5"
echo "test_runtime_faults: ok"
