#!/usr/bin/python3
"""The four-bar of configs/four_bar.yaml at time t, from energy conservation and one quadrature.

An integrator-free reference for the crank-rocker: it has one degree of freedom and is
conservative (no damping, no drive), so along the closed-form assembly q2(q1), q3(q1) and the
velocity constraints u2 = k2(q1) u1, u3 = k3(q1) u1, T + V = E gives the crank rate as a function
of the crank angle alone,

    u1(q1) = ± sqrt(2 (E − V(q1)) / m(q1)),     m(q1) = 2 T(q(q1), [1, k2, k3]),

and time as a quadrature, t(q1) = ∫ dq1 / u1. The crank angle at t_end is found by whole periods
(one crank turn takes the same time every turn) plus Newton on the remaining angle
(d t / d q1 = 1 / u1). Everything is evaluated in mpmath at `dps` digits (30 by default);
T, V, g and A come from tests/sympy/four_bar_kane.py (SymPy, written by hand, no kanesens code).

Preconditions, checked: the linkage assembles at every crank angle without the coupler and rocker
lining up (a Grashof crank-rocker with strict inequalities), and the crank never stops
(E − V(q1) > 0 all the way round); otherwise the motion is no crank rotation and this does not
apply.

    state_at(t_end, parameters=None) -> (y, diagnostics)

y = [q1, q2, q3, u1, u2, u3] in kanesens's coordinates (crank absolute, coupler relative to the
crank, rocker absolute; u = q'), as floats. parameters override NOMINAL: the lengths, masses and
g of four_bar_kane.NOMINAL and the crank's initial angle th1 and rate w1 (the scene's names).

    /usr/bin/python3 tests/sympy/four_bar_quadrature.py --t-end 10 [--set r=0.25 ...] [--dps 30]

prints y, y0 and the diagnostics as JSON.
"""

from __future__ import annotations

import argparse
import functools
import json
import sys
from pathlib import Path

import mpmath

sys.path.insert(0, str(Path(__file__).resolve().parent))
import four_bar_kane as fb  # noqa: E402

# configs/four_bar.yaml: crank upright (th1 = pi/2, kept exact here) at w1 = 6 rad/s.
NOMINAL = {**fb.NOMINAL, "th1": "pi/2", "w1": 6.0}
STATE_NAMES = ["crank.q", "coupler.q", "rocker.q", "crank.u", "coupler.u", "rocker.u"]
SAMPLES = 360                       # crank angles scanned for the slowest point of a turn


@functools.cache
def _mechanics():
    """mpmath functions (q, u, p) -> [T, V] and (q, u, p) -> [A] (A does not depend on u)."""
    model = fb.kane_model()
    return (fb.lambdify(model, ("kinetic_energy", "potential_energy"), modules="mpmath"),
            fb.lambdify(model, ("velocity_matrix",), modules="mpmath"))


def _mpf(value):
    return mpmath.pi / 2 if value == "pi/2" else mpmath.mpf(repr(float(value)))


