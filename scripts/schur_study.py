#!/usr/bin/env python3
"""How well the bending step's Newton system solves through its multipliers alone (issue 24, a formulation tried).

The direct solver's bending step solves a 3x3-block pentadiagonal system in the positions a Newton iteration.
Written with the multipliers as unknowns, H = A (x) I3 + C^T diag(1 / alpha') C, where A = M + D^T K D is scalar
(mass, the bending joints, the segments' geometric stiffness taken isotropic, its axial part moved into alpha'),
D the segments' differences and C = N (D (x) I3) their directions. Its Schur complement on the multipliers is

    S = N (T (x) I3) N^T + alpha',   T = D A^-1 D^T = Q (I + K Q)^-1,   Q = D M^-1 D^T

(Q and K tridiagonal: T applies in O(m)), so S_kl = T_kl (n_k . n_l). On a straight cable S = T + alpha', which
solves in O(m) too; this script measures how many conjugate-gradient iterations S takes with that straight
cable's S as the preconditioner, on arcs of decreasing radius with the demo's cable (0.1 m segments, 0.01 kg
particles, a 5 ms step, EA 1e5 N, EI 0.2 N m^2) and the paper's noise on the positions. Dense numpy, for the
count only; its own check is the identity T = D A^-1 D^T to rounding.

Usage: /usr/bin/python3 scripts/schur_study.py (numpy: python3-numpy)
"""
import numpy as np


def arc(count, segment, radius, noise, rng):
    """Particles on an arc of `radius` (inf: straight), each moved by up to `noise` per axis."""
    s = np.arange(count) * segment
    if np.isinf(radius):
        points = np.stack([s, 0.0 * s, 0.0 * s], 1)
    else:
        points = np.stack([radius * np.sin(s / radius), radius * (1.0 - np.cos(s / radius)), 0.0 * s], 1)
    return points + noise * rng.uniform(-1.0, 1.0, points.shape)


def schur(points, segment, mass, step, ea, ei, tension):
    """S, the straight cable's preconditioner (applied as a function) and the identity's relative error; both ends
    pinned, stiffness in the solver's units (times h^2, against the masses)."""
    n = len(points)
    m = n - 1
    d = points[1:] - points[:-1]
    length = np.linalg.norm(d, axis=1)
    directions = d / length[:, None]
    w = np.full(n, 1.0 / mass)
    w[[0, n - 1]] = 0.0
    free = w > 0.0
    axial = step * step * ea / segment * np.ones(m)
    geometric = step * step * tension / length
    joint = step * step * ei / segment
    diff = np.zeros((m, n))
    for k in range(m):
        diff[k, k], diff[k, k + 1] = -1.0, 1.0
    k_mat = np.diag(geometric)
    for j in range(m - 1):
        v = np.zeros(m)
        v[j], v[j + 1] = -1.0 / segment, 1.0 / segment
        k_mat += joint * np.outer(v, v)
    a_mat = np.diag(np.full(free.sum(), mass)) + diff[:, free].T @ k_mat @ diff[:, free]
    t_direct = diff[:, free] @ np.linalg.solve(a_mat, diff[:, free].T)
    q_mat = diff @ np.diag(w) @ diff.T
    t_mat = q_mat @ np.linalg.inv(np.eye(m) + k_mat @ q_mat)
    identity_error = np.abs(t_mat - t_direct).max() / np.abs(t_direct).max()
    alpha = np.diag(1.0 / (axial - geometric))
    s_mat = t_mat * (directions @ directions.T) + alpha
    # (T + alpha')^-1 r = (I + K Q) (Q + alpha' + alpha' K Q)^-1 r
    banded = q_mat + alpha + alpha @ k_mat @ q_mat
    lift = np.eye(m) + k_mat @ q_mat
    return s_mat, (lambda r: lift @ np.linalg.solve(banded, r)), identity_error


def conjugate_gradients(matrix, rhs, precondition, tolerance, limit=200):
    """Iterations of preconditioned CG until |r| <= tolerance |b|."""
    x = np.zeros_like(rhs)
    r = rhs.copy()
    z = precondition(r)
    p = z.copy()
    rz = r @ z
    for iteration in range(1, limit + 1):
        ap = matrix @ p
        a = rz / (p @ ap)
        x += a * p
        r -= a * ap
        if np.linalg.norm(r) <= tolerance * np.linalg.norm(rhs):
            return iteration
        z = precondition(r)
        rz, previous = r @ z, rz
        p = z + rz / previous * p
    return limit


def main():
    rng = np.random.default_rng(1)
    print("radius [m]  tension [N]  identity error  CG iterations to 1e-6 (straight-cable preconditioner / diagonal)")
    for radius, tension in ((np.inf, 2.0), (5.0, 1.0), (1.0, 0.5), (0.5, 0.1), (0.3, 0.1)):
        points = arc(101, 0.1, radius, 6.3e-5, rng)
        s_mat, straight, error = schur(points, 0.1, 0.01, 0.005, 1e5, 0.2, tension)
        rhs = rng.standard_normal(len(s_mat))
        with_straight = conjugate_gradients(s_mat, rhs, straight, 1e-6)
        plain = conjugate_gradients(s_mat, rhs, lambda r: r / np.diag(s_mat), 1e-6)
        print(f"{radius:10.1f}  {tension:11.1f}  {error:14.1e}  {with_straight:3d} / {plain:3d}")


if __name__ == "__main__":
    main()
