"""The numpy port of the DFKI lab's identification procedure (scripts/dfki_lab_pipeline.py), whose
numbers docs/findings.md quotes, checked against closed forms: its Butterworth design (gain 1/sqrt(2)
at the cutoff, 1 at DC), its filtfilt (zero phase: a constant passes unchanged, a sinusoid in the
interior comes out scaled by |H|^2), its bounded solve (the unconstrained least squares when no bound binds,
the box's edge when one does) and its regressor (the lab's plant's torque for known parameters)."""
import importlib.util
import pathlib

import numpy as np

_path = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "dfki_lab_pipeline.py"
_spec = importlib.util.spec_from_file_location("dfki_lab_pipeline", _path)
lab = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(lab)


def _gain(b, a, w):
    z = np.exp(-1j * w)
    return abs(np.polyval(b[::-1], z) / np.polyval(a[::-1], z))


# A narrow low-pass's coefficients carry rounding amplified by about 1/Wn^3 (its poles crowd z = 1):
# 1e-6 x 1e-16 for Wn = 0.01, so 1e-9 is a bound with margin, not a fit.
def test_butterworth_gain_at_cutoff_and_dc():
    for wn in (0.01, 0.02, 0.04):
        b, a = lab.butter_lowpass(3, wn)
        assert abs(_gain(b, a, np.pi * wn) - 2 ** -0.5) < 1e-9
        assert abs(b.sum() / a.sum() - 1.0) < 1e-9


# Zero phase: a constant passes unchanged (the initial conditions are its steady state), and away
# from the edges a sinusoid comes out in phase, scaled by |H|^2. The edges' transient decays as
# the slowest pole's radius r^k: samples where r^k < 1e-12 are the interior.
def test_filtfilt_is_zero_phase_with_the_squared_gain():
    b, a = lab.butter_lowpass(3, 0.02)
    n = 3000
    assert np.max(np.abs(lab.filtfilt(b, a, np.full(n, 2.5)) - 2.5)) < 1e-9
    r = np.max(np.abs(np.roots(a)))
    edge = int(np.ceil(np.log(1e-12) / np.log(r)))
    assert 2 * edge < n
    k = np.arange(n)
    for w in (np.pi * 0.002, np.pi * 0.02, np.pi * 0.03):
        y = lab.filtfilt(b, a, np.sin(w * k))
        expected = _gain(b, a, w) ** 2 * np.sin(w * k)
        assert np.max(np.abs(y - expected)[edge:n - edge]) < 1e-9


def test_bounded_solve_is_least_squares_inside_the_box_and_clips_at_its_edge():
    rng = np.random.default_rng(7)
    phi = rng.standard_normal((200, 6))
    p_true = np.array([0.1, 0.05, 2e-4, 0.3, 1.0, 0.05])
    q = phi @ p_true
    lo = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    hi = np.array([1.0, 1.0, 1e-3, 1.0, 5.0, 1.0])
    p, _ = lab.bounded_lsq(phi, q, (lo, hi))
    # The solver works in variables rescaled to the box (the lab's rescale=True): a 1e-3-wide box
    # makes the problem ill-conditioned and converges slowly in that variable, so the test is on
    # what the findings use, the fitted torque (and through it the combinations), to 1e-7.
    assert np.linalg.norm(phi @ p - q) < 1e-7 * np.linalg.norm(q)
    hi_tight = hi.copy()
    hi_tight[3] = 0.2  # the truth's m2 r2 is 0.3: the bound binds
    p, x = lab.bounded_lsq(phi, q, (lo, hi_tight))
    assert abs(x[3] - 1.0) < 1e-12
    # KKT of min ||phi p - q||^2 in the box: the gradient is zero on a free variable, points out of
    # the box on one at a bound (<= 0 at the upper, >= 0 at the lower).
    g = (phi.T @ (phi @ p - q)) * (hi_tight - lo)
    tol = 1e-6 * np.abs((phi.T @ q) * (hi_tight - lo)).max()
    for i in range(6):
        if x[i] >= 1.0 - 1e-12:
            assert g[i] <= tol
        elif x[i] <= 1e-12:
            assert g[i] >= -tol
        else:
            assert abs(g[i]) < tol, (i, g[i], tol)


def test_regressor_gives_the_lab_plants_torque():
    rng = np.random.default_rng(3)
    n, l1, g, gr = 50, 0.3, 9.81, 6.0
    q1, q2, qd1, qd2, qdd1, qdd2 = rng.uniform(-2.0, 2.0, (6, n))
    m1, m2, r1, r2, I1, I2, Ir = 0.56, 0.60, 0.3, 0.18, 0.053, 0.024, 7.7e-5
    phi = lab.regressor(q1, q2, qd1, qd2, qdd1, qdd2, l1)
    tau = phi @ np.array([m1 * r1, I1, Ir, m2 * r2, m2, I2])
    # The lab's plant (their README's mapping): M, C qd and gravity with the rotor terms.
    c2, s2 = np.cos(q2), np.sin(q2)
    M11 = I1 + I2 + m2 * l1 ** 2 + 2 * m2 * l1 * r2 * c2 + (gr ** 2 + 1) * Ir
    M12 = I2 + m2 * l1 * r2 * c2 - gr * Ir
    M22 = I2 + gr ** 2 * Ir
    h1 = -m2 * l1 * r2 * s2 * (2 * qd1 * qd2 + qd2 ** 2) + g * (m1 * r1 + m2 * l1) * np.sin(q1) + g * m2 * r2 * np.sin(q1 + q2)
    h2 = m2 * l1 * r2 * s2 * qd1 ** 2 + g * m2 * r2 * np.sin(q1 + q2)
    assert np.max(np.abs(tau[0::2] - (M11 * qdd1 + M12 * qdd2 + h1))) < 1e-12
    assert np.max(np.abs(tau[1::2] - (M12 * qdd1 + M22 * qdd2 + h2))) < 1e-12
