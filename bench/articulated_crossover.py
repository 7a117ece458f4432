#!/usr/bin/python3
"""Where the articulated-body recursion beats M and its factor: `kanesens bench rhs
--rhs-algorithm mass_matrix|articulated_body --json` on spatial N-link chains of revolute joints
(axes z, x alternating: bench/common.py's chain_scene_yaml, as in docs/benchmarks.md's MuJoCo
table), on chains of ball joints (3 speeds each) and on planar chains (every axis z, the planar
path and its own recursion), the two interleaved in every round. The ratio
is taken within a round; the table shows its median over the rounds, and the medians of the times.

  articulated_crossover.py OUT.json [--ns "2 4 8 16 32 64"] [--balls "2 4 8 10 16"]
      [--planar "1 2 4 8 16 32 64"] [--rounds 9] [--build build]
  articulated_crossover.py --table OUT.json

The workspace uses the recursion on every chain of one-speed joints (3-D or planar), and on chains with
multi-speed joints from dynamics::kArticulatedBodyMinSpeeds speeds on (src/dynamics/workspace.hpp),
the crossover of the ball chains.
"""
import argparse
import statistics
import sys
import tempfile
from pathlib import Path

import common as c

WHO = "articulated_crossover"
ALGORITHMS = ("mass_matrix", "articulated_body")


def ball_chain_yaml(n: int) -> str:
    """n boxes hanging on ball joints (as tests/unit/test_articulated_body.cpp's ball_chain)."""
    s = f"kanesens: 1\nscene:\n  name: balls{n}\n  gravity: [0, -9.81, 0]\n  bodies:\n"
    s += "".join(f"    - {{name: b{i}, mass: 1, inertia: {{shape: box, size: [0.1, 1, 0.2]}}}}\n" for i in range(1, n + 1))
    s += "  joints:\n"
    for i in range(1, n + 1):
        parent = "ground" if i == 1 else f"b{i - 1}"
        y = "0" if i == 1 else "-0.5"
        s += (f"    - {{name: j{i}, type: spherical, parent: {parent}, child: b{i}, parent_point: [0, {y}, 0], "
              f"child_point: [0, 0.5, 0]}}\n")
    return s


def measure(a) -> dict:
    exe = c.kanesens_exe(a.build)
    load = c.loadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        chains = [("revolute", int(n), c.chain_scene_yaml(int(n), axes="z,x")) for n in c.words(a.ns)]
        chains += [("ball", 3 * int(n), ball_chain_yaml(int(n))) for n in c.words(a.balls)]
        chains += [("revolute, planar path", int(n), c.chain_scene_yaml(int(n))) for n in c.words(a.planar)]
        for i, (kind, n, text) in enumerate(chains):
            scene = Path(tmp) / f"chain{i}.yaml"
            scene.write_text(text)
            times = {k: [] for k in ALGORITHMS}
            for r in range(a.rounds):
                c.log(WHO, f"round {r + 1}/{a.rounds}, {kind} chain, {n} speeds")
                for k in ALGORITHMS:
                    d = c.run_json([exe, "bench", "rhs", scene, "--json", "--rhs-algorithm", k, "--repeat", "15"])
                    assert d["rhs_algorithm"] == k, d["rhs_algorithm"]
                    times[k].append(d["rhs"]["median_ns"])
            ratio = [m / b for m, b in zip(times["mass_matrix"], times["articulated_body"])]
            rows.append({"joints": kind, "n": n, "mass_matrix_ns": times["mass_matrix"],
                         "articulated_body_ns": times["articulated_body"], "ratio_median": statistics.median(ratio)})
    return {**c.provenance(load), "rounds": a.rounds, "rows": rows}


def table(path):
    r = c.load_json(path)
    print(f"Medians over {r['rounds']} interleaved rounds of `kanesens bench rhs` on each chain.\n")
    print("| joints | speeds | M and its factor (ns) | articulated body (ns) | M and factor / articulated body |")
    print("|---|---:|---:|---:|---:|")
    for row in r["rows"]:
        print(f"| {row.get('joints', 'revolute')} | {row['n']} | {statistics.median(row['mass_matrix_ns']):,.0f} | "
              f"{statistics.median(row['articulated_body_ns']):,.0f} | {row['ratio_median']:.2f} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    c.table_or_usage(argv, table, __doc__) if argv[:1] == ["--table"] else None
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--ns", default="2 4 8 16 32 64")
    ap.add_argument("--balls", default="2 4 8 10 16")
    ap.add_argument("--planar", default="1 2 4 8 16 32 64")
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--build", default=str(c.ROOT / "build"))
    a = ap.parse_args(argv)
    c.write_json(a.out, measure(a))
    c.log(WHO, f"wrote {a.out}; table: bench/make_tables.py")
