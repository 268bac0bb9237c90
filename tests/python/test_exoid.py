"""The exoid Python module against independent truths: exact recovery on exact data, the shipped
real log against the lab's own parameters, the CRB against a Monte Carlo of LS, and errors that
keep their messages."""
import gzip
import os

import numpy as np
import pytest

import exoid
from cli_support import exoid_binary

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


def knee_and_both_records(n=6000):
    """Exact records from the module's own regressor: a knee-only record (hip fixed) and one where
    both joints move, with recorded derivatives, so the parallel processing is exact."""
    t, q, qd, qdd = multisine(n)
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=0.45)
    both = {"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": np.column_stack([hip @ X, knee @ X])}
    qk, qdk, qddk = q.copy(), qd.copy(), qdd.copy()
    qk[:, 0], qdk[:, 0], qddk[:, 0] = -0.3, 0.0, 0.0
    hip_k, knee_k = exoid.regressor(qk, qdk, qddk, thigh_length_m=0.45)
    knee_rec = {"t": t, "q": qk, "qd": qdk, "qdd": qddk, "tau": np.column_stack([hip_k @ X, knee_k @ X])}
    return knee_rec, both


@pytest.mark.parametrize("method", ["ls", "lad"])
def test_segmental_strategy_recovers_x_from_exact_records(method):
    knee_rec, both = knee_and_both_records()
    r = exoid.identify_segmental(knee_rec, both, thigh_length_m=0.45, method=method)
    assert r["knee"]["usable"] and r["hip"]["usable"]
    # Exact rows: both are exact up to roundoff amplified by the stages' conditioning (< 1e3).
    assert np.max(np.abs(r["x"] - X) / np.abs(X)) < 1e-8, r["x"]
    assert np.allclose(r["knee"]["x"], r["x"][5:]) and np.allclose(r["hip"]["x"], r["x"][:5])


def test_rls_is_the_ridge_solution_its_prior_implies():
    """RLS from x0 = 0, P0 = p0 I, no forgetting, is the closed form (H'H + I/p0)^-1 H'y: on exact
    data it keeps the prior's pull (1e-5 of X at p0 = 1e6, 1e-2 at 1e3), which the closed form
    predicts. Sequential roundoff: ~ rows * eps * cond = 6000 * 2.2e-16 * 1.6e3 = 2e-9 (3e-10 seen)."""
    _, q, qd, qdd = multisine(3000)
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=0.45)
    H = np.vstack([hip, knee])
    y = H @ X
    for p0 in (1e6, 1e3):
        ridge = np.linalg.solve(H.T @ H + np.eye(10) / p0, H.T @ y)
        r = exoid.identify(H, y, method="rls", rls_initial_covariance=p0)
        assert np.max(np.abs(r["x"] - ridge) / np.abs(ridge)) < 1e-7, (p0, r["x"], ridge)


def test_every_method_reports_its_summary_and_options_reach_it():
    _, q, qd, qdd = multisine(2000)
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=0.45)
    H = np.vstack([hip, knee])[:, 5:]
    y = H @ X[5:] + np.random.default_rng(1).normal(0, 0.05, H.shape[0])
    for method in ["ls", "rls", "pso", "rls-pso", "lad"]:
        r = exoid.identify(H, y, method=method, pso_iterations=300, seed=5)
        for key in ["x", "status", "usable", "message", "iterations", "final_cost", "l1_cost", "wall_time_s"]:
            assert key in r, (method, key)
        assert r["method"] == method and r["usable"], r
    lad = exoid.identify(H, y, method="lad")
    pso = exoid.identify(H, y, method="rls-pso", pso_iterations=300, seed=5)
    # The reported gap is the estimate's L1 cost against the certified optimum's.
    assert pso["optimality_gap"] == pytest.approx((pso["l1_cost"] - lad["l1_cost"]) / lad["l1_cost"], rel=1e-6)
    assert len(pso["cost_history"]) == 301 and pso["box"] is not None
    # Same seed, same bits; the options reach the swarm (another seed or swarm, another run).
    assert np.array_equal(pso["x"], exoid.identify(H, y, method="rls-pso", pso_iterations=300, seed=5)["x"])
    assert not np.array_equal(pso["x"], exoid.identify(H, y, method="rls-pso", pso_iterations=300, seed=6)["x"])
    assert not np.array_equal(pso["x"], exoid.identify(H, y, method="rls-pso", pso_iterations=300, seed=5,
                                                       pso_swarm_size=17)["x"])
    assert exoid.identify(H, y, method="pso", pso_iterations=5, wide_box_half_width=3.0)["box"][1][0] == 3.0


