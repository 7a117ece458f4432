#!/usr/bin/env bash
# Bad input at the command line (the table of bad YAML is tests/unit/test_bad_input.cpp): every
# case exits 2 with exactly one "kanesens:" line on stderr naming where and what, no abort,
# segfault or stack trace, and leaves no output file that looks complete (an existing output is
# left untouched). `run` is checked under mpirun with 2 ranks.
set -uo pipefail
: "${KANESENS:?path to the kanesens executable}"
source "$(dirname "$0")/common.sh"
cd "$work"
failures=0 cases=0

# expect_bad NAME PATTERN OUTPUT COMMAND...: exit 2, one kanesens line matching PATTERN,
# no crash markers, OUTPUT (if not "-") absent afterwards.
expect_bad() {
  local name=$1 pattern=$2 output=$3; shift 3
  cases=$((cases + 1))
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$? ok=1
  [[ $rc -eq 2 ]] || { echo "FAIL $name: exit code $rc, expected 2"; ok=0; }
  local lines; lines=$(grep -c "^kanesens:" "$work/err.txt")
  [[ $lines -eq 1 ]] || { echo "FAIL $name: $lines kanesens lines on stderr, expected 1"; ok=0; }
  grep -q -- "$pattern" "$work/err.txt" || { echo "FAIL $name: stderr does not match '$pattern'"; ok=0; }
  if grep -qE "terminate called|Segmentation fault|Aborted \(core|core dumped|Process received signal|AddressSanitizer|runtime error:|MPI_ABORT" "$work/err.txt"; then
    echo "FAIL $name: crash marker on stderr"; ok=0
  fi
  if [[ $output != - && ( -e $output || -e $output.partial ) ]]; then echo "FAIL $name: left $output"; ok=0; fi
  if [[ $ok -eq 1 ]]; then echo "ok   $name: $(grep '^kanesens:' "$work/err.txt")"; else sed 's/^/     | /' "$work/err.txt"; failures=$((failures + 1)); fi
}
mpirun_run() { mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run "$@"; }

cat > study.yaml <<YAML
kanesens: 1
scene: $configs/double_pendulum.yaml
time: {end: 0.2, outputs: 5}
sampling: {method: lhs, samples: 6, seed: 3}
vary:
  m2: {dist: uniform, low: 0.8, high: 1.2}
sensitivities: [m2]
YAML
printf 'kanesens: 1\nscene: {name: x\n' > malformed.yaml
sed 's/samples: 6/smaples: 6/' study.yaml > typo.yaml
sed 's/low: 0.8, high: 1.2/low: 1.2, high: 0.8/' study.yaml > lowhigh.yaml
sed 's/samples: 6/samples: 0/' study.yaml > zero_samples.yaml
sed 's/samples: 6/samples: 1000000000/' study.yaml > huge.yaml
sed 's/mass: m2,/mass: "m2 - 1",/' "$configs/double_pendulum.yaml" > zero_mass_scene.yaml
sed 's|^    L2: 1.0|    L2: 1.0\n    k2: "1/(L1-1)"|' "$configs/double_pendulum.yaml" > divzero_scene.yaml
grep -q 'mass: m2,' "$configs/double_pendulum.yaml" || echo "note: double_pendulum.yaml changed; zero_mass_scene.yaml may be valid"

expect_bad check-malformed "malformed.yaml:3:1: malformed YAML" - "$KANESENS" check malformed.yaml
expect_bad check-missing-file "nope.yaml: cannot open file" - "$KANESENS" check nope.yaml
expect_bad check-zero-mass "zero_mass_scene.yaml:[0-9]*:[0-9]*: scene.bodies\[1\].mass: body 'rod2': mass must be > 0" - "$KANESENS" check zero_mass_scene.yaml
expect_bad check-division-by-zero "divzero_scene.yaml:[0-9]*:[0-9]*: scene.parameters.k2: value is not finite" - "$KANESENS" check divzero_scene.yaml
expect_bad bench-articulated-constrained "--rhs-algorithm: articulated_body needs a scene without constraints" - "$KANESENS" bench rhs "$configs/four_bar.yaml" --rhs-algorithm articulated_body --repeat 1
# A puck on a planar joint (three speeds) is evaluated with the planar path, whose recursion
# takes joints of one speed only.
cat > puck.yaml <<'YAML'
kanesens: 1
scene:
  name: puck
  gravity: [0, -9.81, 0]
  bodies:
    - {name: puck, mass: 1, inertia: {shape: cylinder, radius: 0.1, length: 0.05, axis: z}}
  joints:
    - {name: slide, type: planar, parent: ground, child: puck, axis: [0, 0, 1]}
