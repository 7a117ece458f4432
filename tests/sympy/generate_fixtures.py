#!/usr/bin/python3
"""Write the SymPy reference fixtures tests/fixtures/sympy/<scene>.json.

Regenerate (from the repository root, Debian's interpreter, about half a minute):

    /usr/bin/python3 tests/sympy/generate_fixtures.py

What it does:
1. writes the planar chain test scenes tests/fixtures/scenes/nlink_chain_<N>_spring_damper.yaml
   (N = 1..6) with scripts/gen_chain.py (spring k = 2, rest 0.1, damper c = 0.1 on every joint);
2. for every scene in SCENES builds Kane's equations with kane_reference.py (SymPy
   KanesMethod, independent of the C++ engine), evaluates them at the scene's initial state
   (t = 0, q0 with the quaternion normalised, u0) and at CASES random states (fixed seed:
   q in [-pi, pi], unit quaternions, u in [-2, 2], t in [0, 10]);
3. checks each case (M symmetric positive definite, kinetic energy = 1/2 u^T M u, all finite)
   and writes {"scene", "coordinate_names", "speed_names", "cases": [{"t", "q", "u",
   "mass_matrix", "forcing", "kinetic_energy", "potential_energy", "udot", "qdot"}]}
   (udot = M^-1 forcing by numpy, qdot = N(q) u from the kinematic differential equations).

The JSON files are committed; tests/python/test_eom_vs_sympy.py compares `kanesens eom` with them.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT / "scripts"))

import kane_reference as kr  # noqa: E402
from gen_chain import chain_yaml  # noqa: E402

SEED = 20240611
CASES = 6                     # random states per scene (plus the scene's initial state)
CHAIN_SPRING, CHAIN_REST, CHAIN_DAMPER = 2.0, 0.1, 0.1

SCENES = [
    "configs/simple_pendulum.yaml",
    "configs/double_pendulum.yaml",
    "configs/nlink_chain_4.yaml",
    *[f"tests/fixtures/scenes/nlink_chain_{n}_spring_damper.yaml" for n in range(1, 7)],
    "configs/cart_double_pendulum.yaml",
    "configs/arm_3d.yaml",
    "configs/spinning_top.yaml",
    "configs/free_body.yaml",
    "tests/fixtures/scenes/cylindrical_planar.yaml",
]


def write_chain_scenes() -> None:
    for n in range(1, 7):
        path = ROOT / f"tests/fixtures/scenes/nlink_chain_{n}_spring_damper.yaml"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(chain_yaml(n, spring=CHAIN_SPRING, damper=CHAIN_DAMPER, rest=CHAIN_REST))


def initial_state(scene_path: Path, model: kr.Model) -> tuple[list, list]:
    """The scene's (q0, u0) in joint order; quaternions normalised; defaults 0 / [1,0,0,0]."""
    sc = yaml.safe_load(scene_path.read_text())["scene"]
    pvals = {}
    for name, val in (sc.get("parameters") or {}).items():
        pvals[name] = kr.parse(val, pvals, name).evalf(30)
    q, u = [], []
    for j in sc.get("joints", []):
        qn, un = kr.JOINT_NAMES[j["type"]]
        default_q = [0.0] * len(qn)
        if j["type"] in ("spherical", "free"):
            default_q[-4] = 1.0
        jq = j.get("q0", default_q)
        ju = j.get("u0", [0.0] * len(un))
        jq = jq if isinstance(jq, list) else [jq]
        ju = ju if isinstance(ju, list) else [ju]
        jq = [float(kr.parse(v, pvals, "q0")) for v in jq]
        ju = [float(kr.parse(v, pvals, "u0")) for v in ju]
        if j["type"] in ("spherical", "free"):
            n = math.sqrt(sum(x * x for x in jq[-4:]))
            jq[-4:] = [x / n for x in jq[-4:]]
        assert len(jq) == len(qn) and len(ju) == len(un), j["name"]
        q += jq
        u += ju
    assert len(q) == len(model.q) and len(u) == len(model.u)
    return q, u


def check_case(name: str, out: dict, u: list) -> None:
    """Identities every case must satisfy (the reference checking itself)."""
    M, f = out["mass_matrix"], out["forcing"]
    assert np.all(np.isfinite(M)) and np.all(np.isfinite(f)), name
    assert np.allclose(M, M.T, rtol=0, atol=1e-12 * max(1.0, np.abs(M).max())), f"{name}: M not symmetric"
    np.linalg.cholesky(M)  # raises if M is not positive definite
    ke = 0.5 * np.dot(u, M @ np.asarray(u))
    assert abs(ke - out["kinetic_energy"]) <= 1e-12 * max(1.0, abs(ke)), f"{name}: KE != u'Mu/2"


def generate(scene: str, rng: np.random.Generator) -> dict:
    path = ROOT / scene
    model = kr.build_model(path)
    num = kr.NumericModel(model)
    states = [(0.0, *initial_state(path, model))]
    states += [kr.random_state(model, rng) for _ in range(CASES)]
    cases = []
    for t, q, u in states:
        out = num.evaluate(t, q, u)
        check_case(scene, out, u)
        cases.append({"t": t, "q": q, "u": u,
                      "mass_matrix": out["mass_matrix"].tolist(),
                      "forcing": out["forcing"].tolist(),
                      "kinetic_energy": out["kinetic_energy"],
                      "potential_energy": out["potential_energy"],
                      "udot": np.linalg.solve(out["mass_matrix"], out["forcing"]).tolist(),
                      "qdot": num.qdot(q, u).tolist()})
    return {"scene": scene, "generator": "tests/sympy/generate_fixtures.py (SymPy KanesMethod)",
            "coordinate_names": model.coordinate_names, "speed_names": model.speed_names,
            "cases": cases}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Write SymPy reference fixtures.")
    ap.add_argument("--out", default=str(ROOT / "tests/fixtures/sympy"))
    ap.add_argument("--only", nargs="*", help="scene paths (default: all of SCENES)")
    a = ap.parse_args(argv)
    write_chain_scenes()
    out_dir = Path(a.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(SEED)
    start = time.time()
    for scene in SCENES:
        # One generator stream for every scene, consumed in SCENES order, so the states of a
        # scene do not depend on --only: each scene gets its own child generator.
        child = np.random.default_rng(rng.integers(2**63))
        if a.only and scene not in a.only:
            continue
        t0 = time.time()
        data = generate(scene, child)
        dest = out_dir / (Path(scene).stem + ".json")
        dest.write_text(json.dumps(data, indent=1) + "\n")
        print(f"{dest.relative_to(ROOT) if dest.is_relative_to(ROOT) else dest}: "
              f"{len(data['cases'])} cases, nq={len(data['coordinate_names'])}, "
              f"nu={len(data['speed_names'])}, {time.time() - t0:.1f} s", flush=True)
    print(f"total {time.time() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
