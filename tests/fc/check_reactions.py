#!/usr/bin/python3
"""Independent check of fc-solve's reactions: reads the Siconos .dat problem itself
(dense storage), recomputes Siconos' natural-map error with numpy and exits 1 above the
tolerance. Usage: check_reactions.py PROBLEM.dat REACTIONS.txt TOLERANCE"""
import sys
import numpy as np


def read_dat(path):
    v = [float(x) for x in open(path).read().split()]
    d, nc, storage = int(v[0]), int(v[1]), int(v[2])
    n = d * nc
    assert storage == 0, "the checker reads dense storage only"
    # size0 size1, then m n, then the entries column by column
    assert int(v[3]) == n and int(v[5]) == n
    k = 7
    W = np.array(v[k:k + n * n]).reshape((n, n), order="F")
    k += n * n
    q = np.array(v[k:k + n])
    mu = np.array(v[k + n:k + n + nc])
    return d, nc, W, q, mu


def project(z, mu):
    zn, zt = z[0], z[1:]
    t = np.linalg.norm(zt)
    if t <= mu * zn:
        return z
    if mu * t <= -zn:
        return np.zeros_like(z)
    a = (zn + mu * t) / (1 + mu * mu)
    return np.concatenate(([a], a * mu * zt / t))


def main():
    d, nc, W, q, mu = read_dat(sys.argv[1])
    r = np.loadtxt(sys.argv[2])
    tol = float(sys.argv[3])
    assert r.shape == (d * nc,), f"expected {d * nc} reactions, got {r.shape}"
    u = W @ r + q
    err = 0.0
    for a in range(nc):
        ra, ua = r[a * d:(a + 1) * d], u[a * d:(a + 1) * d]
        uhat = ua.copy()
        uhat[0] += mu[a] * np.linalg.norm(ua[1:])
        e = ra - project(ra - uhat, mu[a])
        err += e @ e
    err = np.sqrt(err) / (1 + np.linalg.norm(q))
    print(f"recomputed natural-map error {err:.3e} (tolerance {tol:.1e})")
    sys.exit(0 if err <= tol else 1)


main()
