"""What the tests against Orocos KDL (python3-pykdl, from Debian) share: numpy in, KDL's types, and
KDL's recursive Newton-Euler torques of a chain. Importing it skips a test module where PyKDL is
missing."""
import numpy as np
import pytest

PyKDL = pytest.importorskip("PyKDL")


def kdl_vector(v):
    return PyKDL.Vector(*map(float, v))


def kdl_rotation(R):
    return PyKDL.Rotation(*map(float, np.asarray(R).reshape(-1)))


def kdl_frame(p, R):
    return PyKDL.Frame(kdl_rotation(R), kdl_vector(p))


def kdl_torques(chain, gravity, q, qd, qdd):
    """ChainIdSolver_RNE's joint torques at (q, qd, qdd), gravity in the chain's base frame."""
    n = chain.getNrOfJoints()
    arrays = []
    for v in (q, qd, qdd):
        a = PyKDL.JntArray(n)
        for k in range(n):
            a[k] = float(v[k])
        arrays.append(a)
    tau = PyKDL.JntArray(n)
    wrenches = [PyKDL.Wrench() for _ in range(chain.getNrOfSegments())]
    assert PyKDL.ChainIdSolver_RNE(chain, kdl_vector(gravity)).CartToJnt(*arrays, wrenches, tau) >= 0
    return np.array([tau[k] for k in range(n)])
