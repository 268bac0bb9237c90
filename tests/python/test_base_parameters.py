"""Base parameters (exoid.ChainModel.base_parameters: Eigen's QR with column pivoting) against an
independent computation in numpy: the rank and null space of the same chains' regressor from an
SVD over other random states. The base parameters' space is unique (the regressor's row space),
whatever the pivots, so the check is: same rank, and every combination orthogonal to numpy's null
space."""
import numpy as np

import exoid


def sagittal_leg(ankle_armature=True):
    """hip, knee, ankle about +y, links along -z (thigh 0.42 m, shank 0.40 m), foot offset forward."""
    return exoid.ChainModel([
        dict(name="hip", link="thigh", axis=[0, 1, 0]),
        dict(name="knee", link="shank", axis=[0, 1, 0], origin_m=[0, 0, -0.42]),
        dict(name="ankle", link="foot", axis=[0, 1, 0], origin_m=[0.0, 0, -0.40], armature=ankle_armature),
    ], name="sagittal")


def numpy_rank_and_null_space(model, samples=300, seed=4):
    rng = np.random.default_rng(seed)
    n = model.dof
    W = np.vstack([model.regressor(rng.uniform(-np.pi, np.pi, n), rng.uniform(-3, 3, n), rng.uniform(-30, 30, n))
                   for _ in range(samples)])
    _, s, vt = np.linalg.svd(W)
    rank = int((s > 1e-9 * s[0]).sum())
    return rank, vt[rank:].T


def check(model, expected_rank=None):
    b = model.base_parameters()
    rank, null = numpy_rank_and_null_space(model)
    assert b["rank"] == rank
    if expected_rank is not None:
        assert rank == expected_rank
    C = np.asarray(b["combination"])
    assert C.shape == (rank, len(model.parameter_names))
    assert np.abs(C @ null).max() < 1e-9
    assert np.linalg.matrix_rank(C) == rank
    return b


def test_three_dof_sagittal_leg_against_numpy():
    # A planar chain of 3 links: each link's mx, mz, Iyy (9; the distal links' masses regroup into
    # the proximal ones' mz and Iyy), each joint's fc, fv (6), the ankle's armature (1): 16.
    b = check(sagittal_leg(), expected_rank=16)
    assert any("foot.m" in c for c in b["combinations"])  # the foot's mass rides in the shank's terms


def test_spatial_chain_against_numpy():
    rng = np.random.default_rng(8)
    joints = []
    for i in range(4):
        axis = rng.normal(size=3)
        joints.append(dict(name=f"j{i}", link=f"l{i}", axis=axis / np.linalg.norm(axis),
                           origin_m=rng.uniform(-0.3, 0.3, 3)))
    check(exoid.ChainModel(joints, name="spatial"))