def state_at(t_end: float, parameters: dict | None = None, dps: int = 30):
    """y(t_end) = [q1, q2, q3, u1, u2, u3] (floats) and diagnostics; see the module docstring."""
    unknown = set(parameters or {}) - set(NOMINAL)
    if unknown:
        raise ValueError(f"unknown four-bar parameters {sorted(unknown)}; known: {list(NOMINAL)}")
    if t_end < 0:
        raise ValueError(f"t_end = {t_end} < 0")
    energies, constraint_matrix = _mechanics()
    with mpmath.workdps(dps):
        pd = {k: _mpf(v) for k, v in {**NOMINAL, **(parameters or {})}.items()}
        p = [pd[k] for k in fb.PARAMETERS]
        r, c, b, a = (pd[k] for k in "rcba")
        # The crank pin to rocker pivot distance spans [|a − r|, a + r]; the coupler and rocker
        # close the loop without lining up (A's dependent block singular) iff it stays inside (|c − b|, c + b).
        if not (abs(c - b) < abs(a - r) and a + r < c + b):
            raise ValueError(f"r, c, b, a = {float(r)}, {float(c)}, {float(b)}, {float(a)} is no crank-rocker "
                             "(needs |c − b| < |a − r| and a + r < c + b): the crank cannot turn all the way round")

        def state(q1, u1):
            q2, q3 = fb.assemble(q1, pd, lib=mpmath)
            m = mpmath.matrix(constraint_matrix([q1, q2, q3], [0, 0, 0], p)[0])
            # A_d [u2, u3] = −A_i u1 (Cramer's rule on the 2×2 dependent block)
            det = m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]
            k2 = (-m[0, 0] * m[1, 2] + m[0, 2] * m[1, 0]) / det
            k3 = (-m[0, 1] * m[1, 0] + m[0, 0] * m[1, 1]) / det
            return [q1, q2, q3], [u1, k2 * u1, k3 * u1]

        start, w1 = pd["th1"], pd["w1"]
        q, u = state(start, w1)
        y0 = q + u
        energy = sum(energies(q, u, p))

        def kinetic_left(q1):                      # E − V(q1) = T along the motion
            q, v = state(q1, 1)                     # v = u / u1: the effective mass is 2 T(q, v)
            kinetic, potential = energies(q, v, p)
            return energy - potential, 2 * kinetic

        def rate_squared(q1):                      # u1² at crank angle q1; its sign is that of E − V
            left, mass = kinetic_left(q1)
            return 2 * left / mass

        def speed(q1):                             # |u1| at crank angle q1
            return mpmath.sqrt(rate_squared(q1))

        # The slowest point of a turn: a scan, then golden-section refinement (a narrow dip
        # between two samples could hide a stop).
        xs = [start + 2 * mpmath.pi * i / SAMPLES for i in range(SAMPLES)]
        i = min(range(SAMPLES), key=lambda i: rate_squared(xs[i]))
        lo, hi = xs[i] - 2 * mpmath.pi / SAMPLES, xs[i] + 2 * mpmath.pi / SAMPLES
        ratio = (mpmath.sqrt(5) - 1) / 2
        for _ in range(60):
            x1, x2 = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
            if rate_squared(x1) < rate_squared(x2):
                hi = x2
            else:
                lo = x1
        slowest = (lo + hi) / 2
        if rate_squared(slowest) <= 0:           # w1 = 0 included: u1² = 0 at the start
            raise ValueError(f"the crank stops (E − V = {float(kinetic_left(slowest)[0]):.3e} J at crank angle "
                             f"{float(slowest):.4f} rad, w1 = {float(w1)} rad/s): no full rotation, the energy "
                             "quadrature does not apply")
        direction = mpmath.sign(w1)

        def elapsed(s0, s1):                       # time for the crank to turn from start + s0 to start + s1
            return mpmath.quad(lambda x: 1 / speed(start + direction * x), mpmath.linspace(s0, s1, 9),
                               method="gauss-legendre", error=True)

        period, period_error = elapsed(0, 2 * mpmath.pi)
        turns = int(mpmath.floor(t_end / period))
        rest = t_end - turns * period
        # Newton on elapsed(0, s) = rest (d elapsed / ds = 1 / |u1|), each step adding only the
        # quadrature over the last correction.
        s = rest / period * 2 * mpmath.pi
        t_s, ds = elapsed(0, s)[0], mpmath.inf
        while abs(ds) > mpmath.mpf(10) ** (5 - dps):
            ds = (t_s - rest) * speed(start + direction * s)
            t_s += elapsed(s, s - ds)[0]
            s -= ds
        q, u = state(start + direction * (2 * mpmath.pi * turns + s), direction * speed(start + direction * s))
        info = {"period_s": float(period), "period_quadrature_error": float(period_error), "turns": turns,
                "min_crank_rate": float(speed(slowest)), "min_crank_rate_at": float(slowest),
                "newton_last_step": float(abs(ds)), "energy": float(energy), "y0": [float(x) for x in y0],
                "dps": dps}
        return [float(x) for x in q + u], info


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--t-end", type=float, required=True)
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help=f"override a parameter ({', '.join(NOMINAL)}); repeatable")
    ap.add_argument("--dps", type=int, default=30, help="mpmath decimal digits")
    a = ap.parse_args()
    parameters = {}
    for item in a.set:
        name, sep, value = item.partition("=")
        if not sep:
            ap.error(f"--set {item}: expected NAME=VALUE")
        parameters[name] = float(value)
    y, info = state_at(a.t_end, parameters, a.dps)
    print(json.dumps({"t_end": a.t_end, "parameters": {**NOMINAL, **parameters}, "state_names": STATE_NAMES,
                      "y": y, **info}, indent=1))


if __name__ == "__main__":
    main()
