#!/usr/bin/env python3
"""Write tests/data/andrews_reference.csv: Andrews' squeezing mechanism at t = 0 and t = 0.03.

Two columns are copied from the test set (Mazzia, Magherini & Iavernaro, "Test Set for Initial
Value Problem Solvers", Release 2.3, Report 43/2006, Dept. of Mathematics, Univ. of Bari; problem
`andrews`, file andrews.f):
  y0         its consistent initial values (subroutine `init`): q0, q̇0 = 0, q̈0 and λ0;
  published  its reference solution at t = 0.03 (subroutine `solut`): PSIDE, rtol = atol = 1e-14.
The third is computed here, independently of kanesens:
  recomputed y(0.03) of the index-1 form of the test set's equations, integrated by SciPy's DOP853
             at rtol 1e-13, atol 1e-16; q̈ and λ solved from the augmented system at that state.

The test set's equations: M(q) q̈ = f(q, q̇) − G(q)ᵀλ, g(q) = 0, G = ∂g/∂q, q = (β, Θ, γ, Φ, δ, Ω,
ε). The index-1 form differentiates g twice: G q̈ = −(∂(G q̇)/∂q) q̇, derived here with SymPy.

    /usr/bin/python3 tests/data/andrews_reference.py > tests/data/andrews_reference.csv

It also prints, on stderr, the largest change against a run at rtol 1e-12 (an error estimate).
"""
import sys

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

P = dict(m1=0.04325, m2=0.00365, m3=0.02373, m4=0.00706, m5=0.07050, m6=0.00706, m7=0.05498,
         xa=-0.06934, ya=-0.00227, xb=-0.03635, yb=0.03273, xc=0.014, yc=0.072, c0=4530,
         I1=2.194e-6, I2=4.410e-7, I3=5.255e-6, I4=5.667e-7, I5=1.169e-5, I6=5.667e-7,
         I7=1.912e-5, d=0.028, da=0.0115, e=0.02, ea=0.01421, rr=0.007, ra=0.00092, l0=0.07785,
         ss=0.035, sa=0.01874, sb=0.01043, sc=0.018, sd=0.02, ta=0.02308, tb=0.00916, u=0.04,
         ua=0.01228, ub=0.00449, zf=0.02, zt=0.04, fa=0.01421, mom=0.033)

NAMES = (["q1_beta", "q2_Theta", "q3_gamma", "q4_Phi", "q5_delta", "q6_Omega", "q7_epsilon"]
         + [f"qdot{i}" for i in range(1, 8)] + [f"qddot{i}" for i in range(1, 8)]
         + [f"lambda{i}" for i in range(1, 7)])

# The test set's subroutine `init` (30 digits as published); y = (q, q̇, q̈, λ).
Y0 = ["-0.0617138900142764496358948458001", "0", "0.455279819163070380255912382449",
      "0.222668390165885884674473185609", "0.487364979543842550225598953530",
      "-0.222668390165885884674473185609", "1.23054744454982119249735015568"] + ["0"] * 7 + [
      "14222.4439199541138705911625887", "-10666.8329399655854029433719415"] + ["0"] * 5 + [
      "98.5668703962410896057654982170", "-6.12268834425566265503114393122"] + ["0"] * 4

# The test set's subroutine `solut` (reference solution at t = 0.03), as published.
PUBLISHED = [
    "0.1581077119629904e+2", "-0.1575637105984298e+2", "0.4082224013073101e-1",
    "-0.5347301163226948e+0", "0.5244099658805304e+0", "0.5347301163226948e+0",
    "0.1048080741042263e+1", "0.1139920302151208e+4", "-0.1424379294994111e+4",
    "0.1103291221937134e+2", "0.1929337464421385e+2", "0.5735699284790808e+0",
    "-0.1929337464421385e+2", "0.3231791658026955e+0", "-0.2463176316945196e+5",
    "0.5185037701610329e+5", "0.3241025686413781e+6", "0.5667493645176213e+6",
    "0.1674362929479361e+5", "-0.5667493645176222e+6", "0.9826520791458422e+4",
    "0.1991753333731910e+3", "-0.2975531228015052e+2", "0.2306654119098399e+2",
    "0.3145271365475927e+2", "0.2264249232082739e+2", "0.1161740700019673e+2"]


