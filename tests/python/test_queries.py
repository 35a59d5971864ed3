"""Single queries against closed forms: sphere-sphere, box-sphere, capsule-box, rays; pose forms; results."""
import math

import numpy as np
import pytest

import hedra
from conftest import matrix_of, pose7, random_poses, random_quaternions


def box_point_distance(half, p):
    """Distance from p (box frame) to the box, 0 inside."""
    return float(np.linalg.norm(np.maximum(np.abs(p) - half, 0.0)))


def test_sphere_sphere_closed_form(rng):
    for _ in range(200):
        ra, rb = rng.uniform(0.1, 1.0, size=2)
        ca, cb = rng.uniform(-2, 2, size=(2, 3))
        expected = np.linalg.norm(cb - ca) - ra - rb
        a, b = hedra.Sphere(ra), hedra.Sphere(rb)
        p = hedra.penetration(a, pose7(ca, random_quaternions(rng, 1)[0]), b, pose7(cb))
        assert p.status == "ok"
        assert p.distance == pytest.approx(expected, abs=1e-12)
        d = hedra.distance(a, pose7(ca), b, pose7(cb))
        assert d.distance == pytest.approx(max(expected, 0.0), abs=1e-12)
        assert d.intersecting == (expected <= 0)
        assert hedra.intersect(a, pose7(ca), b, pose7(cb)).intersecting == (expected <= 0)
        n = (cb - ca) / np.linalg.norm(cb - ca)
        assert np.allclose(p.normal, n, atol=1e-12)
        assert np.allclose(p.point_b - p.point_a, p.distance * p.normal, atol=1e-12)


def test_box_sphere_closed_form(rng):
    half = np.array([0.5, 0.3, 0.2])
    box = hedra.Box(half)
    for _ in range(300):
        q = random_quaternions(rng, 1)[0]
        box_pose = pose7(rng.uniform(-1, 1, 3), q)
        local = rng.uniform(-1.5, 1.5, size=3)
        # sphere centre outside the box, in world coordinates through the box's pose
        if np.all(np.abs(local) <= half):
            continue
        r = rng.uniform(0.05, 0.3)
        centre = matrix_of(box_pose) @ np.append(local, 1.0)
        expected = box_point_distance(half, local) - r
        res = hedra.penetration(box, box_pose, hedra.Sphere(r), pose7(centre[:3]))
        assert res.status == "ok"
        assert res.distance == pytest.approx(expected, abs=1e-10)
        if expected > 1e-9:
            d = hedra.distance(box, box_pose, hedra.Sphere(r), pose7(centre[:3]))
            assert d.distance == pytest.approx(expected, abs=1e-10)
            assert not d.intersecting


def test_sphere_inside_box_depth():
    box = hedra.Box([1.0, 2.0, 3.0])
    res = hedra.penetration(box, np.eye(4), hedra.Sphere(0.25), pose7((0.6, 0.0, 0.0)))
    # nearest face x = 1: depth 0.4 + 0.25
    assert res.distance == pytest.approx(-0.65, abs=1e-12)
    assert np.allclose(res.normal, [1, 0, 0])
    assert res.intersecting


def test_capsule_box_closed_form(rng):
    """A capsule above a box's top face, its segment's ends over the face: distance = lowest end - top - radius."""
    half = np.array([1.0, 0.8, 0.25])
    box = hedra.Box(half)
    for _ in range(200):
        radius, half_length = rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.4)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        centre = np.array([rng.uniform(-0.4, 0.4), rng.uniform(-0.3, 0.3), 0.0])
        ends = np.array([centre + half_length * axis, centre - half_length * axis])
        gap = rng.uniform(0.01, 1.0)
        lift = half[2] + radius + gap - ends[:, 2].min()
        centre[2] += lift
        # rotation taking local z to axis
        z = np.array([0.0, 0.0, 1.0])
        v, c = np.cross(z, axis), float(z @ axis)
        if np.linalg.norm(v) < 1e-9:
            q = (1.0, 0.0, 0.0, 0.0)
        else:
            angle = math.atan2(np.linalg.norm(v), c)
            k = v / np.linalg.norm(v)
            q = (math.cos(angle / 2), *(math.sin(angle / 2) * k))
        cap = hedra.Capsule(radius, half_length)
        d = hedra.distance(box, np.eye(4), cap, pose7(centre, q))
        assert d.status == "ok"
        assert d.distance == pytest.approx(gap, abs=1e-10)
        assert np.allclose(d.normal, [0, 0, 1], atol=1e-6)
        p = hedra.penetration(box, np.eye(4), cap, pose7(centre, q))
        assert p.distance == pytest.approx(gap, abs=1e-10)


