#!/usr/bin/python3
"""DOP853's step-size control, two builds compared by work at equal accuracy: right-hand-side
evaluations (stats.rhs_evals: a count, free of timing noise) against the largest state error at
the output times, on the scenes of bench/sensitivity_cost.py, plain and with sensitivities,
at rtol 1e-5 .. 1e-11 (atol = rtol/100).

    /usr/bin/python3 bench/dop853_step_control.py OUT.json BEFORE=EXE AFTER=EXE
    /usr/bin/python3 bench/dop853_step_control.py --table OUT.json

The reference of each case is the BEFORE build at rtol 1e-13, atol 1e-15. "Evaluations at equal
accuracy" is the geometric mean, over the BEFORE points whose error the AFTER build's line
spans, of AFTER's evaluations at that error (log-log interpolation between its two nearest
tolerances) divided by BEFORE's.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile

import common as c
from sensitivity_cost import GENERATED, ROOT, SCENES

TOLERANCES = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11]
# name: (scene of sensitivity_cost.py, sensitivities, output count, end time); None keeps the scene's
CASES = {
    "chain4_planar, 251 outputs, 2 sens": ("chain4_planar", "m,L", 251, 10.0),
    "chain4_planar": ("chain4_planar", "", 101, 10.0),
    "chain16_planar": ("chain16_planar", "", None, None),
    "arm_3d": ("arm_3d", "", None, None),
    "arm_3d, 6 sens": ("arm_3d", SCENES["arm_3d"][1], None, None),
    "chain8_spatial": ("chain8_spatial", "", None, 5.0),
    "chain8_spatial, 6 sens": ("chain8_spatial", SCENES["chain8_spatial"][1], None, 5.0),
    "rolling_disc": ("rolling_disc", "", None, None),
    "rolling_disc, 6 sens": ("rolling_disc", SCENES["rolling_disc"][1], None, None),
    "four_bar_multipliers": ("four_bar_multipliers", "", None, None),
    "four_bar_multipliers, 6 sens": ("four_bar_multipliers", SCENES["four_bar_multipliers"][1], None, None),
    "four_bar_embedding": ("four_bar_embedding", "", None, None),
    "andrews": ("andrews", "", None, None),
}


def run(exe: str, study: str, rtol: float, sens: str) -> dict:
    args = [exe, "simulate", study, "--set", "solver.method=dop853", "--set", f"solver.rtol={rtol:.1e}",
            "--set", f"solver.atol={rtol * 1e-2:.1e}", "--sens", sens or "none"]
    d = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    if d["status"] != 1:
        raise RuntimeError(f"{' '.join(args)}: {d['message']}")
    return d


def at_equal_accuracy(before: list[dict], after: list[dict]) -> tuple[float, int]:
    line = [(p["rtol"], p["error"], p["rhs_evals"]) for p in after]  # loose to tight
    logs = []
    for p in before:
        evals, how = c.time_at(line, p["error"])  # log-log between AFTER's neighbouring tolerances
        if how == "=":
            logs.append(math.log(evals / p["rhs_evals"]))
    return (math.exp(sum(logs) / len(logs)) if logs else float("nan")), len(logs)


def measure(out: str, exes: list[tuple[str, str]]) -> None:
    load_start = c.loadavg()
    result = {"command": "/usr/bin/python3 bench/dop853_step_control.py " + " ".join(sys.argv[1:]),
              "tolerances": TOLERANCES, "builds": [label for label, _ in exes], "cases": []}
    with tempfile.TemporaryDirectory() as tmp:
        for file, make in GENERATED.items():
            with open(os.path.join(tmp, file), "w") as f:
                f.write(make())
        for name, (scene, sens, outputs, end) in CASES.items():
            text = SCENES[scene][0].format(root=ROOT, tmp=tmp)
            if outputs:
                text = text.replace("outputs: 21", f"outputs: {outputs}")
            if end:
                text = text.replace("end: 2.0", f"end: {end}")
            study = os.path.join(tmp, "study.yaml")
            with open(study, "w") as f:
                f.write(text)
            reference = c.flatten(run(exes[0][1], study, 1e-13, sens)["states"])
            case = {"name": name, "sensitivities": sens, "study": text, "points": {}}
            for label, exe in exes:
                case["points"][label] = []
                for rtol in TOLERANCES:
                    d = run(exe, study, rtol, sens)
                    error = c.max_err(c.flatten(d["states"]), reference)
                    s = d["stats"]
                    case["points"][label].append({"rtol": rtol, "rhs_evals": s["rhs_evals"], "steps": s["steps"],
                                                  "rejected": s["error_test_fails"], "error": error})
            result["cases"].append(case)
            c.log("dop853_step_control", name)
    result["provenance"] = c.provenance(load_start)
    with open(out, "w") as f:
        json.dump(result, f, indent=1)


def table(path: str) -> None:
    r = c.load_json(path)
    before, after = r["builds"][0], r["builds"][1]
    print(f"DOP853 at rtol {r['tolerances'][0]:.0e} .. {r['tolerances'][-1]:.0e} (atol = rtol/100); rejected = "
          "rejected trial steps / all trial steps, summed over the tolerances; evaluations at equal accuracy = "
          f"{after}'s right-hand-side evaluations at {before}'s largest state error, as a ratio (geometric mean "
          "over the tolerances whose error both lines span).\n")
    print(f"| case | rejected, {before} | rejected, {after} | evaluations at equal accuracy, {after} / {before} |")
    print("|---|---:|---:|---:|")
    for case in r["cases"]:
        cells = []
        for label in (before, after):
            pts = case["points"][label]
            rejected = sum(p["rejected"] for p in pts)
            cells.append(f"{rejected} / {rejected + sum(p['steps'] for p in pts)}")
        ratio, n = at_equal_accuracy(case["points"][before], case["points"][after])
        print(f"| {case['name']} | {cells[0]} | {cells[1]} | {ratio:.2f} ({n} of {len(r['tolerances'])}) |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    c.table_or_usage(argv, table, __doc__)
    exes = [tuple(a.split("=", 1)) for a in argv[1:]]
    if len(exes) != 2 or any(len(e) != 2 for e in exes):
        sys.exit(__doc__)
    measure(argv[0], exes)
    table(argv[0])
