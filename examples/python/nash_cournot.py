#!/usr/bin/python3
"""A Nash-Cournot equilibrium as an NCP (Murphy, Sherali and Soyster 1982; Harker 1988).

Five firms choose outputs q_i >= 0 [units]; the inverse demand is
    p(Q) = 5000^(1/gamma) Q^(-1/gamma),  Q = sum_i q_i,  gamma = 1.1,
firm i's cost is  f_i(q_i) = c_i q_i + beta_i / (beta_i + 1) L_i^(1/beta_i) q_i^((beta_i+1)/beta_i).
Each firm maximizes its profit q_i p(Q) - f_i(q_i) given the others' outputs; the
first-order conditions of all five are the NCP
    q >= 0,  F(q) >= 0,  q'F(q) = 0,   F_i(q) = f_i'(q_i) - p(Q) - q_i p'(Q).
F is defined only for q >= 0 with Q > 0: outside, F returns None and the line search
shortens the step.  Solution (Harker 1988): q = (15.4293, 12.4986, 9.6635, 7.1651, 5.1326).
Run: PYTHONPATH=build/python /usr/bin/python3 nash_cournot.py
"""
import numpy as np

import ncp

C = np.array([10.0, 8.0, 6.0, 4.0, 2.0])  # marginal cost constants c_i
L = np.array([5.0, 5.0, 5.0, 5.0, 5.0])
BETA = np.array([1.2, 1.1, 1.0, 0.9, 0.8])
GAMMA = 1.1  # demand elasticity


def price(Q):
    return 5000.0 ** (1.0 / GAMMA) * Q ** (-1.0 / GAMMA)


def F(q):
    if not np.all(q >= 0.0) or q.sum() <= 0.0:
        return None
    Q = q.sum()
    p = price(Q)
    dp = -p / (GAMMA * Q)  # p'(Q)
    return C + (L * q) ** (1.0 / BETA) - p - q * dp


def J(q):
    """dF_i/dq_j = delta_ij (f_i'' - p') - p' - q_i p''  (dense 5 x 5)."""
    if not np.all(q >= 0.0) or q.sum() <= 0.0:
        return None
    Q = q.sum()
    p = price(Q)
    dp = -p / (GAMMA * Q)
    d2p = (1.0 + 1.0 / GAMMA) * p / (GAMMA * Q * Q)
    f2 = L ** (1.0 / BETA) / BETA * q ** (1.0 / BETA - 1.0)  # f_i''(q_i)
    if not np.all(np.isfinite(f2)):
        return None
    return np.tile((-dp - q * d2p)[:, None], (1, 5)) + np.diag(f2 - dp)


def main(start=10.0, **options):
    q, summary = ncp.solve_ncp(F, J, np.full(5, start), **options)
    print(summary)
    if not summary.is_solution_usable:
        raise SystemExit(f"no equilibrium: {summary.message}")
    Fq = F(q)
    print("outputs q =", np.round(q, 4), " price p =", round(price(q.sum()), 4))
    print(f"natural residual ||min(q, F(q))||_inf = {np.abs(np.minimum(q, Fq)).max():.3e}")
    return q, summary


if __name__ == "__main__":
    main()
