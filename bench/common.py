"""Shared pieces of the benchmark drivers in bench/: where the executables are, building them,
the benchmark chain scene, the machine description, medians and time-to-accuracy.

Every driver is run with Debian's interpreter from anywhere, e.g.
    /usr/bin/python3 bench/bench_rhs.py --help
and imports this module from its own directory.
"""
from __future__ import annotations

import json
import math
import os
import shlex
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"
BENCH_CONFIGS = ROOT / "bench" / "configs"  # the wp_* work-precision studies
SCRIPTS = ROOT / "scripts"
PYTHON = os.environ.get("KANESENS_PYTHON", "/usr/bin/python3")

# Where the build puts the executables, relative to a build directory.
KANESENS = "kanesens"                             # the product CLI
WORKPRECISION = ("bench/kanesens-workprecision",)  # harness executable and its leading arguments
PEERS = "bench/peers"                             # simbody_*_bench, mujoco_*_bench

median = statistics.median


def env_default(name: str, default):
    """The environment variable `name` if set (the drivers' historical knobs), else default."""
    return os.environ.get(name, default)


def kanesens_exe(build: Path | str) -> Path:
    return Path(build) / KANESENS


def workprecision_cmd(build: Path | str) -> list[str]:
    """The work-precision harness as a command prefix. KANESENS_WORKPRECISION (a command line,
    e.g. "build/bench/kanesens-workprecision") overrides the one in the build directory."""
    given = os.environ.get("KANESENS_WORKPRECISION")
    if given:
        return shlex.split(given)
    exe, *args = WORKPRECISION
    return [str(Path(build) / exe), *args]


def peer_exe(build: Path | str, name: str) -> Path:
    return Path(build) / PEERS / name


def cmake_build(build: Path | str, targets, options=(), configure="missing") -> None:
    """Build `targets` in `build`, configuring it first with `options`.

    configure="missing": only when the directory has no CMakeCache.txt (an existing one may
    come from another worktree of the same sources: cmake refuses a second source directory,
    and --build keeps it up to date from its own); "always": every time (the options win)."""
    build = Path(build)
    if configure == "always" or not (build / "CMakeCache.txt").exists():
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), *options], check=True,
                       stdout=subprocess.DEVNULL)
    jobs = os.environ.get("KANESENS_JOBS", "1")
    subprocess.run(["cmake", "--build", str(build), "-j", jobs, "--target", *targets], check=True,
                   stdout=subprocess.DEVNULL)


def run_json(cmd, **kw):
    """Run cmd (check=True) and parse its stdout as JSON."""
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, check=True, **kw)
    return json.loads(p.stdout)


def write_json(path: Path | str, data) -> None:
    Path(path).write_text(json.dumps(data))


def load_json(path: Path | str):
    return json.loads(Path(path).read_text())


def table_or_usage(argv, table, usage: str) -> None:
    """A driver's `--table OUT.json`: print the Markdown table of a committed measurement and
    exit; fewer than two arguments (OUT.json and what to measure): print the usage and exit."""
    if len(argv) == 2 and argv[0] == "--table":
        table(argv[1])
        sys.exit(0)
    if len(argv) < 2:
        sys.exit(usage)


def log(who: str, message: str) -> None:
    print(f"{who}: {message}", file=sys.stderr, flush=True)


def cpu_model() -> str:
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return "?"


def nproc() -> int:
    """Cores this process may use (what `nproc` prints)."""
    return len(os.sched_getaffinity(0))


def loadavg() -> list[str]:
    return open("/proc/loadavg").read().split()[:3]


def git_revision() -> str:
    return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()


