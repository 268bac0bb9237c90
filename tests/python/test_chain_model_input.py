"""The robot as an input in Python: load a chain from its file, simulate it, process its record and
fit its base parameters, the same path as `exoid simulate/identify --model leg3`."""
import numpy as np
import pytest

import exoid
from cli_support import exoid_binary

pytestmark = pytest.mark.skipif(not exoid.has_simulator, reason="built without MuJoCo")


def test_load_chain_gives_the_model_its_parameters_and_limits():
    leg = exoid.load_chain("leg3")
    assert leg["joints"] == ["hip", "knee", "ankle"]
    assert leg["name"] == "leg3"
    model = leg["model"]
    assert len(leg["phi"]) == len(model.parameter_names)
    assert model.base_parameters()["rank"] == 17
    assert leg["limits"]["hip"]["q_min_rad"] == -1.6
    assert leg["limits"]["ankle"]["tau_max_Nm"] == 80.0
    with pytest.raises(ValueError):
        exoid.load_chain("/nonexistent/robot.urdf")


def test_simulate_process_and_fit_leg3():
    leg = exoid.load_chain("leg3")
    model = leg["model"]
    run = exoid.simulate(model="leg3", duration=12, seed=3)
    data = run["dataset"]
    assert data["joints"] == ["hip", "knee", "ankle"]
    assert data["q"].shape[1] == 3
    rec = exoid.process_chain_record(model, data)
    base = model.base_parameters()
    Wb = rec["W"]  # the rows in base parameters
    assert Wb.shape[1] == base["rank"]
    beta = np.linalg.lstsq(Wb, rec["y"], rcond=None)[0]
    truth = np.array([run["truth"]["base_parameters"][n] for n in base["names"]])
    # The truth's base parameters are the model's own (the same combination of the file's phi).
    np.testing.assert_allclose(truth, np.asarray(base["combination"]) @ leg["phi"], rtol=1e-12, atol=1e-12)
    # Noise-free, angles differentiated, Coulomb smoothed: the fit predicts the torque to well under 1 %.
    rms = np.sqrt(np.mean((Wb @ beta - rec["y"]) ** 2)) / np.sqrt(np.mean(rec["y"] ** 2))
    assert rms < 0.01
    fit = model.consistent_fit(rec["W"], rec["y"], leg["phi"])
    assert min(fit["link_min_eigenvalue"]) > 0.0
    # A dataset of three joints given to the 2-link leg's processing is refused, not misread.
    with pytest.raises(ValueError):
        exoid.process_record(data, thigh_length_m=0.429)


def test_chain_idim_iv_gives_the_command_lines_numbers(tmp_path):
    """IDIM-IV on leg3 through the module and through `exoid identify --model leg3 --method idim-iv`
    on the same record: the same estimate (to the CSV's 17 significant digits)."""
    import json
    import subprocess
    binary = exoid_binary()
    csv, out = tmp_path / "rec.csv", tmp_path / "id.json"
    for args in (["simulate", "--model", "leg3", "--duration", "8", "--noise-q-deg", "0.02", "--noise-tau", "0.2", "--seed", "5",
                  "--out", str(csv)],
                 ["identify", "--model", "leg3", "--data", str(csv), "--method", "ls,idim-iv", "--json", str(out)]):
        done = subprocess.run([binary, *args], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        assert done.returncode == 0, done.stderr
    with open(out) as f:
        cli = np.array(json.load(f)["methods"]["idim-iv"]["beta"])
    leg = exoid.load_chain("leg3")
    py = exoid.identify_chain_idim_iv(leg["model"], exoid.read_dataset(str(csv), joints=leg["joints"]))
    assert py["names"] == leg["model"].base_parameters()["names"]
    np.testing.assert_allclose(py["x"], cli, rtol=1e-9, atol=1e-12)
    # Without its controller (no metadata, no file) the record is refused, naming what is missing.
    with pytest.raises(ValueError, match="controller"):
        data = exoid.read_dataset(str(csv), joints=leg["joints"])
        data["comments"] = []
        exoid.identify_chain_idim_iv(leg["model"], data)


def test_simulate_takes_every_option_of_the_command(tmp_path):
    """exoid.simulate() is `exoid simulate` (one implementation of its options): a leg out of a
    whole-body URDF (base, tip, lock), the rig options every leg takes (tau_bias, integral_hz,
    lock) and the chain's own (record_derivatives) give the command's record, value for value;
    what does not apply to the robot is refused naming the option."""
    import os
    import subprocess
    binary = exoid_binary()
    urdf = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "two_leg_exo.urdf")
    csv = tmp_path / "leg.csv"
    done = subprocess.run([binary, "simulate", "--model", urdf, "--base", "pelvis", "--tip", "l_shank", "--lock", "l_ankle_pitch=0.1",
                           "--lock", "l_ankle_roll=0", "--lock", "l_hip_yaw", "--tau-bias", "0.1,0,0,-0.2", "--integral-hz", "0.5",
                           "--record-derivatives", "--duration", "2", "--noise-tau", "0.3", "--seed", "4", "--out", str(csv)],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    assert done.returncode == 0, done.stderr
    run = exoid.simulate(model=urdf, base="pelvis", tip="l_shank", lock=["l_ankle_pitch=0.1", "l_ankle_roll=0", "l_hip_yaw"],
                         tau_bias=[0.1, 0, 0, -0.2], integral_hz=0.5, record_derivatives=True, duration=2, noise_tau=0.3, seed=4)
    side = run["sidecar"]
    assert side["model"]["selection"] == "--base pelvis --tip l_shank --lock l_ankle_pitch=0.1 --lock l_ankle_roll=0"
    assert side["config"]["locked"] == ["l_hip_yaw"]
    assert side["config"]["torque_bias_Nm"] == [0.1, 0, 0, -0.2]
    assert side["config"]["integral_hz"] == 0.5 and len(side["controller"]["ki"]) == 4
    # A tree's locks as load_chain takes them (a dict), and a chain flag given False, are the same run.
    same = exoid.simulate(model=urdf, base="pelvis", tip="l_shank", lock={"l_ankle_pitch": 0.1, "l_ankle_roll": 0}, duration=1,
                          record_derivatives=False)
    assert same["sidecar"]["model"]["selection"] == side["model"]["selection"]
    assert "qd" not in same["dataset"] or same["dataset"]["qd"] is None
    joints = ["l_hip_yaw", "l_hip_roll", "l_hip_pitch", "l_knee"]
    cli = exoid.read_dataset(str(csv), joints=joints)
    data = run["dataset"]
    assert data["joints"] == joints
    for key in ("t", "q", "tau", "qd", "qdd"):
        np.testing.assert_array_equal(data[key], cli[key], err_msg=key)
    with pytest.raises(ValueError, match="--tip"):
        exoid.simulate(model="leg3", tip="shank", duration=1)
    with pytest.raises(ValueError, match="--tau-bias: expected one bias per joint"):
        exoid.simulate(model="leg3", tau_bias=[0.1], duration=1)
    with pytest.raises(ValueError, match="--bandwidth"):
        exoid.simulate(trajectory=3, bandwidth=3, duration=1)