def test_option_mistakes_name_the_option():
    with pytest.raises(TypeError, match="unexpected keyword argument 'swarm'.*pso_swarm_size"):
        exoid.identify(np.eye(3), np.ones(3), method="pso", swarm=3)
    with pytest.raises(ValueError, match="w_max"):
        exoid.identify(np.eye(3), np.ones(3), method="pso", pso_w_max=5.0)
    with pytest.raises(ValueError, match="pso_boundary must be 'clamp' or 'reflect'"):
        exoid.identify(np.eye(3), np.ones(3), method="pso", pso_boundary="wrap")
    with pytest.raises(ValueError, match="dataset: missing key 'tau'"):
        exoid.process_record({"t": np.zeros(3), "q": np.zeros((3, 2))}, thigh_length_m=0.45)


def test_lowpass_and_differentiate_against_closed_forms():
    fs, t = 1000.0, np.arange(4000) / 1000.0
    x = np.column_stack([np.sin(2 * np.pi * 1.0 * t), np.sin(2 * np.pi * 200.0 * t)])
    y = exoid.lowpass(x, cutoff_hz=10.0, sample_rate_hz=fs)
    mid = slice(500, 3500)
    # Zero phase, |H|^2 of a 2nd-order Butterworth applied twice: 1 / (1 + (f/fc)^4) per pass.
    assert np.max(np.abs(y[mid, 0] - x[mid, 0] / (1 + (1.0 / 10.0) ** 4))) < 1e-3
    assert np.max(np.abs(y[mid, 1])) < 1.0 / (1 + (200.0 / 10.0) ** 4) * 2
    d = exoid.differentiate(x[:, :1], dt_s=1e-3, method="central4")
    assert np.max(np.abs(d[2:-2, 0] - 2 * np.pi * np.cos(2 * np.pi * t[2:-2]))) < 1e-9


needs_simulator = pytest.mark.skipif(not exoid.has_simulator, reason="built without MuJoCo")


@needs_simulator
def test_simulated_rigid_leg_gives_back_its_truth():
    """MuJoCo's rig (cylinder mass 0: the 2-link model is exact) against the module's regressor:
    LS on the exact columns returns the model's own X (as tests/integration does in C++)."""
    sim = exoid.simulate(trajectory=3, duration=10, cylinder_mass_scale=0)
    d, truth = sim["dataset"], sim["truth"]
    e = d["extra"]
    q = np.column_stack([e["q_hip_true"], e["q_knee_true"]])
    qd = np.column_stack([e["qd_hip_true"], e["qd_knee_true"]])
    qdd = np.column_stack([e["qdd_hip_true"], e["qdd_knee_true"]])
    hip, knee = exoid.regressor(q, qd, qdd, thigh_length_m=truth["thigh_length_m"], gravity_mps2=truth["gravity_mps2"])
    # The simulator's Coulomb law is fc tanh(qd / v0) (sidecar): use it in the Coulomb columns.
    v0 = sim["sidecar"]["truth"]["friction"]["v0_radps"]
    names = exoid.param_names()
    hip[:, names.index("fc1")] = np.tanh(qd[:, 0] / v0)
    knee[:, names.index("fc2")] = np.tanh(qd[:, 1] / v0)
    H = np.vstack([hip, knee])
    y = np.concatenate([e["tau_hip_true"], e["tau_knee_true"]])
    x = exoid.identify(H, y)["x"]
    assert np.max(np.abs(x - truth["x"]) / np.abs(truth["x"])) < 1e-3, (x, truth["x"])
    assert sim["sidecar"]["seed"] == 1


