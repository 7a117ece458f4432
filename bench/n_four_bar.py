#!/usr/bin/python3
"""The IFToMM multibody benchmark A02, the N four-bar mechanism, as a kanesens scene and study.

N four-bar windows side by side: 2N+1 uniform rods of length L = 1 m and mass 1 kg under gravity
(−y). N+1 cranks turn about ground pivots at x = 0, L, …, N L; coupler i hangs from the tip of
crank i (a revolute) and is closed onto the tip of crank i+1 by a `coincident` constraint (2 rows
each in the plane): 2N+1 speeds, 2N rows, 1 degree of freedom. The cranks start at 45° and point
B0 (the tip of crank 0) moves at +1 m/s along x (so the crank rate is −1/(L sin 45°)). Twice per
half-swing every link is horizontal: there the constraint rows lose rank N and the mechanism
instantaneously has N+1 degrees of freedom (the benchmark's singular configurations).

Because every window stays a parallelogram, all cranks turn by the same angle φ(t) and every
coupler translates: the motion is that of one degree of freedom with
    T = ½ J φ̇²,  J = (N+1) m L²/3 + N m L²,
    V = G sin φ,  G = ((N+1)/2 + N) m g L,
so φ̈ = −(G/J) cos φ, a pendulum; `exact_solution` integrates it to round-off.

    /usr/bin/python3 bench/n_four_bar.py N --scene OUT.yaml [--study OUT_study.yaml --end 20 ...]
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

L, MASS, G = 1.0, 1.0, 9.81
PHI0 = math.pi / 4
PHIDOT0 = -1.0 / (L * math.sin(PHI0))  # B0 moves at +1 m/s along x


def scene_yaml(n: int) -> str:
    """The scene of `n` windows (n ≥ 1)."""
    if n < 1:
        raise ValueError("n must be at least 1")
    out = [f"# IFToMM benchmark A02, the N four-bar mechanism with N = {n} (bench/n_four_bar.py {n}).",
           "# Cranks crank0..crank%d turn about ground pivots at x = 0, L, ...; coupler i hangs from the" % n,
           "# tip of crank i and is closed onto the tip of crank i+1. All rods: length L, mass m, along x.",
           "kanesens: 1",
           "scene:",
           f"  name: n_four_bar_{n}",
           "  gravity: [0, -9.81, 0]",
           "  parameters:",
           "    L: 1.0",
           "    m: 1.0",
           "    phi0: \"pi/4\"          # initial crank angle from +x",
           "    w0: \"-1/(L*sin(phi0))\"  # crank rate: the tip of crank0 moves at +1 m/s along x",
           "  bodies:"]
    for i in range(n + 1):
        out.append(f"    - {{name: crank{i}, mass: m, inertia: {{shape: rod, length: L, axis: x}}}}")
    for i in range(n):
        out.append(f"    - {{name: coupler{i}, mass: m, inertia: {{shape: rod, length: L, axis: x}}}}")
    out.append("  joints:")
    for i in range(n + 1):
        out.append(f"    - {{name: crank{i}, type: revolute, parent: ground, child: crank{i}, axis: [0, 0, 1],")
        out.append(f"       parent_point: [\"{i}*L\", 0, 0], child_point: [\"-L/2\", 0, 0], q0: phi0, u0: w0}}")
    for i in range(n):
        out.append(f"    - {{name: coupler{i}, type: revolute, parent: crank{i}, child: coupler{i}, axis: [0, 0, 1],")
        out.append("       parent_point: [\"L/2\", 0, 0], child_point: [\"-L/2\", 0, 0], q0: \"-phi0\", u0: \"-w0\"}")
    out.append("  constraints:")
    for i in range(n):
        out.append(f"    - {{name: loop{i}, type: coincident, body_a: coupler{i}, point_a: [\"L/2\", 0, 0],")
        out.append(f"       body_b: crank{i + 1}, point_b: [\"L/2\", 0, 0]}}")
    return "\n".join(out) + "\n"


def study_yaml(scene: str, end: float, outputs: int, method: str, rtol: float, atol: float,
               formulation: str = "multipliers") -> str:
    return (f"kanesens: 1\nscene: {scene}\n"
            f"time: {{end: {end}, outputs: {outputs}}}\n"
            f"solver: {{method: {method}, rtol: {rtol:.1e}, atol: {atol:.1e},\n"
            f"         constraints: {{formulation: {formulation}, stabilization: projection}}}}\n")


def exact_solution(n: int, times):
    """φ(t) and φ̇(t) of the 1-DOF reduction at `times` (SciPy's DOP853 at rtol 1e-13)."""
    from scipy.integrate import solve_ivp
    j = (n + 1) * MASS * L * L / 3 + n * MASS * L * L
    g = ((n + 1) / 2 + n) * MASS * G * L
    sol = solve_ivp(lambda t, y: [y[1], -(g / j) * math.cos(y[0])], (0.0, float(times[-1])),
                    [PHI0, PHIDOT0], method="DOP853", rtol=1e-13, atol=1e-14, t_eval=times)
    return sol.y[0], sol.y[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", type=int, help="number of four-bar windows (N ≥ 1)")
    ap.add_argument("--scene", type=Path, required=True, help="write the scene YAML here")
    ap.add_argument("--study", type=Path, help="also write a study of the scene here")
    ap.add_argument("--end", type=float, default=20.0)
    ap.add_argument("--outputs", type=int, default=401)
    ap.add_argument("--method", default="bdf")
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--atol", type=float, default=1e-10)
    ap.add_argument("--formulation", default="multipliers", choices=["multipliers", "embedding"])
    a = ap.parse_args()
    a.scene.write_text(scene_yaml(a.n))
    if a.study:
        a.study.write_text(study_yaml(str(a.scene.resolve()), a.end, a.outputs, a.method, a.rtol, a.atol,
                                      a.formulation))


if __name__ == "__main__":
    main()
