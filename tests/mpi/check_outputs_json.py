"""Checks `kanesens simulate` JSON of tests/mpi/test_outputs_cli.sh's good study: series outputs
are [T] lists with [T][S] sensitivities, scalar outputs numbers with [S] sensitivities, and an
`at: end` value equals the series' last value."""
import json
import sys

d = json.load(open(sys.argv[1]))
T, S = len(d["time"]), len(d["sensitivity_names"])
out, sens = d["outputs"], d["output_sensitivities"]
assert {"energy", "tip.x", "tip.y", "tip.z", "tip_y_end", "work"} <= set(out), sorted(out)
for name in ("tip.x", "tip.y", "tip.z"):
    assert len(out[name]) == T and len(sens[name]) == T and all(len(r) == S for r in sens[name]), name
for name in ("tip_y_end", "work"):
    assert isinstance(out[name], float) and len(sens[name]) == S, name
assert out["tip_y_end"] == out["tip.y"][-1]
assert sens["tip_y_end"] == sens["tip.y"][-1]
assert "energy" not in sens
print(f"simulate JSON: {len(out)} outputs, T = {T}, S = {S}: ok")