def test_pose_forms_agree(rng):
    """A 7-vector and its 4x4 matrix give the same answer (up to the rotation's rounding)."""
    a, b = hedra.Box([0.5, 0.4, 0.3]), hedra.Cylinder(0.3, 0.4)
    for p in random_poses(rng, 50):
        q = random_poses(rng, 1)[0]
        r7 = hedra.penetration(a, p, b, q)
        r4 = hedra.penetration(a, matrix_of(p), b, matrix_of(q))
        assert r7.distance == pytest.approx(r4.distance, abs=1e-9)
    # a quaternion is normalised: scaling it changes nothing
    p = random_poses(rng, 1)[0]
    scaled = p.copy()
    scaled[3:] *= 1e-5
    assert hedra.distance(a, p, b, pose7((0, 0, 2))).distance == pytest.approx(
        hedra.distance(a, scaled, b, pose7((0, 0, 2))).distance, abs=1e-12
    )


def test_scipy_scalar_last_conversion(rng):
    """docs/python.md's conversion from scipy's as_quat() (x, y, z, w) to hedra's (w, x, y, z)."""
    Rotation = pytest.importorskip("scipy.spatial.transform").Rotation
    rot = Rotation.random(20, random_state=3)
    xyzw = rot.as_quat()
    t = rng.uniform(-1, 1, size=(20, 3))
    poses = np.hstack([t, np.roll(xyzw, 1, axis=1)])  # the docs' line
    mats = np.tile(np.eye(4), (20, 1, 1))
    mats[:, :3, :3] = rot.as_matrix()
    mats[:, :3, 3] = t
    box, cone = hedra.Box([0.4, 0.2, 0.1]), hedra.Cone(0.3, 0.4)
    r7 = hedra.penetration_many(box, poses, cone, pose7((0.2, 0.1, 0.3)))
    r4 = hedra.penetration_many(box, mats, cone, pose7((0.2, 0.1, 0.3)))
    assert np.allclose(r7["distance"], r4["distance"], atol=1e-9)


def test_contact_box_on_box():
    a = hedra.Box([1.0, 1.0, 0.5])
    b = hedra.Box([0.5, 0.5, 0.5])
    c = hedra.contact(a, np.eye(4), b, pose7((0, 0, 0.95)))
    assert c.status == "ok" and c.count == 4
    assert c.points.shape == (4, 3) and c.depths.shape == (4,)
    assert np.allclose(c.depths, 0.05, atol=1e-12)
    assert np.allclose(c.normal, [0, 0, 1])
    assert np.allclose(np.sort(np.abs(c.points[:, :2]), axis=0), 0.5)
    assert np.allclose(c.points[:, 2], 0.475)
    # apart by 0.1: nothing within contact_distance 0, four speculative points within 0.2
    far = hedra.contact(a, np.eye(4), b, pose7((0, 0, 1.1)))
    assert far.count == 0 and far.points.shape == (0, 3)
    spec = hedra.contact(a, np.eye(4), b, pose7((0, 0, 1.1)), contact_distance=0.2)
    assert spec.count == 4 and np.allclose(spec.depths, -0.1, atol=1e-12)


def test_contact_error_bound():
    a = hedra.Box([1.0, 1.0, 0.5])
    b = hedra.Box([0.5, 0.5, 0.5])
    # resting 0.05 deep: the exact depth within the certified bound, the bound rounding small
    c = hedra.contact(a, np.eye(4), b, pose7((0.2, 0, 0.95)))
    assert 0.0 <= c.error_bound < 1e-12
    assert abs(c.distance + 0.05) <= c.error_bound
    assert np.allclose(c.point_b - c.point_a, c.distance * c.normal, atol=1e-12)
    # a sphere on the box (penetration()'s point): its own bound
    s = hedra.contact(a, np.eye(4), hedra.Sphere(0.25), pose7((0.1, 0.2, 0.7)))
    assert abs(s.distance + 0.05) <= s.error_bound + 1e-15 and s.error_bound < 1e-9
    # apart beyond the contact distance: SAT's separation, only a lower bound
    far = hedra.contact(a, np.eye(4), b, pose7((0, 0, 1.1)))
    assert far.distance <= 0.1 + 1e-12 and far.error_bound == np.inf
    # the batch carries the same column
    many = hedra.contact_many(a, np.eye(4), b, np.array([pose7((0.2, 0, 0.95)), pose7((0, 0, 1.1))]))
    assert many["error_bound"][0] == c.error_bound and many["error_bound"][1] == np.inf


def test_raycast_closed_form():
    box = hedra.Box([0.5, 0.5, 0.5])
    h = hedra.raycast(box, pose7((1, 0, 0)), [1, 0, 3], [0, 0, -1], max_fraction=10)
    assert h.hit and h.status == "hit"
    assert h.fraction == pytest.approx(2.5, abs=1e-12)
    assert np.allclose(h.point, [1, 0, 0.5]) and np.allclose(h.normal, [0, 0, 1])
    miss = hedra.raycast(box, pose7((1, 0, 0)), [1, 0, 3], [0, 0, -1], max_fraction=2.0)
    assert not miss.hit and miss.status == "separated"
    inside = hedra.raycast(hedra.Sphere(1.0), np.eye(4), [0.2, 0, 0], [1, 0, 0])
    assert inside.hit and inside.started_inside and inside.fraction == 0.0
    s = hedra.raycast(hedra.Sphere(1.0), np.eye(4), [-3, 0, 0], [1, 0, 0], max_fraction=5)
    assert s.fraction == pytest.approx(2.0 / 1.0, abs=1e-12)


