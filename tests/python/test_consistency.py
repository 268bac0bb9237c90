"""The physically consistent least squares (exoid.consistent_least_squares, Eigen's log-barrier
interior point) against an independent solver: cvxopt's cone QP, from Debian, on the same convex
problem written as a second-order cone program."""
import numpy as np
import pytest

import exoid

cvxopt = pytest.importorskip("cvxopt")
from cvxopt import matrix, solvers  # noqa: E402

LT = 0.45
NAMES = exoid.param_names()
I = {n: k for k, n in enumerate(NAMES)}


def cvxopt_solution(H, y, lt):
    """min ||H x - y||^2 s.t. fc1, fv1, fc2, fv2, Js >= 0, Jt - Js >= 0 and the rotated cone
    (Jt - Js) Js >= lt^2 (Mxs^2 + Mys^2), i.e. ||(2 lt Mxs, 2 lt Mys, Jt - 2 Js)|| <= Jt."""
    d = 1.0 / np.linalg.norm(H, axis=0)  # column scaling: x = d z
    Hs = H * d
    P = Hs.T @ Hs
    q = -Hs.T @ y
    rows, h = [], []
    for name in ("fc1", "fv1", "fc2", "fv2", "Js"):  # -x <= 0
        g = np.zeros(10); g[I[name]] = -1.0; rows.append(g); h.append(0.0)
    g = np.zeros(10); g[I["Jt"]] = -1.0; g[I["Js"]] = 1.0; rows.append(g); h.append(0.0)
    cone = np.zeros((4, 10))
    cone[0, I["Jt"]] = -1.0
    cone[1, I["Mxs"]] = -2.0 * lt
    cone[2, I["Mys"]] = -2.0 * lt
    cone[3, I["Jt"]] = -1.0
    cone[3, I["Js"]] = 2.0
    G = np.vstack([np.array(rows), cone]) * d
    hh = np.concatenate([h, np.zeros(4)])
    solvers.options.update(show_progress=False, abstol=1e-10, reltol=1e-10, feastol=1e-10, maxiters=500)
    sol = solvers.coneqp(matrix(P), matrix(q), matrix(G), matrix(hh), dims={"l": 6, "q": [4], "s": []})
    assert sol["status"] == "optimal", sol["status"]
    # How far cvxopt's answer may be from the optimum: its duality gap (<= abstol) bounds the excess
    # cost, and an excess cost e moves z by at most sqrt(2 e / lambda_min(P)).
    tol_z = np.sqrt(2.0 * max(sol["gap"], 1e-16) / np.linalg.eigvalsh(P)[0])
    return d * np.array(sol["x"]).ravel(), d.max() * tol_z


def problem(x_true, noise, seed, rows=400):
    rng = np.random.default_rng(seed)
    H = rng.standard_normal((rows, 10))
    return H, H @ x_true + noise * rng.standard_normal(rows)


def nominal():
    return np.array([5.83, 2.6, 3.4545, 1.5, 0.6, 1.28, -0.32, 0.5952, 0.35, 0.25])


def test_active_cone_and_bound_match_cvxopt():
    # A shank whose first moment is too large for its inertia, and knee friction at zero: LS
    # violates the cone and fv2 >= 0; both solvers must find the same constrained optimum.
    x = nominal()
    x[I["Jt"]] = x[I["Js"]] + 0.5 * LT**2 * (x[I["Mxs"]] ** 2 + x[I["Mys"]] ** 2) / x[I["Js"]]
    x[I["fv2"]] = -0.05
    H, y = problem(x, 1e-3, 7)
    ours = exoid.consistent_least_squares(H, y, LT)
    ref, tol = cvxopt_solution(H, y, LT)
    assert ours["constrained"]
    # Ours stops at a relative gap of 1e-14 of ||y||^2, far inside cvxopt's: cvxopt's bound decides.
    np.testing.assert_allclose(ours["x"], ref, rtol=0, atol=tol)
    active = {c["condition"] for c in ours["checks"] if c["active"]}
    assert "(Jt - Js) Js >= Lt^2 (Mxs^2 + Mys^2)" in active and "fv2 >= 0" in active, active


@pytest.mark.parametrize("seed", range(5))
def test_random_violations_match_cvxopt(seed):
    rng = np.random.default_rng(100 + seed)
    x = 0.2 * rng.standard_normal(10)
    H, y = problem(x, 0.05, 200 + seed, rows=80)
    ours = exoid.consistent_least_squares(H, y, LT)
    ref, tol = cvxopt_solution(H, y, LT)
    assert tol < 1e-4 * np.abs(ref).max()  # a meaningful comparison
    np.testing.assert_allclose(ours["x"], ref, rtol=0, atol=tol)


def test_a_consistent_estimate_is_returned_unchanged():
    H, y = problem(nominal(), 1e-3, 3)
    ls = np.linalg.lstsq(H, y, rcond=None)[0]
    ours = exoid.consistent_least_squares(H, y, LT, x_ls=ls)
    assert not ours["constrained"]
    np.testing.assert_allclose(ours["x"], ls, rtol=1e-9, atol=0)
