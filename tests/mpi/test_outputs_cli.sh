#!/usr/bin/env bash
# The study's `outputs:` at the command line. Bad outputs (the full table is
# tests/unit/test_outputs_bad_input.cpp): `simulate` and `run` (2 ranks) exit 2 with one
# "kanesens:" line naming file:line:column and the key, print nothing on stdout and create no
# output file. Good outputs: `simulate` prints them in its JSON (check_outputs_json.py).
set -uo pipefail
: "${KANESENS:?path to the kanesens executable}"
source "$(dirname "$0")/common.sh"
cd "$work"
failures=0 cases=0

# expect_bad NAME PATTERN STUDY: both commands exit 2 with one matching line and write nothing.
expect_bad() {
  local name=$1 pattern=$2 study=$3
  for cmd in simulate run; do
    cases=$((cases + 1))
    if [[ $cmd == run ]]; then
      mpirun --allow-run-as-root --oversubscribe -np 2 "$KANESENS" run "$study" -o out.h5 >out.txt 2>err.txt
    else
      "$KANESENS" simulate "$study" >out.txt 2>err.txt
    fi
    local rc=$? ok=1
    [[ $rc -eq 2 ]] || { echo "FAIL $name/$cmd: exit code $rc, expected 2"; ok=0; }
    [[ $(grep -c "^kanesens:" err.txt) -eq 1 ]] || { echo "FAIL $name/$cmd: not one kanesens line"; ok=0; }
    grep -q -- "$pattern" err.txt || { echo "FAIL $name/$cmd: stderr does not match '$pattern'"; ok=0; }
    [[ -s out.txt && $cmd == simulate ]] && { echo "FAIL $name/$cmd: printed on stdout"; ok=0; }
    [[ -e out.h5 || -e out.h5.partial ]] && { echo "FAIL $name/$cmd: left out.h5"; ok=0; rm -f out.h5 out.h5.partial; }
    if [[ $ok -eq 1 ]]; then echo "ok   $name/$cmd: $(grep '^kanesens:' err.txt)"; else sed 's/^/     | /' err.txt; failures=$((failures + 1)); fi
  done
}

study() {  # study NAME OUTPUT-LINES...: a small study with these outputs
  local name=$1; shift
  { printf 'kanesens: 1\nscene: %s/double_pendulum.yaml\ntime: {end: 0.4, outputs: 5}\n' "$configs"
    printf 'sampling: {method: mc, samples: 2, seed: 1}\nsensitivities: [m2, shoulder.q0]\noutputs:\n'
    printf '  %s\n' "$@"; } > "$name.yaml"
}

study unknown_body 'tip: {type: position, body: rod3, point: [0, "-L2/2", 0]}'
expect_bad unknown-body "unknown_body.yaml:7:31: outputs.tip.body: unknown body 'rod3' (did you mean 'rod1'?)" unknown_body.yaml
study unknown_joint 'load: {type: joint_load, joint: elbw}'
expect_bad unknown-joint "unknown_joint.yaml:7:35: outputs.load.joint: unknown joint 'elbw' (did you mean 'elbow'?)" unknown_joint.yaml
study unknown_constraint 'pin: {type: constraint_force, constraint: pin}'
expect_bad unknown-constraint "unknown_constraint.yaml:7:45: outputs.pin.constraint: unknown constraint 'pin'" unknown_constraint.yaml
study unknown_force 's: {type: force_element, force: s1}'
expect_bad unknown-force "unknown_force.yaml:7:35: outputs.s.force: unknown force 's1'" unknown_force.yaml
study vector 'tip: {type: position, body: rod2}' 'reach: {expression: "sqrt(tip^2)"}'
expect_bad vector-without-component "vector.yaml:8:23: outputs.reach.expression: 'tip' is a vector output" vector.yaml
study cycle 'a: {expression: "b + t"}' 'b: {expression: "2*a"}'
expect_bad cycle "cycle.yaml:7:3: outputs.a.expression: outputs depend on each other in a cycle: a -> b -> a" cycle.yaml
study at_outside 'late: {of: elbow.q, at: 0.5}'
expect_bad at-outside "at_outside.yaml:7:27: outputs.late.at: t = 0.5 is outside the study's time span \[0, 0.4\]" at_outside.yaml
study reduce_vector 'w: {type: angular_velocity, body: rod2}' 'r: {of: w, reduce: rms}'
expect_bad reduce-of-a-vector "reduce_vector.yaml:8:11: outputs.r.of: 'w' is a vector output" reduce_vector.yaml

# Good outputs: simulate's JSON has every output with its sensitivities.
study good 'tip: {type: position, body: rod2, point: [0, "-L2/2", 0]}' 'tip_y_end: {of: tip.y, at: end}' \
  'work: {of: "tip.x*elbow.u", reduce: integral}'
if "$KANESENS" simulate good.yaml > good.json 2>err.txt; then
  "$KANESENS_PYTHON" "$here/check_outputs_json.py" good.json || failures=$((failures + 1))
else
  echo "FAIL: the good study did not run"; cat err.txt; failures=$((failures + 1))
fi

echo "test_outputs_cli: $cases bad command lines, $failures failed"
[[ $failures -eq 0 ]]
