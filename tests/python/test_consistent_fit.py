"""The physically consistent fit (exoid.ChainModel.consistent_fit: Levenberg-Marquardt in
log-Cholesky coordinates, then a log-barrier interior point, in Eigen) against an independent
solution of the same convex problem by cvxopt's cone solver (conelp, an SDP):

    minimise ||R (C phi - beta_ls)||   subject to   J_k(phi) >= 0 (PSD),  m_k <= M,
             R^2 m_k - tr Sigma_k >= 0,  friction and armature >= 0,

with A = Wb' Wb = R' R. Both are optimal over the same closed convex set, so for either estimate
||beta - beta*||_A^2 <= excess(beta) - excess* (the projection's Pythagorean inequality): the
two agree within the square roots of their optimality gaps."""
import numpy as np
import pytest

import exoid

cvxopt = pytest.importorskip("cvxopt")
from cvxopt import matrix, solvers  # noqa: E402

LINK = 10  # m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz (about the link origin)


def pseudo_inertia(phi):
    m, h, (ixx, ixy, ixz, iyy, iyz, izz) = phi[0], phi[1:4], phi[4:10]
    inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    J = np.zeros((4, 4))
    J[:3, :3] = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    J[:3, 3] = J[3, :3] = h
    J[3, 3] = m
    return J


def sagittal_leg():
    return exoid.ChainModel([
        dict(name="hip", link="thigh", axis=[0, 1, 0], armature=True),
        dict(name="knee", link="shank", axis=[0, 1, 0], origin_m=[0, 0, -0.42]),
        dict(name="ankle", link="foot", axis=[0, 1, 0], origin_m=[0.0, 0, -0.40], armature=True),
    ], name="sagittal")


def truth():
    thigh = exoid.link_parameters(9.0, [0.01, 0.0, -0.18], np.diag([0.15, 0.16, 0.03]))
    shank = exoid.link_parameters(3.5, [0.0, 0.0, -0.17], np.diag([0.05, 0.05, 0.006]))
    foot = exoid.link_parameters(1.2, [0.06, 0.0, -0.05], np.diag([0.004, 0.005, 0.002]))
    return np.concatenate([thigh, [0.9, 0.4, 0.08], shank, [0.7, 0.3], foot, [0.4, 0.15, 0.02]])


def record(model, phi, samples, seed, noise_nm):
    rng = np.random.default_rng(seed)
    n = model.dof
    W = np.vstack([model.regressor(rng.uniform(-1.5, 1.5, n), rng.uniform(-3, 3, n), rng.uniform(-20, 20, n))
                   for _ in range(samples)])
    return W, W @ phi + noise_nm * rng.standard_normal(W.shape[0])


def link_blocks(names):
    """Start index of each link's 10 parameters, and the friction/armature indices."""
    starts = [k for k, nm in enumerate(names) if nm.endswith(".m")]
    links = {k + i for k in starts for i in range(LINK)}
    return starts, [k for k in range(len(names)) if k not in links]


def sdp_reference(model, W, y, max_mass, radius, tolerance=1e-8):
    names = model.parameter_names
    p = len(names)
    C = np.asarray(model.base_parameters()["combination"])
    # The base regressor: W = Wb C, every row of W in C's row space.
    Wb = np.linalg.lstsq(C.T, W.T, rcond=None)[0].T
    A = Wb.T @ Wb
    R = np.linalg.cholesky(A).T
    beta_ls = np.linalg.solve(A, Wb.T @ y)
    starts, coefficients = link_blocks(names)
    x_dim = p + 1  # phi, then the epigraph variable
    c = np.zeros(x_dim)
    c[-1] = 1.0
    # Linear cone: m <= M, sphere, coefficients >= 0.
    G_l, h_l = [], []
    for k in starts:
        row = np.zeros(x_dim); row[k] = 1.0 / max_mass; G_l.append(row); h_l.append(1.0)  # m / M <= 1
        row = np.zeros(x_dim); row[k] = -radius ** 2; row[k + 4] = row[k + 7] = row[k + 9] = 0.5; G_l.append(row); h_l.append(0.0)
    for k in coefficients:
        row = np.zeros(x_dim); row[k] = -1.0; G_l.append(row); h_l.append(0.0)
    # Second-order cone: (s, target - R C phi).
    r = C.shape[0]
    G_q = np.zeros((r + 1, x_dim)); h_q = np.zeros(r + 1)
    G_q[0, -1] = -1.0
    G_q[1:, :p] = R @ C
    h_q[1:] = R @ beta_ls
    # PSD cones: J_k(phi) = -G phi, column-major.
    G_s, h_s = [], []
    for k in starts:
        G = np.zeros((16, x_dim))
        for i in range(LINK):
            e = np.zeros(LINK); e[i] = 1.0
            G[:, k + i] = -pseudo_inertia(e).flatten(order="F")
        G_s.append(matrix(G)); h_s.append(matrix(np.zeros((4, 4))))
    solvers.options.update(show_progress=False, abstol=tolerance, reltol=tolerance, feastol=tolerance, maxiters=200)
    sol = solvers.conelp(matrix(c), matrix(np.vstack(G_l + [G_q] + [np.asarray(g) for g in G_s])),
                         matrix(np.concatenate([h_l, h_q, np.zeros(16 * len(starts))])),
                         dims=dict(l=len(G_l), q=[r + 1], s=[4] * len(starts)))
    assert sol["status"] == "optimal", sol["status"]
    phi = np.asarray(sol["x"]).ravel()[:p]
    return C @ phi, beta_ls, A


@pytest.mark.parametrize("case", ["negative knee viscous", "ankle too light"])
def test_matches_the_sdp_reference(case):
    model = sagittal_leg()
    phi = truth()
    names = model.parameter_names
    if case == "negative knee viscous":
        phi[names.index("knee.fv")] = -0.5
    else:
        phi[names.index("foot.Iyy")] *= 0.02  # a foot too light for its first moment: no real body
    W, y = record(model, phi, 300, 5, 0.05)
    fit = model.consistent_fit(W, y, truth())
    assert fit["status"] == "constrained", fit["message"]
    assert min(fit["link_min_eigenvalue"]) > 0.0
    beta_ref, beta_ls, A = sdp_reference(model, W, y, 1e4, 2.0)
    np.testing.assert_allclose(fit["beta_ls"], beta_ls, rtol=1e-8, atol=1e-10)

    def excess(beta):
        d = beta - beta_ls
        return d @ A @ d

    e_fit, e_ref = excess(np.asarray(fit["beta"])), excess(beta_ref)
    rss = fit["ls_cost"]
    # The fit's barrier stops within 1e-6 RSS of its optimum; cvxopt's to 1e-8 (relative,
    # on the norm). Neither can be below the other by more than the reference's gap.
    gap = 1e-6 * (rss + e_ref) + 1e-8 * e_ref
    assert e_fit >= e_ref - gap
    assert e_fit <= e_ref + gap
    d = np.asarray(fit["beta"]) - beta_ref
    assert d @ A @ d <= (np.sqrt(abs(e_fit - e_ref) + gap) + np.sqrt(gap)) ** 2


def test_equals_least_squares_when_it_is_consistent():
    model = sagittal_leg()
    W, y = record(model, truth(), 300, 6, 0.0)
    fit = model.consistent_fit(W, y, np.zeros(len(model.parameter_names)))
    assert fit["status"] == "least_squares_consistent", fit["message"]
    beta_true = np.asarray(fit["combination"]) @ truth()
    assert np.abs(np.asarray(fit["beta"]) - beta_true).max() <= 1e-9 * np.abs(beta_true).max()
