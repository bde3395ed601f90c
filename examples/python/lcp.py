#!/usr/bin/python3
"""An LCP from Python: the KKT conditions of Hock-Schittkowski problem 35,

    min 9 - 8 x1 - 6 x2 - 4 x3 + 2 x1^2 + 2 x2^2 + x3^2 + 2 x1 x2 + 2 x1 x3
    s.t. x1 + x2 + 2 x3 <= 3,  x >= 0,

as  z = (x, lambda) >= 0  perp  M z + q >= 0  with  M = [H a; -a' 0],  q = (c; 3)
(solution x = (4/3, 7/9, 4/9), lambda = 2/9).  Run: PYTHONPATH=build/python /usr/bin/python3 lcp.py
"""
import numpy as np
import scipy.sparse as sp

import ncp

M = sp.csc_matrix(np.array([[4.0, 2.0, 2.0, 1.0],
                            [2.0, 4.0, 0.0, 1.0],
                            [2.0, 0.0, 2.0, 2.0],
                            [-1.0, -1.0, -2.0, 0.0]]))
q = np.array([-8.0, -6.0, -4.0, 3.0])


def main():
    z, summary = ncp.solve_lcp(M, q)
    print(summary)
    if not summary.is_solution_usable:
        raise SystemExit(f"no solution: {summary.message}")
    w = M @ z + q
    print("z =", z)
    print(f"min(z) = {z.min():.3e}, min(w) = {w.min():.3e}, |z'w| = {abs(z @ w):.3e}")
    return z, summary


if __name__ == "__main__":
    main()
