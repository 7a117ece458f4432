#!/usr/bin/python3
"""Runs bench/multitangent_kernels.cpp's program and makes the comparison table.

  multitangent_table.py EXE OUT.json            measure (callgrind counts, then wall-clock)
  multitangent_table.py --table OUT.json        print the markdown table of a measured JSON

Instructions per kernel call come from `valgrind --tool=callgrind` (repeatable on a shared
machine): Ir(2 K calls) − Ir(K calls), divided by K. Wall-clock medians come from Google
Benchmark (--benchmark_repetitions, interleaved); they are noisy on a loaded machine and are
reported beside the counts, not instead of them.
"""
import json
import os
import subprocess
import sys
import tempfile

from common import provenance

KERNELS = ["rotation", "inertia", "cholesky", "sincos"]
TYPES = ["MultiDual", "ceres::Jet", "Eigen::AutoDiffScalar"]
WIDTHS = [1, 2, 4, 6, 8, 16]
CALLS = 2000


def instructions(exe, kernel, typ, n, calls):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "cg.out")
        subprocess.run(["valgrind", "--tool=callgrind", "--instr-atstart=no", f"--callgrind-out-file={out}",
                        exe, "--count", kernel, typ, str(n), str(calls)],
                       check=True, capture_output=True, text=True)
        with open(out) as f:
            for line in f:
                if line.startswith("totals:"):
                    return int(line.split()[1])
    raise RuntimeError("no totals line")


def per_call(exe, kernel, typ, n):
    return (instructions(exe, kernel, typ, n, 2 * CALLS) - instructions(exe, kernel, typ, n, CALLS)) / CALLS


def rows():
    for k in KERNELS:
        yield k, "double", 0
        yield k, "Dual", 1
        for n in WIDTHS:
            for t in TYPES:
                yield k, t, n
    for n in WIDTHS:
        yield "cholesky_reuse", "MultiDual", n


def measure(exe, out):
    machine = provenance()
    result = {"command": machine["command"], "machine": machine, "instructions_per_call": {}, "wall_ns_median": {}}
    for k, t, n in rows():
        key = f"{k}/{t}/{n}"
        result["instructions_per_call"][key] = per_call(exe, k, t, n)
        print(key, result["instructions_per_call"][key], file=sys.stderr)
    p = subprocess.run([exe, "--benchmark_repetitions=9", "--benchmark_enable_random_interleaving=true",
                        "--benchmark_min_time=0.05", "--benchmark_format=json"],
                       check=True, capture_output=True, text=True)
    bench = json.loads(p.stdout)
    result["google_benchmark_context"] = bench["context"]
    for b in bench["benchmarks"]:
        if b.get("aggregate_name") == "median":
            result["wall_ns_median"][b["run_name"]] = b["real_time"]
    with open(out, "w") as f:
        json.dump(result, f, indent=1)


def table(path):
    with open(path) as f:
        r = json.load(f)
    ir, wall = r["instructions_per_call"], r["wall_ns_median"]
    print("Instructions per call (callgrind), and in parentheses the ratio to the double kernel;")
    print("wall-clock medians (ns) below.\n")
    for k in KERNELS:
        base = ir[f"{k}/double/0"]
        print(f"**{k}**: double {base:.0f}, Dual {ir[f'{k}/Dual/1']:.0f} ({ir[f'{k}/Dual/1'] / base:.1f}x)\n")
        types = TYPES + (["MultiDual, value factor reused"] if k == "cholesky" else [])
        print("| N | " + " | ".join(types) + " |")
        print("|---:|" + "---:|" * len(types))
        for n in WIDTHS:
            cells = []
            for t in TYPES:
                v = ir[f"{k}/{t}/{n}"]
                cells.append(f"{v:.0f} ({v / base:.1f}x), {wall.get(f'{k}/{t}/{n}', float('nan')):.0f} ns")
            if k == "cholesky":
                v = ir[f"cholesky_reuse/MultiDual/{n}"]
                cells.append(f"{v:.0f} ({v / base:.1f}x), {wall.get(f'cholesky_reuse/MultiDual/{n}', float('nan')):.0f} ns")
            print(f"| {n} | " + " | ".join(cells) + " |")
        print()


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(sys.argv[2])
    elif len(sys.argv) == 3:
        measure(sys.argv[1], sys.argv[2])
        table(sys.argv[2])
    else:
        sys.exit(__doc__)
