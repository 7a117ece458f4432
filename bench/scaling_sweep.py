#!/usr/bin/python3
"""How the cost of one right-hand side grows with the mechanism: `kanesens bench rhs` on the
IFToMM N four-bar mechanism (bench/n_four_bar.py) for several N and on the benchmark chain for
several lengths, plus the 20-second N four-bar study under BDF and DOP853 (wall time, steps,
error of crank0's angle against the exact 1-DOF solution).

    /usr/bin/python3 bench/scaling_sweep.py --build build [--before OTHER/kanesens] \
        [--out bench/results/scaling_sweep.json] [--plot bench/results/scaling_sweep.png]

--before times a second executable (e.g. one built from an older commit) on the same scenes,
interleaved with the first, so the two are measured in one run under the same load.
--plot-only redraws the plot from an existing JSON.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402
import n_four_bar  # noqa: E402

KINDS = ["rhs", "mass_matrix_and_forcing", "rhs_multipliers", "rhs_embedding", "jacobian", "jacobian_dual"]


def bench_rhs(exe: Path, scene: Path, repeat: int) -> dict:
    d = common.run_json([exe, "bench", "rhs", scene, "--repeat", repeat, "--json"])
    out = {"nbody": d["nbody"], "nu": d["nu"], "nconstraint_rows": d.get("nconstraint_rows", 0), "path": d["path"]}
    for k in KINDS:
        if k in d:
            out[k + "_us"] = d[k]["median_ns"] / 1000.0
    return out


def study(exe: Path, n: int, method: str, work: Path, end: float, rtol: float, repeat: int) -> dict:
    scene = work / f"n_four_bar_{n}.yaml"
    st = work / f"n_four_bar_{n}_{method}.yaml"
    scene.write_text(n_four_bar.scene_yaml(n))
    st.write_text(n_four_bar.study_yaml(str(scene), end, 401, method, rtol, 1e-10))
    walls = []
    for _ in range(repeat):
        p = subprocess.run([str(exe), "simulate", str(st)], capture_output=True, text=True, check=True)
        d = json.loads(p.stdout)
        walls.append(d["stats"]["wall_seconds"])
    col = d["state_names"].index("crank0.q")
    times = d["time"]
    phi, _ = n_four_bar.exact_solution(n, times)
    err = max(abs(row[col] - e) for row, e in zip(d["states"], phi))
    s = d["stats"]
    return {"n": n, "method": method, "rtol": rtol, "end": end, "status": d["status"],
            "wall_seconds": common.median(walls), "wall_seconds_all": walls, "steps": s["steps"], "rhs_evals": s["rhs_evals"],
            "jac_evals": s.get("jac_evals", 0), "jtimes_evals": s.get("jtimes_evals", 0),
            # builds before the choice of Newton's linear solver always used the dense one
            "linear_solver": s.get("linear_solver", "dense" if method != "dop853" else "none"),
            "max_error_crank0_q": err}


def sweep(a) -> dict:
    exes = {"after": common.kanesens_exe(a.build)}
    if a.before:
        exes["before"] = Path(a.before)
    load0 = common.loadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        scenes = []
        for n in a.four_bar:
            f = work / f"n_four_bar_{n}.yaml"
            f.write_text(n_four_bar.scene_yaml(n))
            scenes.append(("n_four_bar", n, f))
        for n in a.chain:
            f = work / f"chain_{n}.yaml"
            f.write_text(common.chain_scene_yaml(n))
            scenes.append(("chain", n, f))
        for family, n, f in scenes:
            for label, exe in exes.items():  # interleaved: same load for both
                if label == "before" and family == "n_four_bar" and n > a.before_max_n:
                    continue  # the dense Jacobian of the old code takes seconds there
                common.log("scaling_sweep", f"{label}: {family} N = {n}")
                rows.append({"family": family, "n": n, "build": label, **bench_rhs(exe, f, a.repeat)})
        studies = []
        for label, exe in exes.items():
            for method in a.methods:
                common.log("scaling_sweep", f"{label}: study N = {a.study_n}, {method}")
                studies.append({"build": label, **study(exe, a.study_n, method, work, a.end, a.rtol, a.study_repeat)})
    versions = {label: subprocess.run([str(exe), "--version"], capture_output=True, text=True).stdout.splitlines()[0]
                for label, exe in exes.items()}
    return {"provenance": common.provenance(load0), "versions": versions, "repeat": a.repeat, "rhs": rows,
            "studies": studies}


def growth(rows, family, build, kind, n0, n1):
    """Cost ratio per doubling of N between n0 and n1 (geometric mean)."""
    import math
    t = {r["n"]: r.get(kind + "_us") for r in rows if r["family"] == family and r["build"] == build}
    if t.get(n0) is None or t.get(n1) is None:
        return None
    return (t[n1] / t[n0]) ** (1.0 / math.log2(n1 / n0))


def plot(data: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    styles = {"after": "-", "before": ":"}
    for ax, family, kinds in ((axes[0], "n_four_bar", ["rhs_multipliers", "rhs_embedding", "mass_matrix_and_forcing", "jacobian"]),
                              (axes[1], "chain", ["rhs", "mass_matrix_and_forcing", "jacobian"])):
        for build in ("after", "before"):
            rows = sorted((r for r in data["rhs"] if r["family"] == family and r["build"] == build), key=lambda r: r["nu"])
            if not rows:
                continue
            for i, kind in enumerate(kinds):
                pts = [(r["nu"], r[kind + "_us"]) for r in rows if kind + "_us" in r]
                if pts:
                    ax.loglog(*zip(*pts), styles[build], marker="o", color=f"C{i}", label=f"{kind} ({build})")
        nus = sorted({r["nu"] for r in data["rhs"] if r["family"] == family})
        if nus:
            ax.loglog(nus, [0.05 * n for n in nus], "k--", lw=0.8, label="∝ nu")
        ax.set_xlabel("speeds nu")
        ax.set_ylabel("median time per evaluation, µs")
        ax.set_title("N four-bar (N = (nu − 1)/2)" if family == "n_four_bar" else "pendulum chain")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("kanesens bench rhs (" + data["provenance"]["commit"] + ")")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--before", help="a second kanesens executable to time on the same scenes")
    ap.add_argument("--before-max-n", type=int, default=40, help="largest N four-bar timed with --before")
    ap.add_argument("--four-bar", type=int, nargs="*", default=[5, 10, 20, 40, 80])
    ap.add_argument("--chain", type=int, nargs="*", default=[4, 8, 16, 32, 64])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--study-n", type=int, default=40)
    ap.add_argument("--methods", nargs="*", default=["bdf", "dop853"])
    ap.add_argument("--study-repeat", type=int, default=3, help="runs of each study (the median wall time is kept)")
    ap.add_argument("--end", type=float, default=20.0)
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--out", type=Path, default=common.ROOT / "bench/results/scaling_sweep.json")
    ap.add_argument("--plot", type=Path, default=common.ROOT / "bench/results/scaling_sweep.png")
    ap.add_argument("--plot-only", action="store_true")
    a = ap.parse_args()
    if a.plot_only:
        data = common.load_json(a.out)
    else:
        data = sweep(a)
        data["growth_per_doubling_20_to_80"] = {
            kind: growth(data["rhs"], "n_four_bar", "after", kind, 20, 80)
            for kind in ("rhs_multipliers", "rhs_embedding", "mass_matrix_and_forcing", "jacobian")}
        a.out.write_text(json.dumps(data, indent=1) + "\n")
    plot(data, a.plot)
    for s in data["studies"]:
        print(f"{s['build']:6s} N = {s['n']} {s['method']:7s} {s['wall_seconds']:.3f} s, {s['steps']} steps, "
              f"{s['rhs_evals']} rhs, {s['jac_evals']} jacobians, error {s['max_error_crank0_q']:.1e}")
    for r in data["rhs"]:
        print(f"{r['build']:6s} {r['family']:10s} N = {r['n']:3d} nu = {r['nu']:3d}  " +
              "  ".join(f"{k} {r[k + '_us']:.1f}" for k in KINDS if k + "_us" in r))
    print("growth per doubling of N, 20 → 80:", data.get("growth_per_doubling_20_to_80"))


if __name__ == "__main__":
    main()
