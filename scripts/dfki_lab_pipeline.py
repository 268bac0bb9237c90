#!/usr/bin/env python3
"""The DFKI lab's own identification procedure, ported to numpy, on the shipped A.0 logs: what
their method gives on each record alone and on records 00-05 + 11 together, against the values
they published (design_A0_model_2.0_parameters.yml, their fit over 14 records). It answers whether
a record (the swing-up 11 above all) supports the lab's values by the lab's own method
(docs/findings.md, section 4.5).

Ported from dfki-ric-underactuated-lab/double_pendulum at 1e8544e (BSD-3-Clause):
src/python/double_pendulum/system_identification/{sys_id,dynamics,data_prep,loss}.py,
filter/offline/butterworth.py, utils/optimization.py, examples/paper/system_identification_M1.py
and _M2.py. Their pipeline: pos_meas, vel_meas and tau_meas; velocity and torque filtered by a
3rd-order Butterworth forward and backward at Wn = 0.02 of Nyquist; acceleration by np.gradient of
the angle (the real time stamps), filtered, np.gradient again, filtered; no resampling or trimming;
records filtered one by one, then stacked; six parameters (m1 r1, I1, Ir, m2 r2, m2, I2) fitted by
bounded least squares in variables rescaled to [0, 1]. Their "fixed" friction drops out of the
regressor (a derivative with respect to the fitted parameters) and is never subtracted from the
torque: their fit has no friction at all. scipy is not a dependency of exoid, so
scipy.signal.butter and filtfilt (its defaults: odd extension, padlen 3 max(len(a), len(b))) and
the bounded solve (the QP is convex: projected gradient with restarts to convergence) are written
here in numpy. Only five combinations are identifiable (Phi has rank 5 of 6); the four exoid
reports are Mxt = m1 r1 + m2 l1, Jt = M11 = I1 + I2 + m2 l1^2 + 37 Ir, Mxs = m2 r2, Js = M22 =
I2 + 36 Ir.

Usage: python3 scripts/dfki_lab_pipeline.py [--design-c0 DIR]   (about 70 s)
  --design-c0 DIR  also fit DIR/trajectory_12.csv and DIR/trajectory_13.csv of design C.0
                   (data/experiment_records/design_C.0/20220914/sys_id of that repository; not
                   shipped with exoid), against the lab's model_3.0 values.
"""
import gzip
import gzip
import sys
import numpy as np

G = 9.81
GR = 6.0
import os
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "real", "dfki_double_pendulum",
                    "design_A0_20220815_trajectory_%s.csv.gz")
PUB = {"A0": dict(Mxt=0.3491, Jt=0.1346, Mxs=0.1111, Js=0.0267),
       "C0": dict(Mxt=0.2411, Jt=0.1068, Mxs=0.1812, Js=0.0575)}
VARS = ["m1r1", "I1", "Ir", "m2r2", "m2", "I2"]  # variable_mpar (fix_friction=True)
# bounds from examples/paper/system_identification_M1.py (A.0) and _M2.py (C.0)
BOUNDS = {"A0": np.array([[0.01, 0.3], [0.01, 0.2], [1e-6, 1e-3], [0.05, 1.0], [0.01, 5.0], [0.01, 0.2]]).T,
          "C0": np.array([[0.01, 0.15], [0.01, 0.2], [0.0, 0.003], [0.1, 1.0], [0.01, 5.0], [0.01, 0.2]]).T}
L1 = {"A0": 0.3, "C0": 0.2}


# ---------------------------------------------------------------- filters
def butter_lowpass(N, Wn):
    """scipy.signal.butter(N, Wn) (digital, lowpass, ba output), via zpk + bilinear (fs=2)."""
    k = np.arange(-N + 1, N, 2)
    p = -np.exp(1j * np.pi * k / (2 * N))          # buttap poles
    fs = 2.0
    warped = 2 * fs * np.tan(np.pi * Wn / fs)
    p = warped * p
    kk = warped ** N
    fs2 = 2 * fs
    pd = (fs2 + p) / (fs2 - p)
    zd = -np.ones(N)
    kd = kk * np.real(1.0 / np.prod(fs2 - p))
    b = kd * np.real(np.poly(zd))
    a = np.real(np.poly(pd))
    return b, a


