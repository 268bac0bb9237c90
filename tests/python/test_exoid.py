"""The exoid Python module against independent truths: exact recovery on exact data, the shipped
real log against the lab's own parameters, the CRB against a Monte Carlo of LS, and errors that
keep their messages."""
import gzip
import os

import numpy as np
import pytest

import exoid

SOURCE = os.environ.get("EXOID_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
DFKI = os.path.join(SOURCE, "data", "real", "dfki_double_pendulum")
PROFILE = {"t": "time", "q_hip": "pos_meas1", "q_knee": "pos_meas2", "tau_hip": "tau_meas1", "tau_knee": "tau_meas2"}
X = np.array([5.83, 0.1, 2.1, 1.5, 0.6, 1.3, 0.05, 0.6, 1.2, 0.4])


def multisine(n=4000, dt=1e-3):
    t = np.arange(n) * dt
    w = np.array([1.3, 2.1])
    q = np.column_stack([-0.5 + 0.6 * np.sin(w[0] * t), 1.0 + 0.5 * np.sin(w[1] * t + 0.4)])
    qd = np.column_stack([0.6 * w[0] * np.cos(w[0] * t), 0.5 * w[1] * np.cos(w[1] * t + 0.4)])
    qdd = np.column_stack([-0.6 * w[0] ** 2 * np.sin(w[0] * t), -0.5 * w[1] ** 2 * np.sin(w[1] * t + 0.4)])
    return t, q, qd, qdd


def test_param_names_are_x_in_order():
    assert exoid.param_names() == ["Mxt", "Myt", "Jt", "fc1", "fv1", "Mxs", "Mys", "Js", "fc2", "fv2"]


def test_ls_recovers_x_from_exact_torques():
    _, q, qd, qdd = multisine()
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=0.45)
    H = np.vstack([hip, knee])
    r = exoid.identify(H, H @ X, method="ls")
    assert r["usable"] and r["rank"] == 10
    assert np.max(np.abs(r["x"] - X) / np.abs(X)) < 1e-9


def test_parallel_processing_keeps_exact_data_exact():
    t, q, qd, qdd = multisine(10000)
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=0.45)
    data = {"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": np.column_stack([hip @ X, knee @ X])}
    rows = exoid.process_record(data, thigh_length_m=0.45)
    H = np.vstack([rows["hip"], rows["knee"]])
    r = exoid.identify(H, np.concatenate([rows["tau"][:, 0], rows["tau"][:, 1]]))
    assert np.max(np.abs(r["x"] - X) / np.abs(X)) < 1e-8


def test_crb_matches_a_monte_carlo_of_ls():
    rng = np.random.default_rng(3)
    _, q, qd, qdd = multisine(2000)
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=0.45)
    H = np.vstack([hip, knee])
    sigma = 0.5
    report = exoid.identifiability(H, H @ X, noise_sigma=sigma)
    xs = np.array([exoid.identify(H, H @ X + rng.normal(0, sigma, H.shape[0]))["x"] for _ in range(300)])
    ratio = xs.std(axis=0) / report["crb_std"]
    # The sample std of 300 draws is within 3 standard errors (1/sqrt(2 * 299) = 4 %) of the truth.
    assert np.all(np.abs(ratio - 1) < 3 * np.sqrt(1 / (2 * 299))), ratio


def test_the_shipped_swing_up_gives_the_labs_inertial_parameters():
    lab = {}
    with open(os.path.join(DFKI, "design_A0_model_2.0_parameters.yml")) as f:
        for line in f:
            key, value = line.split(":")
            lab[key.strip()] = float(value)
    truth = {"Mxt": lab["m1"] * lab["r1"] + lab["m2"] * lab["l1"],
             "Jt": lab["I1"] + lab["I2"] + lab["m2"] * lab["l1"] ** 2 + (lab["gr"] ** 2 + 1) * lab["Ir"],
             "Mxs": lab["m2"] * lab["r2"], "Js": lab["I2"] + lab["gr"] ** 2 * lab["Ir"]}
    path = os.path.join(DFKI, "design_A0_20220815_trajectory_11.csv.gz")
    with gzip.open(path, "rt") as f:
        data = exoid.parse_dataset(f.read(), source=path, columns=PROFILE)
    assert data["sampling"]["resampled"]
    rows = exoid.process_record(data, thigh_length_m=lab["l1"])
    H = np.vstack([rows["hip"], rows["knee"]])
    x = exoid.identify(H, np.concatenate([rows["tau"][:, 0], rows["tau"][:, 1]]))["x"]
    names = exoid.param_names()
    for name, value in truth.items():
        assert abs(x[names.index(name)] - value) / value < 0.10, (name, x[names.index(name)], value)


def test_errors_keep_their_messages():
    with pytest.raises(RuntimeError, match="/nonexistent/log.csv"):
        exoid.read_dataset("/nonexistent/log.csv")
    with pytest.raises(RuntimeError, match="log.csv:1:.*missing required column 't'"):
        exoid.parse_dataset("time,a\n0,1\n", source="log.csv")
    with pytest.raises(ValueError, match="unknown method"):
        exoid.identify(np.eye(3), np.ones(3), method="magic")
    with pytest.raises(ValueError, match="time unit 'min'"):
        exoid.read_dataset("x.csv", time_unit="min")
