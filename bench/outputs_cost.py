#!/usr/bin/python3
"""Cost of study outputs on the flagship study (configs/double_pendulum_uq.yaml, nominal sample,
with its three sensitivities): `kanesens simulate` plain, with the outputs of
docs/reference/study.md (point kinematics, joint load, energy, expressions, an integral), and
with only the cheap ones (positions, energy, expressions). Runs interleaved; wall time is the
median of R runs of each variant, ratios against the plain study from the same run.

    /usr/bin/python3 bench/outputs_cost.py [BUILD_DIR] [--repeat R] [--out JSON]

Writes the raw figures to bench/results/outputs_cost.json and prints a markdown table
(docs/benchmarks.md, "Cost of outputs").
"""
from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import common as c

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

ALL_OUTPUTS = """
outputs:
  tip:   {type: position, body: rod2, point: [0, "-L2/2", 0]}
  tipv:  {type: velocity, body: rod2, point: [0, "-L2/2", 0]}
  tipa:  {type: acceleration, body: rod2, point: [0, "-L2/2", 0]}
  elbow_load: {type: joint_load, joint: elbow}
  ke:    {type: energy, kind: kinetic}
  reach: {expression: "sqrt(tip.x^2 + tip.y^2)"}
  tip_y_end: {of: tip.y, at: end}
  work:  {of: "elbow_load.mz*elbow.u", reduce: integral}
"""

CHEAP_OUTPUTS = """
outputs:
  tip:   {type: position, body: rod2, point: [0, "-L2/2", 0]}
  ke:    {type: energy, kind: kinetic}
  reach: {expression: "sqrt(tip.x^2 + tip.y^2)"}
  tip_y_end: {of: tip.y, at: end}
"""


def study(extra: str) -> str:
    """The flagship study without its own outputs and poses (the plain study), plus `extra`."""
    lines = []
    for line in (ROOT / "configs" / "double_pendulum_uq.yaml").read_text().splitlines():
        if line.startswith("outputs:"):
            break  # the study's own outputs block ends the file
        if line.startswith("record:"):
            line = "record: [states, sensitivities, energy]"
        lines.append(line)
    text = "\n".join(lines) + "\n"
    # The nominal sample only: simulate ignores sampling/vary.
    return text.replace("scene: double_pendulum.yaml", f"scene: {ROOT / 'configs' / 'double_pendulum.yaml'}") + extra


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", nargs="?", default=str(ROOT / "build"))
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--out", default=str(HERE / "results" / "outputs_cost.json"))
    a = ap.parse_args()
    exe = c.kanesens_exe(a.build)
    variants = {"plain": study(""), "cheap outputs": study(CHEAP_OUTPUTS), "all outputs": study(ALL_OUTPUTS)}
    with tempfile.TemporaryDirectory() as d:
        files = {}
        for name, text in variants.items():
            p = Path(d) / (name.replace(" ", "_") + ".yaml")
            p.write_text(text)
            files[name] = p
            subprocess.run([str(exe), "simulate", str(p)], check=True, capture_output=True)  # warm-up, and valid
        times = {name: [] for name in files}
        for _ in range(a.repeat):
            for name, p in files.items():
                t0 = time.perf_counter()
                subprocess.run([str(exe), "simulate", str(p)], check=True, capture_output=True)
                times[name].append(time.perf_counter() - t0)
    med = {name: statistics.median(v) for name, v in times.items()}
    result = {
        "command": " ".join(["bench/outputs_cost.py", a.build, "--repeat", str(a.repeat)]),
        "revision": c.git_revision(), "cpu": c.cpu_model(), "nproc": c.nproc(), "loadavg": c.loadavg(),
        "study": "configs/double_pendulum_uq.yaml without its outputs and poses (nominal sample, 3 sensitivities, 251 output times)",
        "median_seconds": med, "runs_seconds": times,
        "ratio_to_plain": {name: med[name] / med["plain"] for name in med},
    }
    c.write_json(a.out, result)
    print("| variant | median wall time (simulate, whole process) | ratio to plain |")
    print("|---|---|---|")
    for name in files:
        print(f"| {name} | {med[name] * 1e3:.1f} ms | {med[name] / med['plain']:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
