"""Shapes: validation, properties, hulls (faces outward, volume, area, flat input), repr, pickling."""
import copy
import pickle

import numpy as np
import pytest

import hedra
from conftest import pose7, shape_zoo

CUBE = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)


def test_properties():
    s = hedra.Sphere(0.5, margin=0.1)
    assert s.radius == 0.5 and s.margin == 0.1 and s.bounding_radius == pytest.approx(0.6)
    b = hedra.Box((1, 2, 3))
    assert np.array_equal(b.half_extents, [1, 2, 3]) and b.bounding_radius == pytest.approx(np.sqrt(14))
    for cls in (hedra.Capsule, hedra.Cylinder, hedra.Cone):
        c = cls(0.25, 0.75, margin=0.0)
        assert c.radius == 0.25 and c.half_length == 0.75 and c.margin == 0.0
    assert isinstance(hedra.Cone(1, 1), hedra.Shape)
    with pytest.raises(TypeError):
        hedra.Sphere(0.5, 0.1)  # margin is keyword-only
    with pytest.raises(AttributeError):
        s.radius = 2.0  # immutable


def test_cube_hull():
    h = hedra.ConvexHull(np.vstack([CUBE, [[0, 0, 0], [0.5, 0.5, 0.5]]]))  # inner points dropped
    assert h.vertices.shape == (8, 3)
    assert sorted(map(tuple, h.vertices)) == sorted(map(tuple, CUBE))
    assert h.volume == pytest.approx(8.0, rel=1e-12)
    assert h.area == pytest.approx(24.0, rel=1e-12)
    assert np.allclose(h.centroid, 0.0, atol=1e-15)
    assert h.triangles.dtype == np.int64 and h.triangles.shape[1] == 3
    assert len(h.triangles) == sum(len(f) - 2 for f in h.faces)
    assert h.points.shape == (10, 3)


def test_hull_faces_counter_clockwise_from_outside(rng):
    pts = rng.normal(size=(60, 3)) + [5.0, -3.0, 2.0]  # off the origin: vertices stay in the points' frame
    h = hedra.ConvexHull(pts)
    v = h.vertices
    centre = v.mean(axis=0)
    for face in h.faces:
        assert face.dtype == np.int64
        p = v[face]
        n = np.cross(p[1] - p[0], p[2] - p[0])
        assert n @ (p[0] - centre) > 0  # counter-clockwise seen from outside: the normal points away
        assert np.all((v - p[0]) @ n <= 1e-9 * np.linalg.norm(n))  # convex: every vertex behind
    # every input point inside or on the hull, and the hull's vertices are input points
    for p in pts:  # vertices are on the surface up to the rounding of the hull's recentring
        assert hedra.distance(h, np.eye(4), hedra.Sphere(0.0), pose7(p)).distance <= 1e-14
    # the hull's vertices are input points (up to the rounding of the recentring)
    assert all(np.min(np.abs(pts - x).max(axis=1)) <= 1e-14 * 8 for x in v)
    # volume of the triangles (divergence theorem) equals .volume
    t = v[h.triangles] - centre
    vol = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6
    assert vol == pytest.approx(h.volume, rel=1e-12)


def test_flat_and_degenerate_hulls():
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    flat = hedra.ConvexHull(square)
    assert flat.volume == 0.0
    assert len(flat.vertices) == 4
    # a flat hull is a valid shape
    d = hedra.distance(flat, np.eye(4), hedra.Sphere(0.1), pose7((0.5, 0.5, 1.0)))
    assert d.distance == pytest.approx(0.9, abs=1e-12)
    seg = hedra.ConvexHull([[0, 0, 0], [1, 0, 0], [0.5, 0, 0]])
    assert len(seg.vertices) == 2 and seg.faces == [] and seg.triangles.shape == (0, 3)
    point = hedra.ConvexHull([[1, 2, 3]])
    assert np.array_equal(point.vertices, [[1, 2, 3]])
    assert hedra.distance(point, np.eye(4), hedra.Sphere(1.0), np.eye(4)).distance == pytest.approx(
        np.sqrt(14) - 1, abs=1e-12
    )


@pytest.mark.parametrize("shape", shape_zoo(), ids=lambda s: type(s).__name__)
def test_pickle_and_copy_give_the_same_bits(shape, rng):
    clone = pickle.loads(pickle.dumps(shape))
    assert type(clone) is type(shape) and repr(clone) == repr(shape)
    assert clone.margin == shape.margin and clone.bounding_radius == shape.bounding_radius
    other = hedra.Box([0.3, 0.2, 0.4])
    for _ in range(20):
        p = np.append(rng.uniform(-1, 1, 3), rng.normal(size=4))
        a = hedra.penetration(shape, p, other, np.eye(4))
        b = hedra.penetration(clone, p, other, np.eye(4))
        assert a.distance == b.distance and np.array_equal(a.normal, b.normal)
    assert repr(copy.deepcopy(shape)) == repr(shape)


def test_repr_is_readable():
    assert repr(hedra.Sphere(0.5)) == "Sphere(radius=0.5, margin=0.0)"
    assert repr(hedra.Box([1, 2, 3], margin=0.25)) == "Box(half_extents=[1.0, 2.0, 3.0], margin=0.25)"
    assert repr(hedra.Capsule(0.1, 0.3)) == "Capsule(radius=0.1, half_length=0.3, margin=0.0)"
    assert repr(hedra.ConvexHull(CUBE)) == "ConvexHull(<8 vertices, 6 faces>, margin=0.0)"
    assert "distance=1.0" in repr(hedra.distance(hedra.Sphere(0.5), np.eye(4), hedra.Sphere(0.5), pose7((2, 0, 0))))


def test_margin_rounds_a_shape():
    rounded = hedra.Box([0.5, 0.5, 0.5], margin=0.1)
    d = hedra.distance(rounded, np.eye(4), hedra.Sphere(0.2), pose7((0, 0, 1.5)))
    assert d.distance == pytest.approx(1.5 - 0.6 - 0.2, abs=1e-12)
