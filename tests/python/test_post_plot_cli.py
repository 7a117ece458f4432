"""Plots are written and non-trivial; every CLI subcommand's --json parses; bad input gives
one clear line and exit status 2."""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from kanesens_post.cli import main
from post_fixtures import pendulum_saltelli

# The package in the source tree (python/), run as `python -m kanesens_post` in a subprocess
# so that exit statuses and stderr are those a user sees.
PACKAGE_DIR = Path(__file__).resolve().parents[2] / "python"


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    return pendulum_saltelli(tmp_path_factory.mktemp("cli") / "pend.h5", n_base=64, nt=51)


def post(*args):
    path = os.pathsep.join(filter(None, [str(PACKAGE_DIR), os.environ.get("PYTHONPATH")]))
    env = dict(os.environ, PYTHONPATH=path)
    return subprocess.run([sys.executable, "-m", "kanesens_post", *map(str, args)],
                          capture_output=True, text=True, env=env)


@pytest.mark.parametrize("kind, extra", [("states", ["--outputs", "energy", "--states",
                                                      "pivot.q"]),
                                         ("sensitivities", []), ("multipliers", [])])
def test_plot_png(run_file, tmp_path, kind, extra):
    png = tmp_path / f"{kind}.png"
    assert main(["plot", str(run_file), "--kind", kind, "--out", str(png), *extra]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 15000


@pytest.mark.parametrize("args, keys", [
    (["summary"], ["ok", "failed", "solver_stats", "energy_drift"]),
    (["sobol", "--output", "pivot.q", "--at", "3", "--bootstrap", "20"], ["S1", "ST", "S1_ci"]),
    (["sobol", "--output", "energy", "--over-time", "--bootstrap", "0"], ["S1", "ST"]),
    (["dgsm", "--output", "pivot.q", "--at", "3"], ["nu", "total_index_bound"]),
    (["linear-uq", "--output", "pivot.u", "--at", "1"], ["variance_linear", "variance_mc"]),
    (["linear-uq", "--output", "pivot.q", "--over-time"], ["holds", "first_breakdown_time"]),
    (["plot", "--kind", "multipliers", "--out", "{tmp}/m.png"], ["png"]),
])
def test_json(run_file, tmp_path, args, keys):
    p = post(args[0], run_file, "--json", *[a.format(tmp=tmp_path) for a in args[1:]])
    assert p.returncode == 0, p.stderr
    result = json.loads(p.stdout)
    assert all(k in result for k in keys)
    if args[0] == "sobol" and "--at" in args:
        assert result["base_points"] == 62 and result["base_points_dropped"] == 2
        assert np.array(result["ST"]).shape == (3,)


def test_morris_json(tmp_path):
    sys.path.insert(0, str(Path(__file__).parent))
    from post_fixtures import morris_design, uniform_vary, write_function_run
    x = morris_design(10, 2, seed=1)
    path = write_function_run(tmp_path / "m.h5", x, ["a", "b"], 3 * x[:, 0] - x[:, 1],
                              method="morris", vary=uniform_vary({"a": (0, 1), "b": (0, 1)}))
    p = post("morris", path, "--output", "y", "--at", "0", "--json")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["mu_star"] == pytest.approx([3, 1])


def test_text_output(run_file):
    p = post("summary", run_file)
    assert p.returncode == 0 and "318 ok, 2 failed, 0 not run" in p.stdout


@pytest.mark.parametrize("args, message", [
    (["sobol", "--output", "elbow.q", "--at", "1"], "no state or output named 'elbow.q'"),
    (["summary", "--output", "enrgy"], "no state or output named 'enrgy' (did you mean 'energy'?)"),
    (["plot", "--output", "pivot"], "name one of its components: pivot.q, pivot.u"),
    (["sobol", "--output", "pivot.q"], "'pivot.q' is a series over time: give --at T"),
    (["sobol", "--output", "pivot.q", "--at", "1", "--over-time"], "either --at T or --over-time"),
    (["morris", "--output", "pivot.q", "--at", "1"], "needs a Morris design"),
    (["dgsm", "--output", "energy", "--at", "1"], "no sensitivities of output 'energy'"),
    (["dgsm", "--output", "pivot.q"], "'pivot.q' is a series over time: give --at T"),
    (["linear-uq", "--output", "pivot.q", "--at", "99"], "covers t = 0.0 .. 10.0"),
])
def test_errors_are_one_line(run_file, capsys, args, message):
    assert main([args[0], str(run_file), *args[1:]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
