#!/usr/bin/python3
"""Embedding or multipliers, and the drift of rolling contacts: cost and accuracy measured on the
examples (docs/explanation/constraints.md, "Choosing a formulation" and "Rolling contacts").

    /usr/bin/python3 bench/constraints_choice.py [BUILD_DIR] [--repeat R] [--out JSON]

Runs `kanesens simulate` on studies written from configs/ (knife-edge vehicle, rolling disc,
crank-rocker four-bar, parallelogram four-bar, two-wheeled vehicle), each formulation, method and
stabilization; accuracy against the closed form (knife edge, rolling disc) or a reference run
(four-bars: DOP853 multipliers at rtol 1e-12); wall time the
median of R runs. Prints the markdown tables and writes the raw figures to
bench/constraints_choice.json (next to this script).
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import common as c

HERE = Path(__file__).resolve().parent


def simulate(exe: Path, study_text: str, repeat: int, sets=()) -> dict:
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=True) as f:
        f.write(study_text)
        f.flush()
        walls, out = [], None
        for _ in range(repeat):
            p = subprocess.run([str(exe), "simulate", f.name, *sum((["--set", s] for s in sets), [])],
                               capture_output=True, text=True)
            out = json.loads(p.stdout)
            walls.append(out["stats"]["wall_seconds"])
        out["wall_median"] = c.median(walls)
        return out


def study(scene: str, end: float, outputs: int, method: str, rtol: float, formulation: str, stab: str,
          record="[states, energy, constraint_residual]", sens="[]") -> str:
    return (f"kanesens: 1\nscene: {c.CONFIGS / scene}\ntime: {{end: {end}, outputs: {outputs}}}\n"
            f"solver: {{method: {method}, rtol: {rtol}, atol: {rtol * 1e-2}, constraints: "
            f"{{formulation: {formulation}, stabilization: {stab}}}}}\n"
            f"sensitivities: {sens}\nrecord: {record}\n")


def stabilizations(method: str, formulation: str) -> str:
    if method == "adams":
        return "none" if formulation == "embedding" else "baumgarte"
    return "projection"


def row(name: str, method: str, formulation: str, stab: str, r: dict, err: float) -> dict:
    e = r["outputs"]["energy"]
    drift = max(abs(x - e[0]) for x in e) / abs(e[0])
    pos = r["constraint_residuals"]["position"]
    return {"case": name, "method": method, "formulation": formulation, "stabilization": stab,
            "status": r["status"], "message": r["message"], "error": err, "energy_drift": drift,
            "position_residual": max(pos) if pos else 0.0, "steps": r["stats"]["steps"],
            "rhs_evals": r["stats"]["rhs_evals"], "repartitions": r["stats"]["repartitions"],
            "wall_median": r["wall_median"]}


def knife_edge(exe, repeat):
    rows = []
    v, w = 1.5, 2.0
    for method in ("bdf", "adams", "dop853"):
        for f in ("embedding", "multipliers"):
            stab = stabilizations(method, f)
            r = simulate(exe, study("knife_edge.yaml", 10.0, 101, method, 1e-10, f, stab, sens="[v, m]"), repeat)
            err = 0.0
            for k, y in enumerate(r["states"]):
                t = 0.1 * k
                err = max(err, abs(y[0] - v / w * math.sin(w * t)), abs(y[1] - v / w * (1 - math.cos(w * t))),
                          abs(y[2] - w * t))
            rows.append(row("knife edge, 3.2 turns, sensitivities [v, m]", method, f, stab, r, err))
    return rows


def lean(y):
    # Rolling disc (configs/rolling_disc.yaml): lean = asin(−(R e_y)·z), R from the quaternion.
    w, x, yy, z = y[3:7]
    n = math.sqrt(w * w + x * x + yy * yy + z * z)
    w, x, yy, z = w / n, x / n, yy / n, z / n
    return math.asin(-(2 * (yy * z + w * x)))


def rolling_disc(exe, repeat):
    rows = []
    for method in ("bdf", "dop853"):
        for f in ("embedding", "multipliers"):
            stab = "projection"
            r = simulate(exe, study("rolling_disc.yaml", 5.0, 51, method, 1e-10, f, stab), repeat)
            err = max(abs(lean(y) - 0.3) for y in r["states"])
            rows.append(row("rolling disc, steady turning 5 s (error: lean)", method, f, stab, r, err))
    return rows


def against_reference(exe, repeat, name, scene, end, outputs, sets=(), methods=("bdf", "dop853")):
    ref = simulate(exe, study(scene, end, outputs, "dop853", 1e-12, "multipliers", "projection"), 1, sets)
    rows = []
    for method in methods:
        for f in ("embedding", "multipliers"):
            stab = stabilizations(method, f)
            r = simulate(exe, study(scene, end, outputs, method, 1e-9, f, stab), repeat, sets)
            err = float("nan")
            if r["status"] == 1 and ref["status"] == 1:
                err = max(abs(a - b) for ya, yb in zip(r["states"], ref["states"]) for a, b in zip(ya, yb))
            rows.append(row(name, method, f, stab, r, err))
    return rows


def contact_drift(exe, repeat):
    rows = []
    for stab in ("none", "baumgarte", "projection"):
        r = simulate(exe, study("two_wheeler.yaml", 20.0, 201, "bdf", 1e-8, "multipliers", stab), repeat,
                     ("v=5", "lean0=0.02", "steer0=0.05"))
        rows.append(row("two-wheeler, v = 5 m/s, 20 s: contact heights", "bdf", "multipliers", stab, r, float("nan")))
        r = simulate(exe, study("rolling_disc.yaml", 30.0, 301, "bdf", 1e-8, "multipliers", stab), repeat)
        rows.append(row("rolling disc, 30 s: contact height", "bdf", "multipliers", stab, r, float("nan")))
    return rows


def table(rows, title):
    print(f"\n{title}\n")
    print("| case | method | formulation | stabilization | error | energy drift (rel.) | max contact/position "
          "residual | steps | RHS evals | repartitions | wall (ms, median) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        status = "" if r["status"] == 1 else f" (failed: {r['message'][:60]})"
        print(f"| {r['case']} | {r['method']} | {r['formulation']} | {r['stabilization']} | {r['error']:.1e}{status} | "
              f"{r['energy_drift']:.1e} | {r['position_residual']:.1e} | {r['steps']} | {r['rhs_evals']} | "
              f"{r['repartitions']} | {1e3 * r['wall_median']:.1f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", nargs="?", default=str(c.ROOT / "build"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=str(HERE / "constraints_choice.json"))
    a = ap.parse_args()
    exe = c.kanesens_exe(a.build)
    if not exe.is_file():
        sys.exit(f"kanesens not found under {a.build} (build first)")
    choice = knife_edge(exe, a.repeat) + rolling_disc(exe, a.repeat)
    choice += against_reference(exe, a.repeat, "crank-rocker four-bar, 10 s", "four_bar_crank_rocker.yaml", 10.0, 101,
                                methods=("bdf", "adams", "dop853"))
    choice += against_reference(exe, a.repeat, "parallelogram four-bar through its toggles, 3 s",
                                "parallelogram_four_bar.yaml", 3.0, 301, sets=("w1=12",))
    drift = contact_drift(exe, a.repeat)
    table(choice, "Embedding or multipliers")
    table(drift, "Contact-height drift")
    c.write_json(a.out, {"command": "bench/constraints_choice.py --repeat %d" % a.repeat, "revision": c.git_revision(),
                         "cpu": c.cpu_model(), "nproc": c.nproc(), "loadavg": c.loadavg(),
                         "choice": choice, "drift": drift})
    print(f"\nwrote {a.out}")


if __name__ == "__main__":
    main()
