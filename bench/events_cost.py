#!/usr/bin/python3
"""Cost of locating one event on the 4-link chain (configs/nlink_chain_4.yaml, 10 s, 251 output
times, sensitivities to m and L): `kanesens simulate` with no event and with one event function
(zero crossings of the first joint angle, direction both), under bdf and dop853, runs
interleaved. Wall time: median of R runs of the integration (stats.wall_seconds); the ratio
with/without from the same run.

    /usr/bin/python3 bench/events_cost.py [BUILD_DIR] [--repeat R] [--out JSON]

Writes the raw figures to bench/results/events_cost.json and prints a markdown table.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import tempfile
from pathlib import Path

import common as c

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
METHODS = ["bdf", "dop853"]
EVENT = "events:\n  - {name: zero, when: j1.q, direction: both}\n"


def study(method: str, events: str) -> str:
    return (f"kanesens: 1\nscene: {ROOT / 'configs' / 'nlink_chain_4.yaml'}\n"
            "time: {end: 10.0, outputs: 251}\n"
            f"solver: {{method: {method}, rtol: 1.0e-8, atol: 1.0e-10}}\n"
            "sensitivities: [m, L]\n" + events)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", nargs="?", default=str(ROOT / "build"))
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--out", default=str(HERE / "results" / "events_cost.json"))
    a = ap.parse_args()
    exe = str(c.kanesens_exe(a.build))
    variants = [(m, e) for m in METHODS for e in ("none", "one event")]
    times = {v: [] for v in variants}
    last = {}
    with tempfile.TemporaryDirectory() as d:
        files = {}
        for m, e in variants:
            p = Path(d) / f"{m}_{e.replace(' ', '_')}.yaml"
            p.write_text(study(m, EVENT if e != "none" else ""))
            files[(m, e)] = p
        for _ in range(a.repeat):
            for v, p in files.items():
                out = json.loads(subprocess.run([exe, "simulate", str(p)], check=True, capture_output=True, text=True).stdout)
                times[v].append(out["stats"]["wall_seconds"])
                last[v] = out
    rows = []
    for m, e in variants:
        out = last[(m, e)]
        base = statistics.median(times[(m, "none")])
        rows.append({"method": m, "events": e, "status": out["status"], "steps": out["stats"]["steps"],
                     "rhs_evals": out["stats"]["rhs_evals"],
                     "zero.count": out["outputs"].get("zero.count"), "zero.time": out["outputs"].get("zero.time"),
                     "integration_seconds_median": statistics.median(times[(m, e)]),
                     "ratio": statistics.median(times[(m, e)]) / base, "integration_seconds": times[(m, e)]})
    result = {"command": " ".join(["bench/events_cost.py", a.build, "--repeat", str(a.repeat)]),
              "revision": c.git_revision(), "cpu": c.cpu_model(), "nproc": c.nproc(), "loadavg": c.loadavg(),
              "study": "configs/nlink_chain_4.yaml, 10 s, 251 output times, rtol 1e-8, sensitivities to m and L; "
                       "event: j1.q crossing zero, both directions", "rows": rows}
    Path(a.out).write_text(json.dumps(result, indent=2) + "\n")
    print("| method | events | steps | rhs evals | count | integration s (median) | ratio |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['method']} | {r['events']} | {r['steps']} | {r['rhs_evals']} | {r['zero.count']} | "
              f"{r['integration_seconds_median']:.4f} | {r['ratio']:.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
