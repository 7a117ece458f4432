#!/usr/bin/env bash
# Bad input at the command line (the table of bad YAML is tests/unit/test_bad_input.cpp): every
# case exits 2 with exactly one "kanesens:" line on stderr naming where and what, no abort,
# segfault or stack trace, and leaves no output file that looks complete (an existing output is
# left untouched). `run` is checked under mpirun with 2 ranks.
set -uo pipefail
: "${KANESENS:?path to the kanesens executable}"
: "${KANESENS_PYTHON:=/usr/bin/python3}"
here=$(cd "$(dirname "$0")" && pwd)
configs=$(cd "$here/../../configs" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
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

echo "test_bad_input_cli: $cases bad command lines, $failures failed"
[[ $failures -eq 0 ]]
