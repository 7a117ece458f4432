#!/usr/bin/python3
"""Constraint drift of the crank-rocker four-bar over 100 s with stabilization none / baumgarte /
projection (rtol 1e-8; docs/explanation/constraints.md, "Drift over a long run").

    /usr/bin/python3 bench/drift_study.py [BUILD_DIR] [--kanesens EXE] [--figure PNG] [--out DIR]

Runs `kanesens simulate configs/four_bar_drift_study.yaml --format json` once per stabilization
(results in out/drift/<stabilization>.json), prints the markdown table and writes
docs/figures/constraint_drift.png.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import common as c

NAMES = ["none", "baumgarte", "projection"]
STUDY = c.CONFIGS / "four_bar_drift_study.yaml"


def find_kanesens(build: Path) -> Path:
    for exe in (build / "apps" / "kanesens" / "kanesens", c.kanesens_exe(build)):
        if exe.is_file():
            return exe
    sys.exit(f"kanesens not found under {build} (build first)")


def plot_and_table(runs: dict, png: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    print("| stabilization | max position residual (m) | max velocity residual (m/s) | max abs(E - E0) (J) | steps | "
          "RHS evals | wall (s) |")
    print("|---|---|---|---|---|---|---|")
    for s in NAMES:
        r = runs[s]
        assert r["status"] == 1, (s, r["message"])
        t = np.array(r["time"])
        pos = np.array(r["constraint_residuals"]["position"])
        vel = np.array(r["constraint_residuals"]["velocity"])
        e = np.array(r["outputs"]["energy"])
        de = np.abs(e - e[0])
        st = r["stats"]
        print(f"| {s} | {pos.max():.1e} | {vel.max():.1e} | {de.max():.1e} | {st['steps']} | {st['rhs_evals']} | "
              f"{st['wall_seconds']:.2f} |")
        floor = 1e-17
        axes[0].semilogy(t, np.maximum(pos, floor), label=s)
        axes[1].semilogy(t, np.maximum(vel, floor), label=s)
        axes[2].semilogy(t, np.maximum(de, floor), label=s)
    for ax, title in zip(axes, ["position residual max|g(q)| (m)", "velocity residual max|A u| (m/s)",
                                "energy drift |E(t) - E(0)| (J)"]):
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("t (s)")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=9)
    fig.suptitle("Crank-rocker four-bar, 100 s, BDF rtol 1e-8 atol 1e-10 (configs/four_bar_drift_study.yaml)",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"\nfigure: {png}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", nargs="?", default=str(c.ROOT / "build"), help="build directory")
    ap.add_argument("--kanesens", help="the kanesens executable (default: found in the build directory)")
    ap.add_argument("--out", default=str(c.ROOT / "out" / "drift"), help="directory of the JSON results")
    ap.add_argument("--figure", default=str(c.ROOT / "docs" / "figures" / "constraint_drift.png"))
    a = ap.parse_args(argv)
    exe = Path(a.kanesens) if a.kanesens else find_kanesens(Path(a.build))
    out, png = Path(a.out), Path(a.figure)
    out.mkdir(parents=True, exist_ok=True)
    png.parent.mkdir(parents=True, exist_ok=True)
    runs = {}
    for s in NAMES:
        p = subprocess.run([str(exe), "simulate", str(STUDY), "--set", f"solver.constraints.stabilization={s}",
                            "--format", "json"], capture_output=True, text=True, check=True)
        (out / f"{s}.json").write_text(p.stdout)
        runs[s] = json.loads(p.stdout)
    plot_and_table(runs, png)


if __name__ == "__main__":
    main()