def lfilter_zi(b, a):
    n = max(len(a), len(b))
    b = b / a[0]
    a = a / a[0]
    comp = np.zeros((n - 1, n - 1))
    comp[0, :] = -a[1:]
    comp[1:, :-1] += np.eye(n - 2)
    IminusA = np.eye(n - 1) - comp.T
    B = b[1:] - a[1:] * b[0]
    return np.linalg.solve(IminusA, B)


def lfilter(b, a, x, zi):
    """direct form II transposed, like scipy.signal.lfilter."""
    n = len(a)
    z = np.array(zi, dtype=float).copy()
    y = np.empty_like(x, dtype=float)
    b0 = b[0]
    for i, xi in enumerate(x):
        yi = b0 * xi + z[0]
        for j in range(n - 2):
            z[j] = b[j + 1] * xi + z[j + 1] - a[j + 1] * yi
        z[n - 2] = b[n - 1] * xi - a[n - 1] * yi
        y[i] = yi
    return y


def filtfilt(b, a, x):
    """scipy.signal.filtfilt(b, a, x) with its defaults (odd extension, padlen=3*max(len))."""
    x = np.asarray(x, dtype=float)
    edge = 3 * max(len(a), len(b))
    ext = np.concatenate((2 * x[0] - x[edge:0:-1], x, 2 * x[-1] - x[-2:-(edge + 2):-1]))
    zi = lfilter_zi(b, a)
    y = lfilter(b, a, ext, zi * ext[0])
    y = lfilter(b, a, y[::-1], zi * y[-1])[::-1]
    return y[edge:-edge]


def butterworth_filter_offline(x, order, cutoff):
    b, a = butter_lowpass(order, cutoff)
    return filtfilt(b, a, x)


# ---------------------------------------------------------------- data
def load(path):
    op = gzip.open if path.endswith(".gz") else open
    with op(path, "rt") as f:
        d = np.genfromtxt(f, delimiter=",", names=True)
    names = d.dtype.names
    T = d["time"]
    # dynamics.py: X_meas if present else X ; U_meas if present, else U_con, else U
    if all(k in names for k in ("pos_meas1", "pos_meas2", "vel_meas1", "vel_meas2")):
        X = np.array([d["pos_meas1"], d["pos_meas2"], d["vel_meas1"], d["vel_meas2"]]).T
    else:
        X = np.array([d["pos1"], d["pos2"], d["vel1"], d["vel2"]]).T
    if "tau_meas1" in names:
        U = np.array([d["tau_meas1"], d["tau_meas2"]]).T
    elif "tau_con1" in names:
        U = np.array([d["tau_con1"], d["tau_con2"]]).T
    else:
        U = np.array([d["tau1"], d["tau2"]]).T
    return T, X, U


def smooth_data(t, X, U, Wn=0.02):
    """data_prep.smooth_data(filt='butterworth')."""
    f = lambda s: butterworth_filter_offline(s, 3, Wn)
    vel = [f(X[:, 2]), f(X[:, 3])]                 # measured velocities, filtered (used in regressor)
    tau = [f(U[:, 0]), f(U[:, 1])]
    acc = []
    for j in (0, 1):
        v = f(np.gradient(X[:, j], t))             # d(pos)/dt (non-uniform t), filter
        acc.append(f(np.gradient(v, t)))           # d/dt again, filter
    return X[:, 0], X[:, 1], vel[0], vel[1], acc[0], acc[1], tau[0], tau[1]


def regressor(q1, q2, qd1, qd2, qdd1, qdd2, l1):
    """d(eom)/d(p), p = [m1r1, I1, Ir, m2r2, m2, I2]; eom = M qdd + C qd - G + F
    (symbolic_plant.py 'UnderactuatedLecture' formulas, r1 = m1r1/m1, r2 = m2r2/m2, g=9.81, gr=6).
    The fixed friction F(qd) does not depend on p, so it vanishes in the derivative."""
    s1, s2, c2, s12 = np.sin(q1), np.sin(q2), np.cos(q2), np.sin(q1 + q2)
    z = np.zeros_like(q1)
    r1 = [G * s1, qdd1, (GR**2 + 1) * qdd1 - GR * qdd2,
          l1 * c2 * (2 * qdd1 + qdd2) - l1 * s2 * (2 * qd1 * qd2 + qd2**2) + G * s12,
          l1**2 * qdd1 + G * l1 * s1, qdd1 + qdd2]
    r2 = [z, z, -GR * qdd1 + GR**2 * qdd2,
          l1 * c2 * qdd1 + l1 * s2 * qd1**2 + G * s12, z, qdd1 + qdd2]
    n = len(q1)
    phi = np.empty((2 * n, 6))
    phi[0::2] = np.array(r1).T
    phi[1::2] = np.array(r2).T
    return phi


