#!/usr/bin/python3
"""DOP853 with 251 output times on the 4-link chain (configs/nlink_chain_4.yaml, 10 s, with the
sensitivities to m and L): `kanesens simulate` of a build that cuts its steps to land on every
output time ("before") against one that interpolates them with the continuous extension
("after"), at several tolerances, runs interleaved. Wall time: median of R runs of the
integration (stats.wall_seconds) and of the whole command; accuracy: the largest error of the
states and of the sensitivities at the output times against a reference run at rtol 1e-13
(the "before" build, which lands on every output time).

    /usr/bin/python3 bench/dop853_dense_output.py BEFORE_EXE AFTER_EXE [--repeat R] [--out JSON] [--floor] [--tolerances 1e-6,1e-8,...]

--floor adds the AFTER build with 2 output times ("floor"): the same steps without the dense
output's three extra evaluations, the least time any interpolation could cost. --also LABEL=EXE
(repeatable) adds further builds, run interleaved with the others.

At equal accuracy: for each "before" row, every other build's time at the same largest state
error, interpolated on its own work-precision line (log time against log error, between its two
nearest tolerances).

Writes the raw figures to bench/results/dop853_dense_output.json and prints a markdown table.
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import common as c

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
TOLERANCES = [1e-6, 1e-8, 1e-10]


def study(rtol: float, outputs: int = 251) -> str:
    return (f"kanesens: 1\nscene: {ROOT / 'configs' / 'nlink_chain_4.yaml'}\n"
            f"time: {{end: 10.0, outputs: {outputs}}}\n"
            f"solver: {{method: dop853, rtol: {rtol:.1e}, atol: {rtol * 1e-2:.1e}}}\n"
            "sensitivities: [m, L]\n")


def simulate(exe: str, path: Path) -> tuple[dict, float]:
    t0 = time.perf_counter()
    out = subprocess.run([exe, "simulate", str(path)], check=True, capture_output=True, text=True).stdout
    return json.loads(out), time.perf_counter() - t0


def max_error(run: dict, ref: dict, key: str) -> float:
    return c.max_err(c.flatten(run[key]), c.flatten(ref[key]))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--out", default=str(HERE / "results" / "dop853_dense_output.json"))
    ap.add_argument("--floor", action="store_true")
    ap.add_argument("--also", action="append", default=[], metavar="LABEL=EXE")
    ap.add_argument("--tolerances", default=",".join(f"{t:.0e}" for t in TOLERANCES),
                    help="comma-separated rtol values (default: %(default)s)")
    a = ap.parse_args()
    tolerances = [float(t) for t in a.tolerances.split(",")]
    builds = {"before": a.before, "after": a.after}
    if a.floor:
        builds["floor"] = a.after
    for spec in a.also:
        label, _, exe = spec.partition("=")
        if not exe or label in builds:
            ap.error(f"--also {spec}: expected a new LABEL=EXE")
        builds[label] = exe
    rows = []
    with tempfile.TemporaryDirectory() as d:
        ref_path = Path(d) / "reference.yaml"
        ref_path.write_text(study(1e-13))
        ref, _ = simulate(a.before, ref_path)
        files = {}
        for rtol in tolerances:
            for b in builds:
                p = Path(d) / f"rtol_{rtol:.0e}_{b}.yaml"
                p.write_text(study(rtol, 2 if b == "floor" else 251))
                files[(b, rtol)] = p
        integ = {(b, r): [] for b in builds for r in tolerances}
        whole = {(b, r): [] for b in builds for r in tolerances}
        last = {}
        for _ in range(a.repeat):
            for rtol in tolerances:
                for b, exe in builds.items():
                    out, w = simulate(exe, files[(b, rtol)])
                    integ[(b, rtol)].append(out["stats"]["wall_seconds"])
                    whole[(b, rtol)].append(w)
                    last[(b, rtol)] = out
        for rtol in tolerances:
            for b in builds:
                out = last[(b, rtol)]
                rows.append({
                    "build": b, "rtol": rtol, "status": out["status"],
                    "steps": out["stats"]["steps"], "rhs_evals": out["stats"]["rhs_evals"],
                    "error_test_fails": out["stats"]["error_test_fails"],
                    "integration_seconds_median": statistics.median(integ[(b, rtol)]),
                    "command_seconds_median": statistics.median(whole[(b, rtol)]),
                    "integration_seconds": integ[(b, rtol)],
                    "max_state_error": None if b == "floor" else max_error(out, ref, "states"),
                    "max_sensitivity_error": None if b == "floor" else max_error(out, ref, "sensitivities"),
                })
    result = {
        "command": " ".join(["bench/dop853_dense_output.py", a.before, a.after, "--repeat", str(a.repeat)]
                            + (["--floor"] if a.floor else []) + [f"--also {x}" for x in a.also]
                            + ([f"--tolerances {a.tolerances}"] if tolerances != TOLERANCES else [])),
        "revision": c.git_revision(), "cpu": c.cpu_model(), "nproc": c.nproc(), "loadavg": c.loadavg(),
        "study": "configs/nlink_chain_4.yaml, 10 s, 251 output times, dop853, atol = 1e-2 rtol, "
                 "sensitivities to m and L; reference: the before build at rtol 1e-13",
        "rows": rows,
    }
    Path(a.out).write_text(json.dumps(result, indent=2) + "\n")
    print("| rtol | build | steps | rhs evals | integration s (median) | ratio to before | max state error | max sensitivity error |")
    print("|---|---|---|---|---|---|---|---|")
    for rtol in tolerances:
        b = next(r for r in rows if r["rtol"] == rtol and r["build"] == "before")
        for r in (r for r in rows if r["rtol"] == rtol):
            ratio = r["integration_seconds_median"] / b["integration_seconds_median"]
            err = (lambda e: "—" if e is None else f"{e:.1e}")
            print(f"| {rtol:.0e} | {r['build']} | {r['steps']} | {r['rhs_evals']} | {r['integration_seconds_median']:.4f} | "
                  f"{ratio:.2f} | {err(r['max_state_error'])} | {err(r['max_sensitivity_error'])} |")
    others = [b for b in builds if b not in ("before", "floor")]
    print()
    print("| before's rtol | before's state error | " + " | ".join(f"{b}: time ratio at that error" for b in others) + " |")
    print("|---|---|" + "---|" * len(others))
    for rtol in tolerances:
        b = next(r for r in rows if r["rtol"] == rtol and r["build"] == "before")
        cells = []
        for o in others:
            t = time_at_error(rows, o, b["max_state_error"])
            cells.append("—" if t is None else f"{t / b['integration_seconds_median']:.2f}")
        print(f"| {rtol:.0e} | {b['max_state_error']:.1e} | " + " | ".join(cells) + " |")
    return 0


def time_at_error(rows: list, build: str, error: float) -> float | None:
    """The build's median time at this largest state error, on the line through its two
    tolerances nearest in error (log time against log error); None outside its range by more
    than a factor 10 in error."""
    pts = sorted((r["max_state_error"], r["integration_seconds_median"]) for r in rows
                 if r["build"] == build and r["max_state_error"])
    if len(pts) < 2 or not (pts[0][0] / 10 <= error <= pts[-1][0] * 10):
        return None
    k = min(max(next((i for i, p in enumerate(pts) if p[0] >= error), len(pts) - 1), 1), len(pts) - 1)
    (e0, t0), (e1, t1) = pts[k - 1], pts[k]
    x = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
    return math.exp(math.log(t0) + x * (math.log(t1) - math.log(t0)))


if __name__ == "__main__":
    raise SystemExit(main())
