#!/usr/bin/env bash
# Failures stay local: samples with a non-physical sampled mass get status -100 and a message,
# samples whose integration fails get the CVODES flag; the run goes on and exits 0 unless every
# sample failed. Bad input is one clear line naming file:line:column and key, with no output.
set -euo pipefail
: "${KANESENS:?path to the kanesens executable}"
source "$(dirname "$0")/common.sh"
run() { mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run "$@"; }
check() { "$KANESENS_PYTHON" "$here/check_ensemble.py" "$@"; }

# Masses drawn from [-0.5, 1.5]: a quarter are <= 0.
cat > "$work/bad_mass.yaml" <<YAML
kanesens: 1
scene: $here/../../configs/double_pendulum.yaml
time: {end: 0.5, outputs: 6}
sampling: {method: grid, levels: 9}
vary:
  m2: {dist: uniform, low: -0.5, high: 1.5}
YAML
run "$work/bad_mass.yaml" -o "$work/bad_mass.h5"
check status "$work/bad_mass.h5" 7 2 0
"$KANESENS_PYTHON" - "$work/bad_mass.h5" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    s, m = f["status"][()], f["message"][()]
    bad = np.flatnonzero(s < 0)
    assert np.all(s[bad] == -100), s
    assert b"mass must be > 0" in m[bad[0]], m[bad[0]]
PY

# Every sample fails (max_steps too small): exit code 5, statuses are CVODES's too-much-work.
if run "$work/bad_mass.yaml" -o "$work/all_fail.h5" --set solver.max_steps=3 --set sampling.levels=3 --set time.end=5; then
  echo "FAIL: expected a non-zero exit when every sample fails"; exit 1
else
  rc=$?; [[ $rc -eq 5 ]] || { echo "FAIL: exit code $rc, expected 5"; exit 1; }
fi
"$KANESENS_PYTHON" - "$work/all_fail.h5" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    s, m = f["status"][()], f["message"][()]
    assert np.all(s < 0), s
    assert any(b"TOO_MUCH_WORK" in x for x in m), m
PY

# Bad input: one line with file:line:column and the key, exit 2, no output file.
sed 's/low: -0.5/lwo: -0.5/' "$work/bad_mass.yaml" > "$work/typo.yaml"
if run "$work/typo.yaml" -o "$work/typo.h5" 2>"$work/err.txt"; then echo "FAIL: accepted a typo"; exit 1; fi
cat "$work/err.txt"
grep -q "typo.yaml:6:.*vary.m2.lwo.*did you mean 'low'" "$work/err.txt"
[[ $(grep -c "^kanesens:" "$work/err.txt") -eq 1 ]]  # one line from kanesens (mpirun adds its own)
[[ ! -e "$work/typo.h5" ]]
echo "test_ensemble_failures: ok"