def test_shape_cast_and_time_of_impact():
    box, ball = hedra.Box([0.5, 0.5, 0.5]), hedra.Sphere(0.25)
    c = hedra.shape_cast(box, np.eye(4), [0, 0, 0], ball, pose7((0, 0, 3)), [0, 0, -3])
    # the ball's bottom meets the box's top at z = 0.75: t = (3 - 0.75) / 3
    assert c.hit and c.status == "hit"
    assert c.fraction == pytest.approx(0.75, abs=1e-9)
    assert c.fraction <= 0.75 + 1e-12
    t = hedra.shape_cast(box, np.eye(4), [0, 0, 0], ball, pose7((0, 0, 3)), [0, 0, -3], target_distance=0.3)
    assert t.fraction == pytest.approx(0.65, abs=1e-9)
    toi = hedra.time_of_impact(box, np.eye(4), np.eye(4), ball, pose7((0, 0, 3)), pose7((0, 0, -3)))
    assert toi.hit and toi.fraction == pytest.approx(2.25 / 6, abs=1e-9) and toi.fraction <= 2.25 / 6 + 1e-12
    missed = hedra.time_of_impact(box, np.eye(4), np.eye(4), ball, pose7((3, 0, 3)), pose7((3, 0, -3)))
    assert not missed.hit and missed.status == "separated"
    # a spinning bar sweeping through a ball it would tunnel past with its end poses only
    bar = hedra.Box([1.0, 0.05, 0.05])
    end = pose7((0, 0, 0), (math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)))
    spin = hedra.time_of_impact(bar, np.eye(4), end, hedra.Sphere(0.1), pose7((0.6, 0.4, 0)), pose7((0.6, 0.4, 0)))
    assert spin.hit and 0.0 < spin.fraction < 1.0
    assert not hedra.intersect(bar, end, hedra.Sphere(0.1), pose7((0.6, 0.4, 0))).intersecting


def test_results_are_new_arrays():
    box = hedra.Box([0.5, 0.5, 0.5])
    r = hedra.distance(box, np.eye(4), box, pose7((0, 0, 2)))
    n1 = r.normal
    n1[:] = 7.0
    assert np.allclose(r.normal, [0, 0, 1])
    assert r.normal.dtype == np.float64 and r.normal.shape == (3,)
    h = hedra.Box([1.0, 2.0, 3.0])
    e = h.half_extents
    e[0] = 9.0
    assert np.allclose(h.half_extents, [1, 2, 3])


def test_status_names():
    assert hedra.STATUS_NAMES[0] == "ok"
    assert hedra.STATUS_NAMES[:6] == ("ok", "max_iterations", "degenerate", "invalid_input", "polytope_full", "stalled")
    assert len(set(hedra.STATUS_NAMES)) == len(hedra.STATUS_NAMES)
    assert isinstance(hedra.__version__, str) and hedra.__version__.count(".") == 2


def test_settings_are_used_and_checked():
    box, ball = hedra.Box([0.5, 0.5, 0.5]), hedra.Sphere(0.5)
    rng = np.random.default_rng(1)
    a, b = hedra.ConvexHull(rng.normal(size=(40, 3))), hedra.ConvexHull(rng.normal(size=(40, 3)))
    far = [2.5, 1, 0.5, 1, 0.2, 0.3, 0.1]
    capped = hedra.distance(a, np.eye(4), b, far, settings=hedra.GjkSettings(max_iterations=1))
    assert capped.status == "max_iterations" and np.isfinite(capped.distance)
    assert hedra.distance(a, np.eye(4), b, far).status == "ok"
    assert hedra.distance(box, np.eye(4), ball, pose7((0, 0, 2))).status == "ok"
    s = hedra.PenetrationSettings(touching_band=1e-8)
    s.gjk.max_iterations = 64
    assert s.gjk.max_iterations == 64
    with pytest.raises(ValueError, match="max_iterations"):
        hedra.GjkSettings(max_iterations=0)
    with pytest.raises(TypeError, match="no setting named"):
        hedra.GjkSettings(iterations=3)
    with pytest.raises(ValueError, match="relative_tolerance"):
        hedra.GjkSettings().relative_tolerance = float("nan")
    with pytest.raises(TypeError, match="settings"):
        hedra.penetration(box, np.eye(4), ball, np.eye(4), settings=hedra.GjkSettings())