def model():
    """Lambdified M(q), f(q, v), G(q) and the bias −(∂(G v)/∂q) v of the test set."""
    q = sp.symbols("q1:8")
    v = sp.symbols("v1:8")
    b, th, g, phi, de, om, ep = q
    p = {k: sp.Float(repr(x), 30) for k, x in P.items()}
    ee, zz = p["e"] - p["ea"], p["zf"] - p["fa"]
    M = sp.zeros(7, 7)
    M[0, 0] = (p["m1"] * p["ra"]**2 + p["m2"] * (p["rr"]**2 - 2 * p["da"] * p["rr"] * sp.cos(th)
               + p["da"]**2) + p["I1"] + p["I2"])
    M[1, 0] = M[0, 1] = p["m2"] * (p["da"]**2 - p["da"] * p["rr"] * sp.cos(th)) + p["I2"]
    M[1, 1] = p["m2"] * p["da"]**2 + p["I2"]
    M[2, 2] = p["m3"] * (p["sa"]**2 + p["sb"]**2) + p["I3"]
    M[3, 3] = p["m4"] * ee**2 + p["I4"]
    M[4, 3] = M[3, 4] = p["m4"] * (ee**2 + p["zt"] * ee * sp.sin(phi)) + p["I4"]
    M[4, 4] = (p["m4"] * (p["zt"]**2 + 2 * p["zt"] * ee * sp.sin(phi) + ee**2)
               + p["m5"] * (p["ta"]**2 + p["tb"]**2) + p["I4"] + p["I5"])
    M[5, 5] = p["m6"] * zz**2 + p["I6"]
    M[6, 5] = M[5, 6] = p["m6"] * (zz**2 - p["u"] * zz * sp.sin(om)) + p["I6"]
    M[6, 6] = (p["m6"] * (zz**2 - 2 * p["u"] * zz * sp.sin(om) + p["u"]**2)
               + p["m7"] * (p["ua"]**2 + p["ub"]**2) + p["I6"] + p["I7"])
    xd = p["sd"] * sp.cos(g) + p["sc"] * sp.sin(g) + p["xb"]
    yd = p["sd"] * sp.sin(g) - p["sc"] * sp.cos(g) + p["yb"]
    L = sp.sqrt((xd - p["xc"])**2 + (yd - p["yc"])**2)
    F = -p["c0"] * (L - p["l0"]) / L
    Fx, Fy = F * (xd - p["xc"]), F * (yd - p["yc"])
    k2, k4, k6 = p["m2"] * p["da"] * p["rr"], p["m4"] * p["zt"] * ee, p["m6"] * p["u"] * zz
    f = sp.Matrix([
        p["mom"] - k2 * v[1] * (v[1] + 2 * v[0]) * sp.sin(th),
        k2 * v[0]**2 * sp.sin(th),
        Fx * (p["sc"] * sp.cos(g) - p["sd"] * sp.sin(g)) + Fy * (p["sd"] * sp.cos(g) + p["sc"] * sp.sin(g)),
        k4 * v[4]**2 * sp.cos(phi),
        -k4 * v[3] * (v[3] + 2 * v[4]) * sp.cos(phi),
        -k6 * v[6]**2 * sp.cos(om),
        k6 * v[5] * (v[5] + 2 * v[6]) * sp.cos(om)])
    x = p["rr"] * sp.cos(b) - p["d"] * sp.cos(b + th)
    y = p["rr"] * sp.sin(b) - p["d"] * sp.sin(b + th)
    gq = sp.Matrix([
        x - p["ss"] * sp.sin(g) - p["xb"],
        y + p["ss"] * sp.cos(g) - p["yb"],
        x - p["e"] * sp.sin(phi + de) - p["zt"] * sp.cos(de) - p["xa"],
        y + p["e"] * sp.cos(phi + de) - p["zt"] * sp.sin(de) - p["ya"],
        x - p["zf"] * sp.cos(om + ep) - p["u"] * sp.sin(ep) - p["xa"],
        y - p["zf"] * sp.sin(om + ep) + p["u"] * sp.cos(ep) - p["ya"]])
    G = gq.jacobian(q)
    vv = sp.Matrix(v)
    bias = -(G * vv).jacobian(q) * vv
    fn = lambda e: sp.lambdify((q, v), e, "numpy")
    return fn(M), fn(f), fn(G), fn(bias), fn(gq)