def friction(qd1, qd2, cf=(0.093, 0.078), b=(0.001, 0.001)):
    return b[0] * qd1 + cf[0] * np.arctan(100 * qd1), b[1] * qd2 + cf[1] * np.arctan(100 * qd2)


def build(paths, l1, Wn=0.02, subtract_friction=False):
    """dynamics.build_identification_matrices: each record filtered on its own, then stacked."""
    Qs, Ps = [], []
    for p in paths:
        T, X, U = load(p)
        q1, q2, v1, v2, a1, a2, t1, t2 = smooth_data(T, X, U, Wn)
        Q = np.empty(2 * len(T))
        Q[0::2], Q[1::2] = t1, t2
        if subtract_friction:  # NOT what the lab's code does; sensitivity only
            f1, f2 = friction(v1, v2)
            Q[0::2] -= f1
            Q[1::2] -= f2
        Qs.append(Q)
        Ps.append(regressor(q1, q2, v1, v2, a1, a2, l1))
    return np.concatenate(Qs), np.vstack(Ps)


# ---------------------------------------------------------------- solver
def bounded_lsq(phi, Q, bounds, iters=200000, tol=1e-15):
    """min ||Q - phi p||^2 s.t. bounds, in the lab's rescaled variables x in [0,1]
    (rescale=True). Convex QP -> FISTA with adaptive restart; phi p (hence the identifiable
    combinations) is unique even though p is not (rank 5 of 6)."""
    lo, hi = bounds
    S = np.diag(hi - lo)
    A = phi @ S
    c = Q - phi @ lo
    H = A.T @ A
    gvec = A.T @ c
    L = np.linalg.eigvalsh(H).max()
    x = np.full(6, 0.5)
    y = x.copy()
    tk = 1.0
    fprev = np.inf
    for _ in range(iters):
        xn = np.clip(y - (H @ y - gvec) / L, 0.0, 1.0)
        f = 0.5 * xn @ H @ xn - gvec @ xn
        if f > fprev:  # restart
            tk = 1.0
            y = x.copy()
            continue
        tn = 0.5 * (1 + np.sqrt(1 + 4 * tk * tk))
        y = xn + (tk - 1) / tn * (xn - x)
        if np.max(np.abs(xn - x)) < tol:
            x = xn
            break
        x, tk, fprev = xn, tn, f
    p = lo + (hi - lo) * x
    return p, x


def combos(p, l1):
    m1r1, I1, Ir, m2r2, m2, I2 = p
    return dict(Mxt=m1r1 + m2 * l1,
                Jt=I1 + I2 + m2 * l1**2 + (GR**2 + 1) * Ir,
                Mxs=m2r2,
                Js=I2 + GR**2 * Ir,
                J12=I2 - GR * Ir, Ir=Ir)


def unconstrained_combos(phi, Q, l1):
    """Plain LS on the 5 identifiable combinations (no bounds), for comparison."""
    # columns: Mxt-> gsin(q1) col ; J11 -> qdd1 (row1) ; Mxs ; J12 ; J22
    B = np.column_stack([phi[:, 0], phi[:, 1], phi[:, 3]])
    # I2 col = [a1+a2, a1+a2]; Ir col = [37a1-6a2, -6a1+36a2]; J12 multiplies (row1 a2, row2 a1), J22 row2 a2
    a1 = np.zeros(len(Q)); a2 = np.zeros(len(Q))
    # recover a1, a2 per row from I1 and I2 columns: row1: I1col=a1, I2col=a1+a2 ; row2: I2col=a1+a2, Ircol=-6a1+36a2
    r1 = slice(0, None, 2); r2 = slice(1, None, 2)
    A1_1 = phi[r1, 1]; A2_1 = phi[r1, 5] - phi[r1, 1]
    s_2 = phi[r2, 5]; A2_2 = (phi[r2, 2] + 6 * s_2) / 42.0; A1_2 = s_2 - A2_2
    J12col = np.zeros(len(Q)); J22col = np.zeros(len(Q))
    J12col[r1] = A2_1; J12col[r2] = A1_2
    J22col[r2] = A2_2
    M = np.column_stack([phi[:, 0], phi[:, 1], phi[:, 3], J12col, J22col])
    sol, *_ = np.linalg.lstsq(M, Q, rcond=None)
    Mxt, J11, Mxs, J12, J22 = sol
    return dict(Mxt=Mxt, Jt=J11, Mxs=Mxs, Js=J22, J12=J12, Ir=(J22 - J12) / (GR**2 + GR))