def chain_scene_yaml(n: int, tilt: float = 0.0, axes: str = "z") -> str:
    """The N-link benchmark chain (rods of mass 1, length 1, central inertia
    diag(1/12, 1e-4, 1/12); tests/support/test_scenes.hpp's chain_scene and the peer programs
    build the same). `axes` ("z" planar, "z,x" spatial: the peers' --axes) are the joint axes,
    cycled along the chain. `tilt` rad tips the last axis out of the plane (which forces the
    general 3-D evaluation of an otherwise planar chain)."""
    unit = {"x": "[1, 0, 0]", "y": "[0, 1, 0]", "z": "[0, 0, 1]"}
    cycle = [unit[a] for a in axes.split(",")]
    lines = [f"kanesens: 1\nscene:\n  name: chain{n}\n  gravity: [0, -9.81, 0]",
             "  parameters: {m: 1.0, L: 1.0}\n  bodies:"]
    for i in range(1, n + 1):
        lines.append('    - {name: link%d, mass: m, inertia: {xx: "m*L^2/12", yy: 1.0e-4, zz: "m*L^2/12"}}' % i)
    lines.append("  joints:")
    for i in range(1, n + 1):
        axis = cycle[(i - 1) % len(cycle)]
        if tilt and i == n:
            axis = "[%.17g, 0, %.17g]" % (math.sin(tilt), math.cos(tilt))
        parent = "ground" if i == 1 else "link%d" % (i - 1)
        pp = "0" if i == 1 else '"-L/2"'
        lines.append('    - {name: j%d, type: revolute, parent: %s, child: link%d, axis: %s, '
                     'parent_point: [0, %s, 0], child_point: [0, "L/2", 0]}' % (i, parent, i, axis, pp))
    return "\n".join(lines) + "\n"


def gen_chain_yaml(n: int, **kw) -> str:
    """scripts/gen_chain.py's chain scene (the user tool that writes configs/nlink_chain_*.yaml)."""
    if str(SCRIPTS) not in sys.path:
        sys.path.insert(0, str(SCRIPTS))
    from gen_chain import chain_yaml
    return chain_yaml(n, **kw)


def fmt_list(xs) -> str:
    """A comma-separated list of exact (round-trip) numbers for --q=/--u= arguments."""
    return ",".join(repr(x) for x in xs)


def flatten(x) -> list:
    """The numbers of a nested list (a JSON series of rows), in order; a number as [x]."""
    return [v for row in x for v in flatten(row)] if isinstance(x, list) else [x]


def max_err(y, ref) -> float:
    return float(max(abs(a - b) for a, b in zip(y, ref)))


def interleaved(a, b) -> list:
    """a[0], b[0], a[1], b[1], ...; the longer list's tail last."""
    out = []
    for i in range(max(len(a), len(b))):
        out += a[i:i + 1] + b[i:i + 1]
    return out


def repeated_runs(configs, reps: int, run, slow_s: float = 2.0) -> dict:
    """{config: [run(config), ...]}: `reps` rounds through all configurations in turn, so that the
    machine's load hits every one alike; one whose first run took over slow_s seconds runs once."""
    res = {c: [] for c in configs}
    for rep in range(reps):
        for c in configs:
            if rep > 0 and res[c][0]["time_s"] > slow_s:
                continue
            res[c].append(run(c))
    return res


def time_at(points, target):
    """Time to reach error <= target on a sweep [(setting, err, time)] ordered loose -> tight:
    log-log interpolation between the last point above and the first point at or below.
    Returns (time, "<=" | "=") or (None, "not reached")."""
    prev = None
    for _setting, err, t in points:
        if err <= target:
            if prev is None:
                return t, "<="            # already the loosest setting reaches it
            e0, t0 = prev
            if e0 == err:
                return t, "="
            a = (math.log(target) - math.log(e0)) / (math.log(err) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t) - math.log(t0))), "="
        prev = (err, t)
    return None, "not reached"


def provenance(load_start=None) -> dict:
    """What a result JSON records about how it was made: the command line (as typed, relative to
    the repository), date, commit, machine, load."""
    argv = [sys.executable, os.path.relpath(sys.argv[0], ROOT)] + sys.argv[1:]
    import datetime
    import platform
    return {"command": " ".join(shlex.quote(a) for a in argv), "date": str(datetime.date.today()),
            "commit": git_revision(), "cpu": cpu_model(), "nproc": nproc(), "platform": platform.platform(),
            "loadavg_start": load_start, "loadavg_end": loadavg()}


def words(value) -> list[str]:
    """A space- or comma-separated list given on the command line or in the environment."""
    return str(value).replace(",", " ").split()