YAML
expect_bad bench-articulated-planar "--rhs-algorithm: articulated_body needs a scene without constraints, and on the planar path joints of at most one speed" - "$KANESENS" bench rhs puck.yaml --rhs-algorithm articulated_body --repeat 1
expect_bad eom-wrong-q-count "--q: expected 2 coordinates" - "$KANESENS" eom "$configs/double_pendulum.yaml" --q=1 --u=0,0
expect_bad simulate-typo "typo.yaml:4:[0-9]*: sampling.smaples: unknown key" - "$KANESENS" simulate typo.yaml
expect_bad simulate-set-nan "--set m2: value must be finite" - "$KANESENS" simulate study.yaml --set m2=nan
expect_bad run-malformed "malformed.yaml:3:1: malformed YAML" out1.h5 mpirun_run malformed.yaml -o out1.h5
expect_bad run-unknown-key "typo.yaml:4:[0-9]*: sampling.smaples: unknown key 'smaples' (did you mean 'samples'?)" out2.h5 mpirun_run typo.yaml -o out2.h5
expect_bad run-low-ge-high "lowhigh.yaml:6:[0-9]*: vary.m2.high: uniform: expected low < high" out3.h5 mpirun_run lowhigh.yaml -o out3.h5
expect_bad run-zero-samples "zero_samples.yaml:4:[0-9]*: sampling.samples: expected an integer in \[1," out4.h5 mpirun_run zero_samples.yaml -o out4.h5
expect_bad run-too-big-for-disk "huge.yaml:4:[0-9]*: sampling.samples: the output would need about .* free" out5.h5 mpirun_run huge.yaml -o out5.h5
expect_bad run-set-unknown "--set m9: 'm9' is neither a parameter" out6.h5 mpirun_run study.yaml -o out6.h5 --set m9=1
expect_bad run-no-such-dir "-o: cannot write 'nodir/out.h5': directory 'nodir' does not exist" - mpirun_run study.yaml -o nodir/out.h5
mkdir adir
expect_bad run-output-is-dir "-o: 'adir' is a directory" - mpirun_run study.yaml -o adir
touch afile
expect_bad run-dir-is-file "-o: cannot write 'afile/out.h5': 'afile' is not a directory" - mpirun_run study.yaml -o afile/out.h5
mkdir ro && chmod 555 ro
if [[ $(id -u) -ne 0 ]]; then  # root writes anywhere; the check is for ordinary users
  expect_bad run-unwritable-dir "is not writable" ro/out.h5 mpirun_run study.yaml -o ro/out.h5
fi
expect_bad run-resume-missing "--resume: no file 'none.h5' to resume" none.h5 mpirun_run study.yaml -o none.h5 --resume
expect_bad run-resume-and-overwrite "--resume: --resume and --overwrite exclude each other" - mpirun_run study.yaml -o x.h5 --resume --overwrite

# An existing output: refused without --resume/--overwrite, untouched.
mpirun_run study.yaml -o done.h5 >/dev/null 2>&1 || { echo "FAIL: the good study did not run"; failures=$((failures + 1)); }
before=$(md5sum < done.h5)
expect_bad run-existing-output "-o: output file 'done.h5' already exists; pass --overwrite" - mpirun_run study.yaml -o done.h5
expect_bad run-resume-other-study "--resume: cannot resume 'done.h5': .*another study" - mpirun_run study.yaml -o done.h5 --resume --set m1=2
[[ "$before" == "$(md5sum < done.h5)" ]] || { echo "FAIL: done.h5 was modified"; failures=$((failures + 1)); }
echo "not hdf5" > text.h5
expect_bad run-resume-not-hdf5 "--resume: HDF5 call H5Fopen(text.h5) failed" - mpirun_run study.yaml -o text.h5 --resume

