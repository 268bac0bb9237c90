"""A chain out of a tree (--base/--tip, load_chain's base and tip) against Orocos KDL's own:
Tree::getChain on the tree kdl_parser builds from the same URDF (python3-pykdl, from Debian; the
URDF read here with xml.etree as kdl_parser reads it), inverse dynamics by ChainIdSolver_RNE.
The URDF is a two-legged exoskeleton with trunk, arms and head (tests/data/two_leg_exo.urdf)."""
import json
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import exoid
from cli_support import exoid_binary, identify
from kdl_support import PyKDL, kdl_frame, kdl_torques, kdl_vector
if not exoid.has_simulator:
    pytest.skip("built without MuJoCo and urdfdom, which read robot models", allow_module_level=True)

SOURCE = os.environ.get("EXOID_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
URDF = os.path.join(SOURCE, "tests", "data", "two_leg_exo.urdf")
# Both sides sum O(10^2) products of O(1..100) factors: roundoff ~1e-14 of the torque scale.
REL_TOL = 1e-12


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def origin_of(element):
    o = element.find("origin")
    xyz = np.array([float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()])
    rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
    return xyz, rpy_matrix(*rpy)


def body_of(link):
    """(mass, COM, inertia about the COM) of a link in its own frame (kdl_parser's reading)."""
    inertial = link.find("inertial")
    if inertial is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    c, R = origin_of(inertial)
    i = inertial.find("inertia")
    I = np.array([[float(i.get("ixx")), float(i.get("ixy")), float(i.get("ixz"))],
                  [float(i.get("ixy")), float(i.get("iyy")), float(i.get("iyz"))],
                  [float(i.get("ixz")), float(i.get("iyz")), float(i.get("izz"))]])
    return float(inertial.find("mass").get("value")), c, R @ I @ R.T


def merged(a, b):
    """Two bodies (mass, COM, inertia about the COM) in one frame as one (parallel axis theorem)."""
    m = a[0] + b[0]
    if m == 0.0:
        return a
    c = (a[0] * a[1] + b[0] * b[1]) / m
    shift = lambda body: body[2] + body[0] * ((body[1] - c) @ (body[1] - c) * np.eye(3) - np.outer(body[1] - c, body[1] - c))
    return m, c, shift(a) + shift(b)


def kdl_tree(path):
    """As kdl_parser's treeFromUrdfModel (a segment per moving joint's child link, its joint at the
    joint's origin), except that a link on a fixed joint is merged into its parent's segment: KDL's
    Tree::getChain keeps the segments on the path only, and would drop a fixed branch's mass (a
    thigh cuff) that rides with the chain. Returns the tree and which segment holds each link."""
    robot = ET.parse(path).getroot()
    links = {l.get("name"): l for l in robot.findall("link")}
    joints = robot.findall("joint")
    children = {j.find("child").get("link") for j in joints}
    root = next(name for name in links if name not in children)
    segments, body, owner = [], {root: (0.0, np.zeros(3), np.zeros((3, 3)))}, {}

    def visit(segment, link, p, R):  # `link` rides with `segment`, at (p, R) in its frame
        owner[link] = segment
        m, c, I = body_of(links[link])
        body[segment] = merged(body[segment], (m, p + R @ c, R @ I @ R.T))
        for j in joints:
            if j.find("parent").get("link") != link:
                continue
            pj, Rj = origin_of(j)
            child = j.find("child").get("link")
            if j.get("type") == "fixed":
                visit(segment, child, p + R @ pj, R @ Rj)
                continue
            axis = np.array([float(v) for v in j.find("axis").get("xyz").split()])
            segments.append((child, segment, j, p + R @ pj, R @ Rj, axis))
            body[child] = (0.0, np.zeros(3), np.zeros((3, 3)))
            visit(child, child, np.zeros(3), np.eye(3))

    visit(root, root, np.zeros(3), np.eye(3))
    tree = PyKDL.Tree(root)
    for child, parent, j, p, R, axis in segments:
        kind = PyKDL.Joint.TransAxis if j.get("type") == "prismatic" else PyKDL.Joint.RotAxis
        joint = PyKDL.Joint(j.get("name"), kdl_vector(p), kdl_vector(R @ axis), kind)
        m, c, I = body[child]
        inertia = PyKDL.RigidBodyInertia(m, kdl_vector(c),
                                         PyKDL.RotationalInertia(I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))
        assert tree.addSegment(PyKDL.Segment(child, joint, kdl_frame(p, R), inertia), parent)
    return tree, owner


def kdl_chain(path, base, tip):
    tree, owner = kdl_tree(path)
    return tree.getChain(owner[base], owner[tip])


def friction_of(path):
    robot = ET.parse(path).getroot()
    out = {}
    for j in robot.findall("joint"):
        d = j.find("dynamics")
        out[j.get("name")] = (float(d.get("friction", 0)), float(d.get("damping", 0))) if d is not None else (0.0, 0.0)
    return out


def without_friction(leg):
    phi = np.array(leg["phi"], dtype=float)
    for k, name in enumerate(leg["model"].parameter_names):
        if name.endswith(".fc") or name.endswith(".fv"):
            phi[k] = 0.0
    return phi


# (base, tip, gravity in the base's frame at q = 0): pelvis sits on base_link by a translation;
# l_thigh is turned by its hip_pitch origin's roll of 0.05 rad.
CASES = [("pelvis", "l_sole", np.array([0.0, 0.0, -9.81])),
         ("pelvis", "r_sole", np.array([0.0, 0.0, -9.81])),
         ("l_thigh", "l_sole", rpy_matrix(0.05, 0.0, 0.0).T @ np.array([0.0, 0.0, -9.81]))]


@pytest.mark.parametrize("base,tip,gravity", CASES)
def test_a_leg_out_of_the_tree_equals_kdls_get_chain(base, tip, gravity):
    leg = exoid.load_chain(URDF, base=base, tip=tip)
    chain = kdl_chain(URDF, base, tip)
    assert chain.getNrOfJoints() == len(leg["joints"])
    phi = without_friction(leg)
    rng = np.random.default_rng(37)
    worst = 0.0
    for _ in range(50):
        n = len(leg["joints"])
        q, qd, qdd = rng.uniform(-1.5, 1.5, n), rng.uniform(-2, 2, n), rng.uniform(-5, 5, n)
        ours = leg["model"].regressor(q, qd, qdd) @ phi
        theirs = kdl_torques(chain, gravity, q, qd, qdd)
        worst = max(worst, np.abs(ours - theirs).max() / max(1.0, np.abs(theirs).max()))
    assert worst <= REL_TOL, f"largest difference {worst:.3g} of the torque scale"


def test_a_tree_without_a_tip_is_refused_with_its_leaves():
    with pytest.raises(ValueError, match="l_sole, l_thigh_cuff, r_sole"):
        exoid.load_chain(URDF)


def record(path, joints, chain, friction, gravity, seed, duration_s=20.0, dt_s=0.002):
    """Exact torques (KDL plus the URDF's friction) along a multisine, with exact derivatives."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration_s, dt_s)
    n = len(joints)
    f = rng.uniform(0.1, 0.6, (n, 3))
    a = rng.uniform(0.1, 0.4, (n, 3))
    ph = rng.uniform(0, 2 * math.pi, (n, 3))
    w = 2 * math.pi * f
    q = np.einsum("jk,tjk->tj", a, np.sin(w[None] * t[:, None, None] + ph[None]))
    qd = np.einsum("jk,tjk->tj", a * w, np.cos(w[None] * t[:, None, None] + ph[None]))
    qdd = np.einsum("jk,tjk->tj", -a * w * w, np.sin(w[None] * t[:, None, None] + ph[None]))
    tau = np.array([kdl_torques(chain, gravity, q[i], qd[i], qdd[i]) for i in range(len(t))])
    for k, j in enumerate(joints):
        fc, fv = friction[j]
        tau[:, k] += fc * np.sign(qd[:, k]) + fv * qd[:, k]
    header = ["t"] + [f"{p}_{j}" for p in ("q", "qd", "qdd", "tau") for j in joints]
    np.savetxt(path, np.column_stack([t, q, qd, qdd, tau]), delimiter=",", header=",".join(header), comments="", fmt="%.17g")


def left_leg_records(folder, fit_seed, check_seed):
    """A fit and a validation record of the exoskeleton's left leg (CASES[0]), exact (KDL's torques)."""
    base, tip, gravity = CASES[0]
    joints = exoid.load_chain(URDF, base=base, tip=tip)["joints"]
    chain = kdl_chain(URDF, base, tip)
    paths = (folder / f"fit_{fit_seed}.csv", folder / f"check_{check_seed}.csv")
    for path, seed in zip(paths, (fit_seed, check_seed)):
        record(path, joints, chain, friction_of(URDF), gravity, seed)
    return paths


def test_identify_is_exact_on_one_leg_of_the_tree_from_kdl_data(tmp_path):
    binary = exoid_binary()
    base, tip, _ = CASES[0]
    fit, check = left_leg_records(tmp_path, 1, 2)
    out = tmp_path / "id.json"
    done = identify(binary, "--model", URDF, "--base", base, "--tip", tip, "--data", fit, "--validate", check, "--json", out)
    assert done.returncode == 0, done.stdout + done.stderr
    j = json.loads(out.read_text())
    rms = [joint["rms_error_Nm"] for v in j["validation"] for joint in v["joints"]]
    assert len(rms) == 6 and max(rms) <= 1e-6, rms
    # The same URDF without the options: exit 1 listing the leaf links to choose a tip from.
    done = identify(binary, "--model", URDF, "--data", fit)
    assert done.returncode == 1 and "l_sole" in done.stderr and "r_sole" in done.stderr, done.stderr


def arm_urdf(path, dof=7, seed=7):
    """A random spatial arm (axes off the frame's axes, rolled joint frames) with a fixed tool."""
    rng = np.random.default_rng(seed)
    parts = ['<robot name="random_arm"><link name="arm_base_link"/>']
    parent = "arm_base_link"
    for k in range(dof):
        link = f"arm_link_{k + 1}"
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        a, b = rng.uniform(0.005, 0.05, 2)
        parts.append(f'<link name="{link}"><inertial><origin xyz="{rng.uniform(-.05, .05):.4f} {rng.uniform(-.05, .05):.4f} {rng.uniform(0, .15):.4f}"/>'
                     f'<mass value="{rng.uniform(0.5, 4):.3f}"/><inertia ixx="{a:.5f}" ixy="0.001" ixz="0" iyy="{b:.5f}" iyz="0" izz="{a + b - 0.001:.5f}"/></inertial></link>')
        parts.append(f'<joint name="arm_joint_{k + 1}" type="revolute"><parent link="{parent}"/><child link="{link}"/>'
                     f'<origin xyz="{rng.uniform(-.1, .1):.3f} {rng.uniform(-.1, .1):.3f} {rng.uniform(.1, .3):.3f}" rpy="{rng.uniform(-1, 1):.3f} {rng.uniform(-1, 1):.3f} 0"/>'
                     f'<axis xyz="{axis[0]:.6f} {axis[1]:.6f} {axis[2]:.6f}"/><limit lower="-3" upper="3" effort="100" velocity="5"/>'
                     f'<dynamics damping="0.1" friction="0.2"/></joint>')
        parent = link
    parts.append('<link name="tool0"/><joint name="flange" type="fixed"><parent link="arm_link_7"/><child link="tool0"/><origin xyz="0 0 0.1"/></joint>')
    parts.append("</robot>")
    path.write_text("\n".join(parts) + "\n")


def test_a_seven_joint_arms_identify_output_fits_a_terminal(tmp_path):
    binary = exoid_binary()
    urdf = tmp_path / "arm.urdf"
    arm_urdf(urdf)
    arm = exoid.load_chain(str(urdf))
    chain = kdl_chain(str(urdf), "arm_base_link", "tool0")
    gravity = np.array([0.0, 0.0, -9.81])
    record(tmp_path / "fit.csv", arm["joints"], chain, friction_of(str(urdf)), gravity, 3)
    record(tmp_path / "check.csv", arm["joints"], chain, friction_of(str(urdf)), gravity, 4)
    out = tmp_path / "id.json"
    done = identify(binary, "--model", urdf, "--data", tmp_path / "fit.csv", "--validate", tmp_path / "check.csv", "--json", out)
    assert done.returncode == 0, done.stdout + done.stderr
    long_lines = [line for line in (done.stdout + done.stderr).splitlines() if len(line) > 120]
    assert not long_lines, f"{len(long_lines)} lines over 120 characters, e.g. {long_lines[0]}"
    j = json.loads(out.read_text())
    base = j["base_parameters"]
    # Short labels, each combination written out once in the JSON.
    assert max(len(n) for n in base["names"]) < 40 and len(base["combinations"]) == len(base["names"])
    assert any(" + " in c or " - " in c for c in base["combinations"])
    assert max(joint["rms_error_Nm"] for v in j["validation"] for joint in v["joints"]) <= 1e-6


def test_the_cad_beside_the_estimate(tmp_path):
    """The model file's own values of every base parameter beside the estimate: equal to it on exact
    data from that file; from a file whose masses are 20 % off, a larger validation torque error."""
    binary = exoid_binary()
    base, tip, _ = CASES[0]
    fit, check = left_leg_records(tmp_path, 5, 6)
    import re
    heavier = tmp_path / "heavier.urdf"
    heavier.write_text(re.sub(r'<mass value="([0-9.]+)"/>', lambda m: f'<mass value="{1.2 * float(m.group(1)):.6g}"/>', open(URDF).read()))
    results = {}
    for name, model in (("cad", URDF), ("heavier", str(heavier))):
        out = tmp_path / f"{name}.json"
        done = identify(binary, "--model", model, "--base", base, "--tip", tip, "--data", fit, "--validate", check, "--json", out)
        assert done.returncode == 0, done.stdout + done.stderr
        assert "the model file's own parameters (CAD): torque error RMS" in " ".join(done.stdout.split())
        results[name] = json.loads(out.read_text())
    b = results["cad"]["base_parameters"]
    assert np.allclose(b["cad"], b["ls"], rtol=0, atol=1e-6 * max(1.0, np.abs(b["ls"]).max()))
    joints = results["heavier"]["validation"][0]["joints"]
    for joint in joints:
        assert joint["cad_rms_error_Nm"] > 100 * max(joint["rms_error_Nm"], 1e-9), joint
