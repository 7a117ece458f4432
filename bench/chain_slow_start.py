#!/usr/bin/python3
"""Initial joint angles that start a stiff-spring chain on its slow manifold (to first order).

    /usr/bin/python3 bench/chain_slow_start.py SCENE.yaml [--kanesens build/kanesens]

For a chain whose first joint is free and whose other joints carry stiff springs
(scripts/gen_chain.py N --spring K --damper C --free-first), released from rest at the scene's
j1.q0, finds the small deflections q2..qN at which the stiff joints' accelerations vanish
(u = 0, so udot[1:] = 0): then the release does not excite the fast modes, and the motion is the
slow swing plus O(1/k) corrections. Newton with a finite-difference Jacobian on
`kanesens eom`. Prints the comma-separated q0 list for gen_chain.py --q0-list.
"""
import argparse
import json
import subprocess

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--kanesens", default="build/kanesens")
    ap.add_argument("--q1", type=float, default=0.5, help="first joint angle")
    a = ap.parse_args()

    def udot(q):
        out = subprocess.run([a.kanesens, "eom", a.scene, "--q=" + ",".join("%.17g" % x for x in q),
                              "--u=" + ",".join("0" for _ in q)], capture_output=True, text=True, check=True)
        return np.array(json.loads(out.stdout)["udot"])

    check = subprocess.run([a.kanesens, "check", a.scene], capture_output=True, text=True, check=True).stdout
    nq = int(check.split("nq = ")[1].split(",")[0])  # "degrees of freedom: 4 (nq = 4, nu = 4)"
    q = np.zeros(nq)
    q[0] = a.q1
    for _ in range(8):
        r = udot(q)[1:]
        if np.abs(r).max() < 1e-12:
            break
        J = np.zeros((len(r), len(r)))
        for j in range(len(r)):
            dq = q.copy()
            dq[1 + j] += 1e-7
            J[:, j] = (udot(dq)[1:] - r) / 1e-7
        q[1:] -= np.linalg.solve(J, r)
    print(",".join("%.10g" % x for x in q))


if __name__ == "__main__":
    main()
