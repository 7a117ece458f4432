"""kanesens runs of the four-bar (configs/four_bar.yaml) for the four-bar peer benches.

Shared by bench/bench_peers_fourbar.py and bench/bench_peers_fourbar_sympy.py: one study
file, one way to run `kanesens simulate` with a (method, constraint formulation, stabilization)
variant at a tolerance, and the variants' names.

A variant whose method this kanesens does not know (dop853 before it landed) is skipped with a
printed note, so that the benches run on kanesens builds from before and after it.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "configs" / "four_bar.yaml"

# (method, formulation, stabilization): CVODES projects only with BDF; dop853 (explicit
# Dormand–Prince 8(5,3)) takes embedding without stabilization or multipliers with Baumgarte.
LABELS = {("bdf", "multipliers", "projection"): "BDF mult.+proj.",
          ("adams", "multipliers", "baumgarte"): "Adams mult.+Baumg.",
          ("adams", "embedding", "none"): "Adams embed.",
          ("bdf", "embedding", "projection"): "BDF embed.+proj.",
          ("dop853", "embedding", "none"): "DOP853 embed.",
          ("dop853", "multipliers", "baumgarte"): "DOP853 mult.+Baumg."}


class UnknownMethod(RuntimeError):
    """This kanesens has no such solver.method."""


def name(variant) -> str:
    return "/".join(variant)


def label(variant_name: str) -> str:
    return LABELS[tuple(variant_name.split("/"))]


def write_study(path: Path, t_end: float) -> Path:
    """A study of the four-bar scene recording the states at t = 0 and t_end only."""
    path.write_text(f"kanesens: 1\nscene: {SCENE}\ntime: {{end: {t_end!r}, outputs: 2}}\n"
                    "solver: {method: bdf, rtol: 1.0e-8, atol: 1.0e-10, jacobian: exact, max_steps: 100000000,\n"
                    "         constraints: {formulation: multipliers, stabilization: projection}}\n"
                    "record: [states]\n")
    return path


def simulate(exe, study, variant, rtol, atol, settings=()) -> dict:
    """`kanesens simulate` of the study with the variant; its JSON output plus "process_wall_s".
    Exit status 4 (integration stopped early) is returned, not raised: the caller records it."""
    method, formulation, stabilization = variant
    cmd = [str(exe), "simulate", str(study), "--format", "json", "--sens", "none",
           "--set", f"solver.method={method}", "--set", f"solver.constraints.formulation={formulation}",
           "--set", f"solver.constraints.stabilization={stabilization}",
           "--set", f"solver.rtol={rtol!r}", "--set", f"solver.atol={atol!r}"]
    for s in settings:
        cmd += ["--set", s]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode not in (0, 4):
        # kanesens's enum error: "solver.method: expected one of bdf, adams, found 'dop853'"
        if "solver.method" in p.stderr and "expected one of" in p.stderr and f"'{method}'" in p.stderr:
            raise UnknownMethod(p.stderr.strip())
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
    out = json.loads(p.stdout)
    out["process_wall_s"] = dt
    return out


def available(exe, study, variants, who: str) -> list:
    """The variants this kanesens can run (one loose run each); a note on stderr for each skipped."""
    kept = []
    for v in variants:
        try:
            simulate(exe, study, v, 1e-4, 1e-6)
            kept.append(v)
        except UnknownMethod as e:
            print(f"{who}: skipping kanesens {name(v)}: this kanesens has no solver.method {v[0]} ({e})",
                  file=sys.stderr, flush=True)
    return kept