# ---- Command-line values: a usage error is bad input too (one line, exit 2, on rank 0 only) -----
expect_bad eom-t-nan "--t: expected a finite number, found 'nan'" - "$KANESENS" eom "$configs/double_pendulum.yaml" --q=0,0 --u=0,0 --t nan
expect_bad eom-t-inf "--t: expected a finite number, found 'inf'" - "$KANESENS" eom "$configs/double_pendulum.yaml" --q=0,0 --u=0,0 --t inf
expect_bad eom-t-not-a-number "--t: expected a finite number, found 'x'" - "$KANESENS" eom "$configs/double_pendulum.yaml" --q=0,0 --u=0,0 --t x
expect_bad check-unknown-option "The following argument was not expected: --frobnicate" - "$KANESENS" check study.yaml --frobnicate
expect_bad run-chunk-overflow "--chunk: expected a whole number from 1 to" out7.h5 mpirun_run study.yaml -o out7.h5 --chunk 9223372036854775807
expect_bad run-chunk-zero "--chunk: expected a whole number from 1 to" out7.h5 mpirun_run study.yaml -o out7.h5 --chunk 0
expect_bad run-samples-negative "--samples: expected a whole number ≥ 1, found '-5'" out7.h5 mpirun_run study.yaml -o out7.h5 --samples -5
expect_bad run-missing-study "study is required" - mpirun_run -o out7.h5
sed 's/^time:.*/time: {end: 0.2, outputs: 5}\nsolver: {max_order: 4294967297}/' study.yaml > max_order.yaml
expect_bad run-max-order-overflow "max_order.yaml:[0-9]*:[0-9]*: solver.max_order: expected a whole number from 0 to 12, found 4294967297" out7.h5 mpirun_run max_order.yaml -o out7.h5

# ---- Input files are bounded text -----------------------------------------------------------
expect_bad check-dev-zero "/dev/zero: file is larger than 16 MiB" - "$KANESENS" check /dev/zero
sed "s|^scene: .*|scene: /dev/zero|" study.yaml > devzero_study.yaml
expect_bad run-scene-dev-zero "/dev/zero: file is larger than 16 MiB" out7.h5 mpirun_run devzero_study.yaml -o out7.h5
expect_bad check-directory "adir: is a directory" - "$KANESENS" check adir
printf 'kanesens: 1\nscene:\n  name: "ab\xff"\n' > bad_utf8.yaml
expect_bad check-invalid-utf8 "bad_utf8.yaml:3:[0-9]*: invalid UTF-8 (byte 0xFF)" - "$KANESENS" check bad_utf8.yaml
printf 'kanesens: 1\nscene:\n  name: "a\x01b"\n' > control.yaml
expect_bad check-control-character "control.yaml:3:[0-9]*: control character 0x01" - "$KANESENS" check control.yaml
"$KANESENS_PYTHON" -c "import sys; sys.stdout.write(open('study.yaml').read().replace('sensitivities: [m2]', 'sensitivities: [' + 'm' * 250000 + ']'))" > long_name.yaml
expect_bad run-unknown-name-250000-chars "long_name.yaml:7:[0-9]*: sensitivities\[0\]: 'mmmm* \[... [0-9]* bytes ...\] mmmm*' is neither a parameter" out7.h5 mpirun_run long_name.yaml -o out7.h5

# ---- Memory: one sample's results must fit in every rank (KANESENS_FAULT_MEMORY_AVAILABLE
# stands in for a small node) --------------------------------------------------------------
expect_bad run-memory "study.yaml:3:[0-9]*: time: one sample's results .* need about .* of memory per rank (2 ranks on this node" out7.h5 env KANESENS_FAULT_MEMORY_AVAILABLE=10000 mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run study.yaml -o out7.h5
expect_bad simulate-memory "study.yaml:3:[0-9]*: time: the trajectory (5 times x 4 states x (1 + 1 sensitivities)) needs about" - env KANESENS_FAULT_MEMORY_AVAILABLE=100 "$KANESENS" simulate study.yaml

# ---- The output path is never followed or clobbered -------------------------------------------
echo precious > precious.txt
cp precious.txt precious.orig
ln -s precious.txt link.h5.partial
expect_bad run-partial-is-symlink "-o: 'link.h5.partial' exists" - mpirun_run study.yaml -o link.h5
cmp -s precious.txt precious.orig || { echo "FAIL: precious.txt changed through link.h5.partial"; failures=$((failures + 1)); }
# With --overwrite the stale link is removed (never written through) and the run succeeds.
if mpirun_run study.yaml -o link.h5 --overwrite >/dev/null 2>&1 && [[ -f link.h5 && ! -L link.h5.partial ]] \
   && cmp -s precious.txt precious.orig; then echo "ok   run-partial-symlink-overwrite: target byte-identical"