def run_cli(*args):
    import subprocess
    binary = exoid_binary()
    # Exit 3 = an estimate is not usable (e.g. implausible): its numbers are still written.
    done = subprocess.run([binary, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    assert done.returncode in (0, 3), done.stderr


@needs_simulator
def test_bindings_give_the_command_lines_numbers(tmp_path):
    """The same records through `exoid simulate` + `exoid identify` and through the module: the
    segmental LS (and its standard errors, stage by stage), RLS-PSO and IDIM-IV estimates agree to
    the CSV's 17 significant digits."""
    opts = dict(duration=4, noise_tau=0.5, noise_q_deg=0.01)
    knee = exoid.simulate(trajectory=1, seed=3, **opts)
    both = exoid.simulate(trajectory=3, seed=4, **opts)
    lt = knee["truth"]["thigh_length_m"]
    for name, traj, seed in (("k.csv", 1, 3), ("b.csv", 3, 4)):
        run_cli("simulate", "--trajectory", str(traj), "--seed", str(seed), "--duration", "4", "--noise-tau", "0.5",
                "--noise-q-deg", "0.01", "--out", str(tmp_path / name))
    out = tmp_path / "id.json"
    run_cli("identify", "--knee-data", str(tmp_path / "k.csv"), "--both-data", str(tmp_path / "b.csv"),
            "--method", "ls", "--method", "rls-pso", "--method", "idim-iv", "--pso-iterations", "400", "--seed", "9",
            "--json", str(out))
    import json
    with open(out) as f:
        methods = json.load(f)["methods"]
    cli = {name: np.array([m["parameters"][n] for n in exoid.param_names()]) for name, m in methods.items()}
    py = exoid.identify_segmental(knee["dataset"], both["dataset"], thigh_length_m=lt, method="rls-pso",
                                  pso_iterations=400, seed=9)["x"]
    iv = exoid.identify_idim_iv(both["dataset"], lt, knee_record=knee["dataset"])["x"]
    assert np.allclose(py, cli["rls-pso"], rtol=1e-9, atol=1e-12), (py, cli["rls-pso"])
    assert np.allclose(iv, cli["idim-iv"], rtol=1e-9, atol=1e-12), (iv, cli["idim-iv"])
    ls = exoid.identify_segmental(knee["dataset"], both["dataset"], thigh_length_m=lt, method="ls")
    cli_se = np.array([methods["ls"]["segmental_errors"]["standard_errors"][n] for n in exoid.param_names()])
    assert np.allclose(ls["x"], cli["ls"], rtol=1e-9, atol=1e-12), (ls["x"], cli["ls"])
    assert np.allclose(ls["std_error"], cli_se, rtol=1e-9, atol=1e-15), (ls["std_error"], cli_se)
    assert np.all(ls["std_error"] > 0)


@needs_simulator
def test_simulate_option_mistakes_name_the_option():
    with pytest.raises(TypeError, match="unexpected keyword argument 'trajectry'"):
        exoid.simulate(trajectry=3)
    with pytest.raises(ValueError, match="--trajectory: Value 9 not in range 1 to 4"):
        exoid.simulate(trajectory=9)


def test_results_carry_the_warnings_the_command_line_prints():
    # A well-posed fit has none; nearly parallel columns (condition > 100) are said, as identify's
    # "excitation" line says them; an unidentified column and an unusable result too.
    rng = np.random.default_rng(5)
    H = rng.normal(size=(400, 3))
    y = H @ np.array([1.0, 2.0, 3.0])
    assert exoid.identify(H, y)["warnings"] == []
    H2 = H.copy()
    H2[:, 2] = H2[:, 1] + 1e-3 * rng.normal(size=400)
    fit = exoid.identify(H2, H2 @ np.array([1.0, 2.0, 3.0]))
    assert any("condition number" in w and "> 100" in w for w in fit["warnings"]), fit["warnings"]
    H3 = H.copy()
    H3[:, 2] = H3[:, 1]
    fit = exoid.identify(H3, y)
    assert any("not identified" in w for w in fit["warnings"]), fit["warnings"]
    assert any(w.startswith("not usable") for w in fit["warnings"]), fit["warnings"]
