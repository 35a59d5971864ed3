"""Shared helpers of the hedra Python tests (run by ctest with PYTHONPATH set to build/python)."""
import numpy as np
import pytest

import hedra


def pose7(t=(0.0, 0.0, 0.0), q=(1.0, 0.0, 0.0, 0.0)):
    """A 7-vector pose [x, y, z, qw, qx, qy, qz]."""
    return np.array([*t, *q], dtype=float)


def random_quaternions(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def random_poses(rng, n, spread=1.0):
    """(n, 7) random poses, translations in [-spread, spread]^3."""
    return np.hstack([rng.uniform(-spread, spread, size=(n, 3)), random_quaternions(rng, n)])


def matrix_of(p):
    """The 4x4 transform of a 7-vector pose (independent of hedra: the unit quaternion's rotation matrix)."""
    w, x, y, z = np.asarray(p[3:], dtype=float) / np.linalg.norm(p[3:])
    m = np.eye(4)
    m[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    m[:3, 3] = p[:3]
    return m


def shape_zoo(rng=None):
    """One shape of every kind, some with margins."""
    rng = rng or np.random.default_rng(7)
    return [
        hedra.Sphere(0.4),
        hedra.Box([0.5, 0.3, 0.2]),
        hedra.Box([0.3, 0.3, 0.3], margin=0.05),
        hedra.Capsule(0.2, 0.4),
        hedra.Cylinder(0.3, 0.25),
        hedra.Cone(0.35, 0.3, margin=0.02),
        hedra.ConvexHull(rng.normal(scale=0.4, size=(24, 3))),
    ]


@pytest.fixture
def rng():
    return np.random.default_rng(20261128)
