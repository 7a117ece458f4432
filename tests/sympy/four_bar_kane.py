"""The four-bar crank-rocker of configs/four_bar.yaml, written directly in SymPy KanesMethod.

Independent of kanesens and of kane_reference.py (which has no constraints): the geometry is
written out here by hand, in kanesens's coordinates so that the numbers can be compared:

    O = (0, 0) —— crank (r) —— P —— coupler (c) —— Q —— rocker (b) —— B = (a, 0)

* q1 = crank angle from world x, q2 = coupler angle relative to the crank, q3 = rocker angle
  from world x (at B); u_i = q_i' (joint rates).
* Independent speed u1, dependent speeds u2, u3. Configuration constraints: the loop closure
  g(q) = Q − R = 0 (world x, y; R = rocker tip); velocity constraints: g' with q' = u, which
  is linear in u, A(q) u = 0.
* Uniform rods along their body x axes, mass centers at the middles, central inertia m L²/12
  about z; gravity −g y on the mass centers.

KanesMethod's ``mass_matrix``/``forcing`` with dependent speeds are 3×3/3: the one reduced
dynamical equation (for u1') stacked on the two differentiated velocity constraints
A u' + A' u = 0, so ``solve(M, f)`` gives all three u' at a consistent state.

Used by four_bar_quadrature.py (the energy-quadrature reference), bench/bench_peers_fourbar_sympy.py
and tests/python/test_fourbar_vs_sympy.py.
"""

from __future__ import annotations

import math

import sympy as sp
from sympy.physics.mechanics import (KanesMethod, Point, ReferenceFrame, RigidBody, dynamicsymbols,
                                     inertia, msubs)

# Numerical parameters of configs/four_bar.yaml (lengths m, masses kg, g m/s², crank start).
NOMINAL = {"r": 0.2, "c": 0.7, "b": 0.5, "a": 0.6, "m1": 1.0, "m2": 2.0, "m3": 1.5, "g": 9.81}
PARAMETERS = tuple(NOMINAL)


def kane_model():
    """Frames, points, rods, loads and the KanesMethod object (before kanes_equations, so that
    the two stages can be timed separately); returns them in a dict."""
    q1, q2, q3 = dynamicsymbols("q1:4")
    u1, u2, u3 = dynamicsymbols("u1:4")
    r, c, b, a, m1, m2, m3, g = sp.symbols(" ".join(PARAMETERS), positive=True)
    t = dynamicsymbols._t

    N = ReferenceFrame("N")
    crank = N.orientnew("crank", "Axis", [q1, N.z])
    coupler = crank.orientnew("coupler", "Axis", [q2, crank.z])
    rocker = N.orientnew("rocker", "Axis", [q3, N.z])
    crank.set_ang_vel(N, u1 * N.z)
    coupler.set_ang_vel(crank, u2 * crank.z)
    rocker.set_ang_vel(N, u3 * N.z)

    O = Point("O")
    O.set_vel(N, 0)
    B = O.locatenew("B", a * N.x)
    B.set_vel(N, 0)
    G1 = O.locatenew("G1", r / 2 * crank.x)
    P = O.locatenew("P", r * crank.x)
    G2 = P.locatenew("G2", c / 2 * coupler.x)
    Q = P.locatenew("Q", c * coupler.x)
    G3 = B.locatenew("G3", b / 2 * rocker.x)
    R = B.locatenew("R", b * rocker.x)
    for pt, base, frame in ((G1, O, crank), (P, O, crank), (G2, P, coupler), (Q, P, coupler),
                            (G3, B, rocker), (R, B, rocker)):
        pt.v2pt_theory(base, N, frame)

    loop = Q.pos_from(O) - R.pos_from(O)
    closure = sp.Matrix([loop.dot(N.x), loop.dot(N.y)])
    qdot_to_u = {q1.diff(t): u1, q2.diff(t): u2, q3.diff(t): u3}
    velocity = msubs(closure.diff(t), qdot_to_u)

    rods = [RigidBody(name, G, frame, m, (inertia(frame, 0, 0, m * L**2 / 12), G))
            for name, G, frame, m, L in (("crank", G1, crank, m1, r), ("coupler", G2, coupler, m2, c),
                                         ("rocker", G3, rocker, m3, b))]
    loads = [(G, -m * g * N.y) for G, m in ((G1, m1), (G2, m2), (G3, m3))]
    kane = KanesMethod(N, q_ind=[q1], u_ind=[u1], kd_eqs=[q1.diff(t) - u1, q2.diff(t) - u2, q3.diff(t) - u3],
                       q_dependent=[q2, q3], configuration_constraints=list(closure),
                       u_dependent=[u2, u3], velocity_constraints=list(velocity))
    energy_kinetic = sum(rod.kinetic_energy(N) for rod in rods)
    energy_potential = sum(m * g * G.pos_from(O).dot(N.y) for G, m in ((G1, m1), (G2, m2), (G3, m3)))
    return {"kane": kane, "bodies": rods, "loads": loads, "q": [q1, q2, q3], "u": [u1, u2, u3],
            "p": [r, c, b, a, m1, m2, m3, g], "closure": closure,
            "velocity_matrix": velocity.jacobian([u1, u2, u3]),
            "kinetic_energy": energy_kinetic, "potential_energy": energy_potential}


def equations(model):
    """Kane's equations: fills model['mass_matrix'], model['forcing'] (3×3, 3, see above)."""
    model["kane"].kanes_equations(model["bodies"], model["loads"])
    model["mass_matrix"] = model["kane"].mass_matrix
    model["forcing"] = model["kane"].forcing
    return model


def lambdify(model, names=("mass_matrix", "forcing"), modules="numpy"):
    """One function (q, u, p) -> [model[name] for name in names], through plain symbols
    (lambdify does not take functions of t as arguments), with common subexpressions shared."""
    qs, us = sp.symbols("qq1:4"), sp.symbols("uu1:4")
    sub = dict(zip(model["q"], qs))
    sub.update(zip(model["u"], us))
    exprs = [msubs(model[n], sub) for n in names]
    return sp.lambdify([qs, us, model["p"]], exprs, modules=modules, cse=(modules == "numpy"))


def assemble(q1, p, elbow=1, lib=math):
    """Closed-form assembly: q2, q3 with the loop closed at crank angle q1 (elbow = +1 is the
    branch of configs/four_bar.yaml's phi0). lib = math or mpmath (for the quadrature reference).
    The coupler's absolute angle is the principal one, so q2 = phi − q1 carries the crank's turns."""
    r, c, b, a = (p[k] for k in "rcba")
    px, py = r * lib.cos(q1), r * lib.sin(q1)
    dx, dy = a - px, -py                          # P -> B
    L = lib.sqrt(dx * dx + dy * dy)
    phi = lib.atan2(dy, dx) + elbow * lib.acos((c * c + L * L - b * b) / (2 * c * L))
    qx, qy = px + c * lib.cos(phi), py + c * lib.sin(phi)
    return phi - q1, lib.atan2(qy, qx - a)