def solve(M, f, G, bias, _g, q, v):
    """q̈ and λ of M q̈ + Gᵀλ = f, G q̈ = bias (the test set's sign of λ)."""
    A = np.zeros((13, 13))
    A[:7, :7] = M(q, v)
    Gq = G(q, v)
    A[:7, 7:] = Gq.T
    A[7:, :7] = Gq
    rhs = np.concatenate([np.ravel(f(q, v)), np.ravel(bias(q, v))])
    x = np.linalg.solve(A, rhs)
    return x[:7], x[7:]


def end_state(fns, rtol):
    def rhs(_t, y):
        a, _ = solve(*fns, y[:7], y[7:])
        return np.concatenate([y[7:], a])

    y0 = np.array([float(s) for s in Y0[:14]])
    sol = solve_ivp(rhs, (0.0, 0.03), y0, method="DOP853", rtol=rtol, atol=1e-16)
    assert sol.success, sol.message
    y = sol.y[:, -1]
    a, lam = solve(*fns, y[:7], y[7:])
    return np.concatenate([y, a, lam]), np.abs(np.ravel(fns[4](y[:7], y[7:]))).max()


def main():
    fns = model()
    y, g_end = end_state(fns, 1e-13)
    y_loose, _ = end_state(fns, 1e-12)
    est = np.abs(y - y_loose) / np.maximum(np.abs(y), 1e-300)
    print(f"max relative change against rtol 1e-12: positions {est[:7].max():.1e}, velocities "
          f"{est[7:14].max():.1e}, accelerations {est[14:21].max():.1e}, multipliers "
          f"{est[21:].max():.1e}; |g(q(0.03))| = {g_end:.1e} m", file=sys.stderr)
    out = sys.stdout
    out.write(
        "# Andrews' squeezing mechanism, problem `andrews` of the Test Set for IVP Solvers (Mazzia,\n"
        "# Magherini & Iavernaro, Release 2.3, Report 43/2006, Univ. of Bari; Fortran andrews.f).\n"
        "# y = (q[1..7], qdot[1..7], qddot[1..7], lambda[1..6]), q = (beta, Theta, gamma, Phi, delta,\n"
        "# Omega, epsilon) in rad, the test set's multiplier sign: M qddot = f - G^T lambda.\n"
        "# y0: the test set's consistent initial values at t = 0 (subroutine init, as published).\n"
        "# published: the test set's reference solution at t = 0.03 (subroutine solut; PSIDE,\n"
        "#   rtol = atol = 1e-14).\n"
        "# recomputed: y(0.03) from tests/data/andrews_reference.py (the test set's equations in\n"
        "#   index-1 form, SciPy DOP853 at rtol 1e-13), which writes this file.\n"
        "index,name,y0,published,recomputed\n")
    for i in range(27):
        out.write(f"{i + 1},{NAMES[i]},{Y0[i]},{PUBLISHED[i]},{y[i]:.17g}\n")


if __name__ == "__main__":
    main()
