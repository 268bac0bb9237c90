"""exoid's generic chain regressor (ident/model, recursive Newton-Euler in regressor form) against
an independent inverse dynamics: Orocos KDL's ChainIdSolver_RNE (python3-pykdl, from Debian) on
random spatial 6-DOF chains built the way kdl_parser builds a URDF's. KDL computes torques, not a
regressor, so the check is Y(q, qd, qdd) @ phi == KDL's tau for random physical phi."""
import numpy as np
import pytest

import exoid
from kdl_support import PyKDL, kdl_frame, kdl_torques, kdl_vector

# Both sides sum O(10^2) products of O(1..100) factors: roundoff is ~1e-14 relative; 1e-12 is
# the bar.
REL_TOL = 1e-12


def random_rotation(rng):
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def random_inertia(rng):
    a, b = rng.uniform(0.01, 0.5, size=2)
    c = rng.uniform(abs(a - b) + 1e-3, a + b)
    R = random_rotation(rng)
    return R @ np.diag([a, b, c]) @ R.T


def random_chain(rng, dof, armature):
    joints, bodies = [], []
    for i in range(dof):
        axis = rng.normal(size=3)
        joints.append(dict(name=f"j{i}", link=f"l{i}", rotation=random_rotation(rng),
                           origin_m=rng.uniform(-0.4, 0.4, size=3), axis=axis / np.linalg.norm(axis),
                           friction=False, armature=armature and i % 2 == 1))
        bodies.append(dict(m=rng.uniform(0.2, 8.0), c=rng.uniform(-0.3, 0.3, size=3), Ic=random_inertia(rng),
                           Ia=rng.uniform(0.01, 1.0)))
    g = rng.normal(size=3)
    return joints, bodies, 9.81 * g / np.linalg.norm(g)


def kdl_chain(joints, bodies):
    """As kdl_parser does for a URDF: the joint's origin and axis in the parent link's frame, the
    segment's tip = the child link's frame at q = 0, its inertia in that frame about the COM."""
    chain = PyKDL.Chain()
    for j, b in zip(joints, bodies):
        origin, R = j["origin_m"], j["rotation"]
        armature = b["Ia"] if j["armature"] else 0.0
        joint = PyKDL.Joint(j["name"], kdl_vector(origin), kdl_vector(R @ j["axis"]), PyKDL.Joint.RotAxis,
                            1.0, 0.0, armature, 0.0, 0.0)
        tip = kdl_frame(origin, R)
        I = b["Ic"]
        inertia = PyKDL.RigidBodyInertia(b["m"], kdl_vector(b["c"]),
                                         PyKDL.RotationalInertia(I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))
        chain.addSegment(PyKDL.Segment(j["link"], joint, tip, inertia))
    return chain


@pytest.mark.parametrize("armature", [False, True])
def test_generic_regressor_equals_kdl_on_random_spatial_chains(armature):
    rng = np.random.default_rng(2026 + armature)
    worst = 0.0
    for trial in range(50):
        joints, bodies, gravity = random_chain(rng, 6, armature)
        model = exoid.ChainModel(joints, gravity_mps2=gravity)
        phi = []
        for j, b in zip(joints, bodies):
            phi.extend(exoid.link_parameters(b["m"], b["c"], b["Ic"]))
            if j["armature"]:
                phi.append(b["Ia"])
        q, qd, qdd = rng.uniform(-3, 3, 6), rng.uniform(-2, 2, 6), rng.uniform(-5, 5, 6)
        ours = model.regressor(q, qd, qdd) @ np.array(phi)
        theirs = kdl_torques(kdl_chain(joints, bodies), gravity, q, qd, qdd)
        scale = max(1.0, np.abs(theirs).max())
        worst = max(worst, np.abs(ours - theirs).max() / scale)
    assert worst <= REL_TOL, f"largest difference {worst:.3g} of the torque scale"


def test_parameter_names_and_size():
    joints = [dict(name="hip", link="thigh", axis=[0, 1, 0]),
              dict(name="knee", link="shank", axis=[0, 1, 0], origin_m=[0, 0, -0.45], armature=True)]
    model = exoid.ChainModel(joints)
    names = model.parameter_names
    assert names[:2] == ["thigh.m", "thigh.mx"] and names[10:12] == ["hip.fc", "hip.fv"] and names[-1] == "knee.Ia"
    assert model.regressor(np.zeros(2), np.zeros(2), np.zeros(2)).shape == (2, len(names))
    with pytest.raises(ValueError, match="unit vector"):
        exoid.ChainModel([dict(name="a", link="b", axis=[0, 0, 2])])
