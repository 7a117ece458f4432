"""`kanesens eom` on the four-bar (configs/four_bar.yaml) against SymPy KanesMethod.

The SymPy side is tests/sympy/four_bar_kane.py: the four-bar written by hand (no kanesens code,
no scene parsing) with u1 independent, u2, u3 dependent, loop closure as configuration
constraints and its time derivative as velocity constraints. At random consistent states
(random crank angle q1 and elbow branch, q2, q3 by the closed-form assembly; random u1, u2 and
u3 from the velocity constraints), for the nominal parameters and a second set (`--set`):

* u̇: kanesens's constrained accelerations (M u̇ = f + Aᵀλ, A u̇ = −Ȧu) against SymPy's, u̇1 from
  the reduced (Kane) equation and u̇2, u̇3 from the differentiated velocity constraints;
  max abs difference / max(1, max |u̇|) <= 1e-10.
* λ: with SymPy's u̇, kanesens's own M, f, A and λ must satisfy M u̇ − f − Aᵀλ = 0;
  max abs residual / max(1, max |f|, max |Aᵀλ|) <= 1e-10.
* kinetic and potential energy (T = Σ ½ m v·v + ½ I ω², V = Σ m g y_G): relative <= 1e-12.

The worst differences are printed (pytest -s shows them).
Environment: KANESENS = kanesens executable (skips without it), KANESENS_SOURCE_DIR = repository
root. Needs Debian's python3 (sympy, numpy).
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR") or Path(__file__).resolve().parents[2])
sys.path.insert(0, str(ROOT / "tests" / "sympy"))
import four_bar_kane as fb  # noqa: E402

SCENE = ROOT / "configs" / "four_bar.yaml"
TOL = 1e-10
STATES = 10
# A second crank-rocker (Grashof: s + l = 0.25 + 0.7 < 0.65 + 0.55, crank next to the ground
# link) with other masses; gravity is the scene's, not a parameter.
SECOND = {"r": 0.25, "c": 0.65, "b": 0.55, "a": 0.7, "m1": 1.3, "m2": 1.7, "m3": 0.9, "g": 9.81}


def _exe() -> str:
    exe = os.environ.get("KANESENS")
    if not exe:
        pytest.skip("KANESENS is not set (path of the kanesens executable)")
    return exe


@pytest.fixture(scope="module")
def sympy_model():
    model = fb.equations(fb.kane_model())
    return (fb.lambdify(model, ("mass_matrix", "forcing", "kinetic_energy", "potential_energy")),
            fb.lambdify(model, ("closure", "velocity_matrix")))


def eom(params: dict, q, u) -> dict:
    cmd = [_exe(), "eom", str(SCENE), "--q=" + ",".join(repr(float(x)) for x in q),
           "--u=" + ",".join(repr(float(x)) for x in u)]
    for k, v in params.items():           # only what differs from the scene (gravity cannot)
        if v != fb.NOMINAL[k]:
            cmd += ["--set", f"{k}={v!r}"]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def consistent_states(params: dict, constraints, rng):
    """Random (q, u) on the constraint manifold, both assembly branches."""
    p = [params[k] for k in fb.PARAMETERS]
    for _ in range(STATES):
        q1 = rng.uniform(-2 * np.pi, 4 * np.pi)
        q2, q3 = fb.assemble(q1, params, elbow=rng.choice([-1, 1]))
        q = np.array([q1, q2, q3])
        g, A = (np.asarray(x, dtype=float) for x in constraints(q, np.zeros(3), p))
        assert np.max(np.abs(g)) < 1e-12, f"assembly does not close the loop: g = {g.ravel()}"
        u1 = rng.uniform(-8.0, 8.0)
        u = np.concatenate([[u1], np.linalg.solve(A[:, 1:], -A[:, 0] * u1)])
        yield q, u


@pytest.mark.parametrize("name,params", [("nominal", fb.NOMINAL), ("second", SECOND)])
def test_constrained_accelerations_and_multipliers(sympy_model, name, params):
    dynamics, constraints = sympy_model
    p = [params[k] for k in fb.PARAMETERS]
    worst = {"udot": 0.0, "multiplier_residual": 0.0, "energy": 0.0}
    for q, u in consistent_states(params, constraints, np.random.default_rng(20261122)):
        M, f, T, V = dynamics(q, u, p)
        udot = np.linalg.solve(np.asarray(M, dtype=float), np.asarray(f, dtype=float).ravel())
        k = eom(params, q, u)
        d_udot = np.max(np.abs(np.array(k["udot"]) - udot)) / max(1.0, np.max(np.abs(udot)))
        Mk, fk = np.array(k["mass_matrix"]), np.array(k["forcing"])
        force = np.array(k["constraint_matrix"]).T @ np.array(k["multipliers"])
        residual = Mk @ udot - fk - force
        d_lambda = np.max(np.abs(residual)) / max(1.0, np.max(np.abs(fk)), np.max(np.abs(force)))
        d_energy = max(abs(k["kinetic_energy"] - T) / max(1.0, abs(T)),
                       abs(k["potential_energy"] - V) / max(1.0, abs(V)))
        for key, d in (("udot", d_udot), ("multiplier_residual", d_lambda), ("energy", d_energy)):
            worst[key] = max(worst[key], d)
        assert d_udot <= TOL, f"{name}: u̇ kanesens {k['udot']} vs SymPy {udot.tolist()} at q {q}, u {u}"
        assert d_lambda <= TOL, f"{name}: M u̇ − f − Aᵀλ = {residual} at q {q}, u {u}"
        assert d_energy <= 1e-12, f"{name}: T, V kanesens {k['kinetic_energy']}, {k['potential_energy']} vs {T}, {V}"
    print(f"\nfour-bar {name}: worst relative difference over {STATES} states: "
          + ", ".join(f"{key} {v:.1e}" for key, v in worst.items()))