def fit(paths, design, Wn=0.02, subtract_friction=False):
    l1 = L1[design]
    Q, phi = build(paths, l1, Wn, subtract_friction)
    p, x = bounded_lsq(phi, Q, BOUNDS[design])
    c = combos(p, l1)
    cu = unconstrained_combos(phi, Q, l1)
    active = [VARS[i] + ("@lo" if x[i] < 1e-6 else "@hi") for i in range(6) if x[i] < 1e-6 or x[i] > 1 - 1e-6]
    rms = np.sqrt(np.mean((Q - phi @ p) ** 2))
    return c, cu, p, active, rms


def row(label, design, c, extra=""):
    pub = PUB[design]
    s = "%-34s" % label
    for k in ("Mxt", "Jt", "Mxs", "Js"):
        s += " %s %.4f (%+6.1f%%)" % (k, c[k], 100 * (c[k] / pub[k] - 1))
    s += "  Ir %.2e J12 %.4f %s" % (c["Ir"], c["J12"], extra)
    return s


if __name__ == "__main__":
    # sanity check of the filter design against known properties
    b, a = butter_lowpass(3, 0.02)
    w = np.pi * 0.02
    H = np.polyval(b[::-1], np.exp(-1j * w)) / np.polyval(a[::-1], np.exp(-1j * w))
    print("butter(3,0.02): b=%s a=%s |H(Wn)|=%.6f (expect 0.707107), DC gain %.6f"
          % (np.array2string(b, precision=6), np.array2string(a, precision=8), abs(H), b.sum() / a.sum()))
    for n in ("11",):
        T, X, U = load(DATA % n)
        print("record %s: N=%d, mean fs %.1f Hz -> Wn=0.02 cutoff %.2f Hz" % (n, len(T), 1 / np.mean(np.diff(T)), 0.01 / np.mean(np.diff(T))))

    A = lambda ns: [DATA % n for n in ns]
    jobs = [("(a) A0 rec 11", "A0", A(["11"]))]
    jobs += [("(b) A0 rec 00-05+11", "A0", A(["00", "01", "02", "03", "04", "05", "11"]))]
    jobs += [("(c) A0 rec %s" % n, "A0", A([n])) for n in ("00", "01", "02", "03", "04", "05", "12", "13")]
    if len(sys.argv) == 3 and sys.argv[1] == "--design-c0":
        jobs += [("(d) C0 rec %s" % n, "C0", [os.path.join(sys.argv[2], "trajectory_%s.csv" % n)]) for n in ("12", "13")]
    elif len(sys.argv) != 1:
        sys.exit("usage: dfki_lab_pipeline.py [--design-c0 DIR]")
    for label, design, paths in jobs:
        c, cu, p, active, rms = fit(paths, design)
        print(row(label, design, c, "rms %.4f active %s" % (rms, active or "-")))
        if active:
            print(row("    unbounded LS on combos", design, cu))
        if label.startswith("(a)") or label.startswith("(b)"):
            for fac in (0.5, 2.0):
                c2, _, _, act2, rms2 = fit(paths, design, Wn=0.02 * fac)
                print(row("    Wn x%.1f (=%.2f)" % (fac, 0.02 * fac), design, c2, "rms %.4f active %s" % (rms2, act2 or "-")))
            c3, _, _, act3, _ = fit(paths, design, subtract_friction=True)
            print(row("    [not lab] friction subtracted", design, c3, "active %s" % (act3 or "-")))
        sys.stdout.flush()
