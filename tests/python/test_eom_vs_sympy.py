"""`kanesens eom` against the independent SymPy reference fixtures (tests/fixtures/sympy/*.json).

For every fixture (one scene each) and every case in it, runs

    $KANESENS eom <scene> --q=<q...> --u=<u...> --t=<t>

and compares mass_matrix, forcing, kinetic_energy and potential_energy with SymPy's
KanesMethod values (written by tests/sympy/generate_fixtures.py). The error measure per
quantity is

    rel = ||kanesens - reference|| / max(1, ||reference||)      (Frobenius / 2-norm / abs)

and must be <= 1e-10. udot (= M^-1 f) is also compared, to 1e-10 * cond(M), and qdot (the
kinematic differential equations, e.g. q' = 1/2 q (x) (0, w) for quaternions) to 1e-10.
The worst rel per quantity and scene is printed (pytest -s shows it) and, when the environment
variable KANESENS_REPORT names a file, merged into that JSON file as
{"<scene>": {"mass_matrix": .., "forcing": .., ..., "cases": n}}.

Environment: KANESENS = path of the kanesens executable (the test skips without it);
KANESENS_SOURCE_DIR = repository root (default: two levels above this file).
Only the standard library, numpy and pytest are needed (no SymPy).
"""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])
FIXTURES = sorted((ROOT / "tests" / "fixtures" / "sympy").glob("*.json"))
TOL = 1e-10
QUANTITIES = ("mass_matrix", "forcing", "kinetic_energy", "potential_energy")


def _exe() -> str:
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable); "
                    "ctest sets it, or run: KANESENS=build/kanesens pytest tests/python")
    if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
        pytest.fail(f"KANESENS={exe} is not an executable file")
    return exe


def _list(values) -> str:
    """Comma-separated, round-trip precision (repr of a float is the shortest exact form)."""
    return ",".join(repr(float(v)) for v in values)


def eom_command(exe: str, scene: Path, t: float, q, u) -> list:
    """The `kanesens eom` command line; `--q=` form so negative numbers are not options."""
    cmd = [exe, "eom", str(scene)]
    if len(q):
        cmd.append(f"--q={_list(q)}")
    if len(u):
        cmd.append(f"--u={_list(u)}")
    cmd.append(f"--t={float(t)!r}")
    return cmd


def rel_diff(got, ref) -> float:
    got, ref = np.asarray(got, dtype=float), np.asarray(ref, dtype=float)
    if got.shape != ref.shape:
        raise AssertionError(f"shape {got.shape} != reference shape {ref.shape}")
    return float(np.linalg.norm(got - ref) / max(1.0, np.linalg.norm(ref)))


def _report(scene: str, worst: dict) -> None:
    line = ", ".join(f"{k} {v:.2e}" for k, v in worst.items() if k != "cases")
    print(f"\n{scene}: worst relative difference over {worst['cases']} cases: {line}")
    path = os.environ.get("KANESENS_REPORT")
    if path:
        p = Path(path)
        data = json.loads(p.read_text()) if p.exists() and p.stat().st_size else {}
        data[scene] = worst
        p.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


def test_fixtures_exist():
    assert FIXTURES, f"no fixtures in {ROOT / 'tests/fixtures/sympy'}"


@pytest.mark.parametrize("fixture", FIXTURES, ids=[f.stem for f in FIXTURES])
def test_eom_matches_sympy(fixture):
    exe = _exe()
    data = json.loads(fixture.read_text())
    scene = ROOT / data["scene"]
    worst = {k: 0.0 for k in QUANTITIES + ("udot", "qdot")}
    failures = []
    for i, case in enumerate(data["cases"]):
        cmd = eom_command(exe, scene, case["t"], case["q"], case["u"])
        run = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=120)
        assert run.returncode == 0, (f"case {i}: {' '.join(cmd)} exited {run.returncode}\n"
                                     f"{run.stderr}")
        try:
            out = json.loads(run.stdout)
        except json.JSONDecodeError as exc:
            raise AssertionError(f"case {i}: output is not JSON ({exc}):\n{run.stdout[:500]}")
        for key in ("coordinate_names", "speed_names"):
            if key in out:
                assert out[key] == data[key], f"{key}: {out[key]} != {data[key]}"
        for key in QUANTITIES:
            assert key in out, f"case {i}: key {key!r} missing from eom output"
            r = rel_diff(out[key], case[key])
            worst[key] = max(worst[key], r)
            if r > TOL:
                failures.append(f"case {i} {key}: rel {r:.3e}\n  got {out[key]}\n  ref {case[key]}"
                                f"\n  command: {' '.join(cmd)}")
        M = np.asarray(case["mass_matrix"], dtype=float)
        checks = (("udot", TOL * np.linalg.cond(M)), ("qdot", TOL))
        for key, tol in checks:
            if key in case and out.get(key) is not None:
                r = rel_diff(out[key], case[key])
                worst[key] = max(worst[key], r)
                if r > tol:
                    failures.append(f"case {i} {key}: rel {r:.3e} > {tol:.1e}\n  got {out[key]}\n"
                                    f"  ref {case[key]}")
    worst["cases"] = len(data["cases"])
    _report(data["scene"], worst)
    assert not failures, f"{data['scene']}:\n" + "\n".join(failures)
