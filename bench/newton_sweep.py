#!/usr/bin/python3
"""Newton's linear solver against the size of the mechanism: dense LU of the exact Jacobian vs
matrix-free GMRES (krylov) with exact Jacobian-vector products (one dual pass each) or CVODES's
difference-quotient products, with BDF.

Two families:
  * the IFToMM A02 N four-bar mechanism (bench/n_four_bar.py; 2N+1 rods, 2N constraint rows,
    multipliers + projection), the 20-s study at rtol 1e-8; error = max |crank0.q - φ(t)| over
    the outputs against the exact 1-DOF solution;
  * a planar chain of N links with joint springs and dampers (scripts/gen_chain.py), a 5-s swing
    at rtol 1e-8; error = max |state - dense state| (no closed form: the solvers' agreement);
  * optionally (--stiff-chain N:k:c) chains with stiff joints, 2 s at rtol 1e-6, with what
    linear_solver: auto chose;
  * optionally (--spatial-chain N) the benchmark chain of N links about alternating z and x axes
    (bench/common.py, the peers' spatial chain), released from 0.5 rad at its first joint, a
    2-s swing at rtol 1e-8: it moves in 3-D, so its right-hand side is the 3-D recursion.

For every case and linear solver: `kanesens simulate` --repeat times, the median (and all) of
the integration's wall seconds (stats.wall_seconds, setup included), and the solver counters of
the first run. Timings on a shared machine are noisy: compare the ratios of one run.

    /usr/bin/python3 bench/newton_sweep.py --kanesens build/kanesens \\
        --out bench/results/newton_sweep.json [--four-bar 5 10 20 40] [--chain 8 16 32 64] [--repeat 3]
        [--stiff-chain 64:1e4:10 64:1e5:100 64:1e5:1e3] [--spatial-chain 64 128]
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import n_four_bar  # noqa: E402
from common import chain_scene_yaml  # noqa: E402

SOLVERS = {  # name: extra solver keys
    "dense": "linear_solver: dense, jacobian: exact",
    "krylov": "linear_solver: krylov, jacobian: exact",
    "krylov_dq": "linear_solver: krylov, jacobian: dq",
}


def run(kanesens: str, study: Path, repeat: int) -> dict:
    walls, first = [], None
    for _ in range(repeat):
        out = subprocess.run([kanesens, "simulate", str(study)], capture_output=True, text=True)
        d = json.loads(out.stdout)
        if d["status"] != 1:
            return {"status": d["status"], "message": d["message"]}
        walls.append(d["stats"]["wall_seconds"])
        if first is None:
            first = d
    s = first["stats"]
    return {"status": 1, "linear_solver": s["linear_solver"], "wall_seconds_median": statistics.median(walls),
            "wall_seconds": walls,
            "steps": s["steps"], "rhs_evals": s["rhs_evals"], "jac_evals": s["jac_evals"],
            "jtimes_evals": s["jtimes_evals"], "lin_iters": s["lin_iters"],
            "lin_rhs_evals": s["lin_rhs_evals"], "nonlin_iters": s["nonlin_iters"],
            "nonlin_conv_fails": s["nonlin_conv_fails"], "error_test_fails": s["error_test_fails"],
            "_states": np.array(first["states"]), "_names": first["state_names"], "_time": first["time"]}


def four_bar(kanesens: str, n: int, repeat: int, tmp: Path) -> dict:
    scene = tmp / f"n_four_bar_{n}.yaml"
    scene.write_text(n_four_bar.scene_yaml(n))
    head = n_four_bar.study_yaml(str(scene), 20.0, 401, "bdf", 1e-8, 1e-10)
    phi, _ = n_four_bar.exact_solution(n, np.linspace(0.0, 20.0, 401))
    case = {"family": "n_four_bar", "n": n, "nbody": 2 * n + 1, "states": 2 * (2 * n + 1),
            "constraint_rows": 2 * n, "end": 20.0, "rtol": 1e-8, "atol": 1e-10, "solvers": {}}
    for name, keys in SOLVERS.items():
        study = tmp / f"n_four_bar_{n}_{name}.yaml"
        study.write_text(head.replace("solver: {method: bdf,", f"solver: {{method: bdf, {keys},"))
        r = run(kanesens, study, repeat)
        if r["status"] == 1:
            q = r["_states"][:, r["_names"].index("crank0.q")]
            r["error_vs_exact"] = float(np.max(np.abs(q - phi)))
        case["solvers"][name] = r
    return case


def against_dense(kanesens: str, case: dict, scene: Path, outputs: int, repeat: int, tmp: Path) -> dict:
    """Every solver of SOLVERS on the scene (BDF, rtol 1e-8), each one's states against dense's."""
    for name, keys in SOLVERS.items():
        study = tmp / f"{scene.stem}_{name}.yaml"
        study.write_text(f"kanesens: 1\nscene: {scene}\ntime: {{end: {case['end']}, outputs: {outputs}}}\n"
                         f"solver: {{method: bdf, rtol: 1.0e-8, atol: 1.0e-10, {keys}}}\n")
        case["solvers"][name] = run(kanesens, study, repeat)
    ref = case["solvers"]["dense"]
    for r in case["solvers"].values():
        if r["status"] == 1 and ref["status"] == 1:
            r["max_difference_vs_dense"] = float(np.max(np.abs(r["_states"] - ref["_states"])))
    return case


def chain(kanesens: str, n: int, repeat: int, tmp: Path) -> dict:
    scene = tmp / f"chain_{n}.yaml"
    text = subprocess.run([sys.executable, str(HERE.parent / "scripts" / "gen_chain.py"), str(n), "--spring", "20",
                           "--damper", "0.2", "--q0", "0.5"], capture_output=True, text=True, check=True).stdout
    scene.write_text(text)
    case = {"family": "chain", "n": n, "nbody": n, "states": 2 * n, "spring": 20, "damper": 0.2, "end": 5.0,
            "rtol": 1e-8, "atol": 1e-10, "solvers": {}}
    return against_dense(kanesens, case, scene, 101, repeat, tmp)


def spatial_chain(kanesens: str, n: int, repeat: int, tmp: Path) -> dict:
    scene = tmp / f"spatial_chain_{n}.yaml"
    scene.write_text(chain_scene_yaml(n, axes="z,x").replace("{name: j1, type: revolute,",
                                                             "{name: j1, q0: 0.5, type: revolute,"))
    case = {"family": "spatial_chain", "n": n, "nbody": n, "states": 2 * n, "end": 2.0, "rtol": 1e-8, "atol": 1e-10,
            "solvers": {}}
    return against_dense(kanesens, case, scene, 21, repeat, tmp)


def stiff_chain(kanesens: str, n: int, k: float, c: float, repeat: int, tmp: Path) -> dict:
    """A chain whose joints (all but the first) carry stiff springs and dampers, released at
    rest from j1.q0 = 0.5: how much stiffness unpreconditioned GMRES stands, and what auto takes."""
    scene = tmp / f"stiff_chain_{n}_{k:g}_{c:g}.yaml"
    text = subprocess.run([sys.executable, str(HERE.parent / "scripts" / "gen_chain.py"), str(n), "--spring", str(k),
                           "--damper", str(c), "--q0", "0.5", "--free-first"],
                          capture_output=True, text=True, check=True).stdout
    scene.write_text(text)
    case = {"family": "stiff_chain", "n": n, "nbody": n, "states": 2 * n, "spring": k, "damper": c, "end": 2.0,
            "rtol": 1e-6, "atol": 1e-8, "solvers": {}}
    for name, keys in {"dense": SOLVERS["dense"], "krylov": SOLVERS["krylov"],
                       "auto": "linear_solver: auto, jacobian: exact"}.items():
        study = tmp / f"stiff_chain_{n}_{k:g}_{c:g}_{name}.yaml"
        study.write_text(f"kanesens: 1\nscene: {scene}\ntime: {{end: 2.0, outputs: 11}}\n"
                         f"solver: {{method: bdf, rtol: 1.0e-6, atol: 1.0e-8, {keys}}}\n")
        case["solvers"][name] = run(kanesens, study, repeat)
    return case


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kanesens", default="build/kanesens")
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--four-bar", type=int, nargs="*", default=[5, 10, 20, 40])
    ap.add_argument("--chain", type=int, nargs="*", default=[8, 16, 32, 64])
    ap.add_argument("--stiff-chain", type=str, nargs="*", default=[],
                    help="N:k:c chains with stiff joints, e.g. 64:1e5:1e3")
    ap.add_argument("--spatial-chain", type=int, nargs="*", default=[])
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    cases = []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for n in a.four_bar:
            cases.append(four_bar(a.kanesens, n, a.repeat, tmp))
        for n in a.chain:
            cases.append(chain(a.kanesens, n, a.repeat, tmp))
        for spec in a.stiff_chain:
            n, k, c = spec.split(":")
            cases.append(stiff_chain(a.kanesens, int(n), float(k), float(c), a.repeat, tmp))
        for n in a.spatial_chain:
            cases.append(spatial_chain(a.kanesens, n, a.repeat, tmp))
    for c in cases:
        dense = c["solvers"]["dense"]
        for name, r in c["solvers"].items():
            for k in [k for k in r if k.startswith("_")]:
                del r[k]
            if r["status"] == 1 and dense["status"] == 1:
                r["wall_ratio_vs_dense"] = r["wall_seconds_median"] / dense["wall_seconds_median"]
            print(f"{c['family']:13s} N={c['n']:3d} {name:9s} {r.get('linear_solver', '')} " + (
                f"{r['wall_seconds_median']:8.3f} s  ratio {r.get('wall_ratio_vs_dense', 0):5.2f}  steps {r['steps']:5d}"
                f"  rhs {r['rhs_evals']:5d}  J {r['jac_evals']:3d}  Jv {r['jtimes_evals']:5d}"
                f"  newton {r['nonlin_iters']:5d}  err {r.get('error_vs_exact', r.get('max_difference_vs_dense', 0)):.2e}"
                if r["status"] == 1 else f"failed: {r['message']}"), flush=True)
    command = "/usr/bin/python3 bench/newton_sweep.py " + " ".join(sys.argv[1:])
    a.out.write_text(json.dumps({"command": command, "repeat": a.repeat, "cases": cases}, indent=1) + "\n")


if __name__ == "__main__":
    main()
