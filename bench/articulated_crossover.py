#!/usr/bin/python3
"""Where the articulated-body recursion beats M and its factor: `kanesens bench rhs
--rhs-algorithm mass_matrix|articulated_body --json` on spatial N-link chains (joint axes z, x
alternating: bench/common.py's chain_scene_yaml, as in docs/benchmarks.md's MuJoCo table), the
two interleaved in every round. The ratio is taken within a round; the table shows its median
over the rounds, and the medians of the times.

  articulated_crossover.py OUT.json [--ns "8 16 20 24 28 32 48 64"] [--rounds 9] [--build build]
  articulated_crossover.py --table OUT.json

dynamics::kArticulatedBodyMinSpeeds (src/dynamics/workspace.hpp) is the first N of the crossover.
"""
import argparse
import statistics
import sys
import tempfile
from pathlib import Path

import common as c

WHO = "articulated_crossover"
ALGORITHMS = ("mass_matrix", "articulated_body")


def measure(a) -> dict:
    exe = c.kanesens_exe(a.build)
    load = c.loadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(x) for x in c.words(a.ns)]:
            scene = Path(tmp) / f"chain{n}_spatial.yaml"
            scene.write_text(c.chain_scene_yaml(n, axes="z,x"))
            times = {k: [] for k in ALGORITHMS}
            for r in range(a.rounds):
                c.log(WHO, f"round {r + 1}/{a.rounds}, N = {n}")
                for k in ALGORITHMS:
                    d = c.run_json([exe, "bench", "rhs", scene, "--json", "--rhs-algorithm", k, "--repeat", "15"])
                    assert d["rhs_algorithm"] == k, d["rhs_algorithm"]
                    times[k].append(d["rhs"]["median_ns"])
            ratio = [m / b for m, b in zip(times["mass_matrix"], times["articulated_body"])]
            rows.append({"n": n, "mass_matrix_ns": times["mass_matrix"], "articulated_body_ns": times["articulated_body"],
                         "ratio_median": statistics.median(ratio)})
    return {**c.provenance(load), "rounds": a.rounds, "rows": rows}


def table(path):
    r = c.load_json(path)
    print(f"Medians over {r['rounds']} interleaved rounds of `kanesens bench rhs` on spatial chains.\n")
    print("| N (speeds) | M and its factor (ns) | articulated body (ns) | M and factor / articulated body |")
    print("|---:|---:|---:|---:|")
    for row in r["rows"]:
        print(f"| {row['n']} | {statistics.median(row['mass_matrix_ns']):,.0f} | "
              f"{statistics.median(row['articulated_body_ns']):,.0f} | {row['ratio_median']:.2f} |")


if __name__ == "__main__":
    argv = sys.argv[1:]
    c.table_or_usage(argv, table, __doc__) if argv[:1] == ["--table"] else None
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--ns", default="8 16 20 24 28 32 48 64")
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--build", default=str(c.ROOT / "build"))
    a = ap.parse_args(argv)
    c.write_json(a.out, measure(a))
    c.log(WHO, f"wrote {a.out}; table: bench/make_tables.py")