else echo "FAIL run-partial-symlink-overwrite"; failures=$((failures + 1)); fi
cases=$((cases + 1))
ln -s precious.txt outlink.h5
expect_bad run-output-is-symlink "-o: output file 'outlink.h5' already exists" - mpirun_run study.yaml -o outlink.h5
cmp -s precious.txt precious.orig || { echo "FAIL: precious.txt changed through outlink.h5"; failures=$((failures + 1)); }
echo "my own notes" > mine.h5.partial
expect_bad run-partial-exists "-o: 'mine.h5.partial' exists" - mpirun_run study.yaml -o mine.h5
[[ $(cat mine.h5.partial) == "my own notes" ]] || { echo "FAIL: mine.h5.partial was modified"; failures=$((failures + 1)); }
mkdir dir.h5.partial
expect_bad run-partial-is-directory "-o: 'dir.h5.partial' (the name the output is built under) is a directory" - mpirun_run study.yaml -o dir.h5 --overwrite
[[ -d dir.h5.partial && ! -e dir.h5 ]] || { echo "FAIL: dir.h5.partial"; failures=$((failures + 1)); }

# ---- A run file given to --resume is input: hostile edits of a real one are refused, the file
# is left byte-identical -----------------------------------------------------------------------
edit_run_file() {  # edit_run_file FILE PYTHON-STATEMENTS (h5py File as f)
  "$KANESENS_PYTHON" -c "import h5py, numpy as np
with h5py.File('$1', 'r+') as f:
    $2"
}
cp done.h5 long_status.h5
edit_run_file long_status.h5 "del f['status']; f['status'] = np.zeros(9, dtype='i4')"
cp done.h5 states_shape.h5
edit_run_file states_shape.h5 "del f['states']; f['states'] = np.zeros((6, 5, 3))"
cp done.h5 no_hash.h5
edit_run_file no_hash.h5 "del f.attrs['study_hash']"
cp done.h5 status_link.h5
edit_run_file status_link.h5 "del f['status']; f['status'] = h5py.SoftLink('/sample')"
for bad in "long_status:dataset /status has shape (9), this study writes (6)" \
           "states_shape:dataset /states has shape (6, 5, 3), this study writes (6, 5, 4)" \
           "no_hash:it has no study_hash attribute" \
           "status_link:/status is a soft or external link"; do
  name=${bad%%:*} says=${bad#*:}
  before=$(md5sum < "$name.h5")
  expect_bad "run-resume-$name" "--resume: cannot resume '$name.h5': $says" - mpirun_run study.yaml -o "$name.h5" --resume
  [[ "$before" == "$(md5sum < "$name.h5")" ]] || { echo "FAIL: $name.h5 was modified"; failures=$((failures + 1)); }
done

# ---- Found at validation, before any file, once (rank 0), instead of in every sample --------------
cat > degenerate.yaml <<'YAML'
kanesens: 1
scene:
  name: p
  bodies: [{name: b, mass: 1, inertia: {shape: point}}]
  joints: [{name: j, type: prismatic, parent: ground, child: b, axis: [1, 0, 0]}]
  constraints: [{name: g, type: general, position: "j.q^2"}]
time: {end: 1, outputs: 3}
sampling: {method: mc, samples: 4, seed: 1}
YAML
head -6 degenerate.yaml > degenerate_scene.yaml
expect_bad check-degenerate-constraint "degenerate_scene.yaml:6:17: scene.constraints\[0\]: constraint 'g' constrains nothing at the initial state" - "$KANESENS" check degenerate_scene.yaml
expect_bad simulate-degenerate-constraint "degenerate.yaml:6:17: scene.constraints\[0\]: constraint 'g' constrains nothing at the initial state" - "$KANESENS" simulate degenerate.yaml
expect_bad run-degenerate-constraint "degenerate.yaml:6:17: scene.constraints\[0\]: constraint 'g' constrains nothing" out8.h5 mpirun_run degenerate.yaml -o out8.h5
expect_bad run1-degenerate-constraint "degenerate.yaml:6:17: scene.constraints\[0\]: constraint 'g' constrains nothing" out8.h5 "$KANESENS" run degenerate.yaml -o out8.h5
sed 's/^time:.*/time: {end: 0.2, outputs: 5}\nsolver: {atol: [1e-8, 1e-8]}/' study.yaml > short_atol.yaml
expect_bad run-short-atol "short_atol.yaml:4:[0-9]*: solver.atol: expected one entry per state (4: shoulder.q, elbow.q, shoulder.u, elbow.u), found 2" out8.h5 mpirun_run short_atol.yaml -o out8.h5
sed 's/^time:.*/time: {end: 0.2, outputs: 5}\nsolver: {linear_solver: sparse}/' study.yaml > linear_solver.yaml
expect_bad run-linear-solver "linear_solver.yaml:4:[0-9]*: solver.linear_solver: expected one of dense, krylov, auto" out8.h5 mpirun_run linear_solver.yaml -o out8.h5
expect_bad simulate-linear-solver "linear_solver.yaml:4:[0-9]*: solver.linear_solver: expected one of dense, krylov, auto" - "$KANESENS" simulate linear_solver.yaml
sed 's/^sensitivities: \[m2\]/sensitivities: [m2, L1, m2]/' study.yaml > sens_twice.yaml
expect_bad run-sensitivity-twice "sens_twice.yaml:7:[0-9]*: sensitivities\[2\]: 'm2' is listed twice" out8.h5 mpirun_run sens_twice.yaml -o out8.h5
expect_bad simulate-sens-twice "--sens: 'm2' is listed twice" - "$KANESENS" simulate study.yaml --sens m2,m2
printf 'kanesens: 1\nscene: %s\ntime: {end: 1}\nsolver: {method: adams}\n' "$configs/four_bar.yaml" > adams.yaml
expect_bad simulate-adams-constrained "adams.yaml:4:18: solver.method: the scene has constraints and their default stabilization is projection" - "$KANESENS" simulate adams.yaml
expect_bad run-adams-constrained "adams.yaml:4:18: solver.method: the scene has constraints" out8.h5 mpirun_run adams.yaml -o out8.h5
sed 's/^time:.*/time: {start: 1e16, end: 1.000000000000002e16, outputs: 101}/' study.yaml > repeated_times.yaml
expect_bad run-repeated-times "repeated_times.yaml:3:7: time: the 101 output times .* are not distinct" out8.h5 mpirun_run repeated_times.yaml -o out8.h5
sed 's/mass: m1,/mass: 1e308,/; s/child_point: \[0, "L1\/2", 0\]/child_point: [0, 1e10, 0]/' "$configs/double_pendulum.yaml" > huge_scene.yaml
printf 'kanesens: 1\nscene: huge_scene.yaml\ntime: {end: 1}\n' > huge.yaml
expect_bad run-absurd-mass "huge_scene.yaml:[0-9]*:3: scene: at the initial state (t = 0) .* out of range" out8.h5 mpirun_run huge.yaml -o out8.h5
printf 'kanesens: 1\nscene:\n  name: w\n  bodies: [{name: b, mass: 1, inertia: {shape: point}}]\n  joints: [{name: j, type: weld, parent: ground, child: b}]\n' > welded.yaml
expect_bad check-no-degrees-of-freedom "welded.yaml:3:3: scene.joints: the scene has no degrees of freedom" - "$KANESENS" check welded.yaml
printf 'kanesens: 1\nscene:\n  name: u\n  bodies: [{name: b, mass: 1, inertia: {xx: 1, yy: 1, zz: 1}}]\n  joints: [{name: j, type: universal, parent: ground, child: b, axes: [[1, 0, 0], [2, 0, 0]]}]\n' > universal.yaml
expect_bad check-universal-parallel-axes "universal.yaml:5:[0-9]*: scene.joints\[0\].axes\[1\]: joint 'j': its two axes are parallel" - "$KANESENS" check universal.yaml
printf 'kanesens: 1\nscene:\n  name: c\n  bodies: [{name: b, mass: 1, inertia: {shape: point}}]\n  joints: [{name: j, type: prismatic, parent: ground, child: b, axis: [1, 0, 0]}]\n  constraints: [{type: coincident, body_a: b, body_b: ground, components: [x, y, z, x]}]\n' > components.yaml
expect_bad check-components-repeated "components.yaml:6:[0-9]*: scene.constraints\[0\].components: component 'x' is given twice" - "$KANESENS" check components.yaml

echo "test_bad_input_cli: $cases bad command lines, $failures failed"
[[ $failures -eq 0 ]]
