"""`kanesens simulate --repeat N` integrates the nominal sample N times in one process, as a
rank integrates sample after sample, and prints the last trajectory: it must be the very one a
single solve prints (states, sensitivities, multipliers, counters), for CVODES and DOP853, on a
constrained scene with projection and sensitivities (the four-bar study), with each repeat's
wall time listed. A count below 1 is a clear error."""
import json
import os
import subprocess

import pytest

ROOT = os.environ.get("KANESENS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
STUDY = os.path.join(ROOT, "configs", "four_bar_study.yaml")


def simulate(*args):
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable)")
    return subprocess.run([exe, "simulate", STUDY, "--set", "time.end=0.5", "--set", "time.outputs=11", *args],
                          capture_output=True, text=True)


@pytest.mark.parametrize("method", ["bdf", "dop853"])
def test_repeats_print_the_single_solve(method):
    once = simulate("--set", f"solver.method={method}")
    thrice = simulate("--set", f"solver.method={method}", "--repeat", "3")
    assert once.returncode == 0 and thrice.returncode == 0, once.stderr + thrice.stderr
    a, b = json.loads(once.stdout), json.loads(thrice.stdout)
    for key in ("states", "sensitivities", "multipliers", "multiplier_sensitivities", "outputs"):
        assert a[key] == b[key], key
    assert a["sensitivities"] and a["multipliers"]
    walls = b["stats"].pop("wall_seconds_repeats")
    assert len(walls) == 3 and all(w > 0 for w in walls)
    assert b["stats"]["wall_seconds"] == walls[-1]
    assert "wall_seconds_repeats" not in a["stats"]
    for s in (a["stats"], b["stats"]):
        s.pop("wall_seconds")
    assert a["stats"] == b["stats"]


def test_repeat_below_one_is_an_error():
    p = simulate("--repeat", "0")
    assert p.returncode == 2 and p.stdout == ""
    assert "--repeat" in p.stderr and "at least 1" in p.stderr
