"""Batches: row i equals the single query on row i bit for bit, for 1, 2 and all threads; broadcasting; N = 0."""
import numpy as np
import pytest

import hedra
from conftest import matrix_of, pose7, random_poses, shape_zoo

SINGLE = {
    "intersect": hedra.intersect,
    "distance": hedra.distance,
    "penetration": hedra.penetration,
    "contact": hedra.contact,
}
MANY = {
    "intersect": hedra.intersect_many,
    "distance": hedra.distance_many,
    "penetration": hedra.penetration_many,
    "contact": hedra.contact_many,
}
COLUMNS = {
    "intersect": ["intersecting", "status"],
    "distance": ["distance", "normal", "point_a", "point_b", "intersecting", "error_bound", "status"],
    "penetration": ["distance", "normal", "point_a", "point_b", "intersecting", "error_bound", "status"],
    "contact": ["distance", "normal", "point_a", "point_b", "intersecting", "error_bound", "status", "count", "points",
                "depths"],
}


def same_bits(x, y):
    x, y = np.asarray(x), np.asarray(y)
    return x.shape == y.shape and x.dtype == y.dtype and x.tobytes() == y.tobytes()


def single_row(query, result, name):
    """The single query's result as the batch's column entry."""
    if name == "status":
        return np.int8(hedra.STATUS_NAMES.index(result.status))
    if query == "contact" and name == "points":
        out = np.zeros((4, 3))
        out[: result.count] = result.points
        return out
    if query == "contact" and name == "depths":
        out = np.zeros(4)
        out[: result.count] = result.depths
        return out
    value = getattr(result, name)
    return np.asarray(value, dtype={"intersecting": bool, "count": np.int64}.get(name, np.float64))


@pytest.mark.parametrize("query", list(MANY))
def test_rows_equal_single_queries(query, rng):
    zoo = shape_zoo(rng)
    kwargs = {"contact_distance": 0.05} if query == "contact" else {}
    for a in zoo[::2]:
        for b in zoo[1::2]:
            n = 97  # more than one chunk on some runners, not a multiple of any
            pa, pb = random_poses(rng, n, 0.6), random_poses(rng, n, 0.6)
            pb_mats = np.array([matrix_of(p) for p in pb])  # the two pose forms mixed
            runs = [MANY[query](a, pa, b, pb_mats, threads=t, **kwargs) for t in (1, 2, 0)]
            assert sorted(runs[0]) == sorted(COLUMNS[query])
            for run in runs[1:]:
                for k in runs[0]:
                    assert same_bits(runs[0][k], run[k]), (query, k)
            for i in range(n):
                single = SINGLE[query](a, pa[i], b, pb_mats[i], **kwargs)
                for k in COLUMNS[query]:
                    assert same_bits(runs[0][k][i], single_row(query, single, k)), (query, k, i)


def test_raycast_many_equals_raycast(rng):
    hull = shape_zoo(rng)[-1]
    pose = random_poses(rng, 1)[0]
    origins = rng.uniform(-2, 2, size=(300, 3))
    directions = pose[:3] - origins + rng.normal(scale=0.3, size=(300, 3))
    runs = [hedra.raycast_many(hull, pose, origins, directions, max_fraction=1.5, threads=t) for t in (1, 2, 0)]
    for run in runs[1:]:
        for k in runs[0]:
            assert same_bits(runs[0][k], run[k])
    hits = runs[0]["hit"]
    assert 50 < hits.sum() < 300
    for i in range(300):
        h = hedra.raycast(hull, pose, origins[i], directions[i], max_fraction=1.5)
        assert runs[0]["hit"][i] == h.hit
        assert same_bits(runs[0]["fraction"][i], np.float64(h.fraction))
        assert same_bits(runs[0]["point"][i], h.point) and same_bits(runs[0]["normal"][i], h.normal)
        assert hedra.STATUS_NAMES[runs[0]["status"][i]] == h.status
    # one direction broadcast to every origin
    down = hedra.raycast_many(hedra.Box([1, 1, 1]), np.eye(4), origins * [1, 1, 0] + [0, 0, 5], [0, 0, -10])
    inside = np.all(np.abs(origins[:, :2]) <= 1, axis=1)
    assert np.array_equal(down["hit"], inside)
    assert np.allclose(down["fraction"][inside], 0.4)


def test_broadcast_and_empty(rng):
    box, ball = hedra.Box([0.5, 0.5, 0.5]), hedra.Sphere(0.25)
    zs = np.linspace(0.0, 2.0, 11)
    poses = np.array([pose7((0, 0, z)) for z in zs])
    r = hedra.penetration_many(box, np.eye(4), ball, poses)
    assert r["distance"].shape == (11,) and r["normal"].shape == (11, 3)
    assert np.allclose(r["distance"][zs >= 0.5], zs[zs >= 0.5] - 0.75, atol=1e-12)
    # either side may broadcast, as a single pose or a batch of one
    r2 = hedra.penetration_many(ball, poses, box, np.eye(4)[None])
    assert np.array_equal(r["distance"], r2["distance"])
    empty = hedra.distance_many(box, np.zeros((0, 7)), ball, np.eye(4))
    assert all(len(v) == 0 for v in empty.values())
    assert empty["normal"].shape == (0, 3)
    e2 = hedra.contact_many(box, np.zeros((0, 4, 4)), ball, np.zeros((0, 7)))
    assert e2["points"].shape == (0, 4, 3)
    one = hedra.intersect_many(box, np.eye(4), ball, pose7((0, 0, 0.7)))
    assert one["intersecting"].tolist() == [True] and one["status"].dtype == np.int8


def test_mismatched_lengths_name_both(rng):
    with pytest.raises(ValueError, match="poses_a has 3 poses and poses_b has 5"):
        hedra.distance_many(hedra.Sphere(1), random_poses(rng, 3), hedra.Sphere(1), random_poses(rng, 5))
    with pytest.raises(ValueError, match=r"poses_b\[2\]: zero quaternion"):
        p = random_poses(rng, 4)
        p[2, 3:] = 0
        hedra.penetration_many(hedra.Sphere(1), np.eye(4), hedra.Sphere(1), p)
    with pytest.raises(ValueError, match="origins has 4 rows and directions has 2"):
        hedra.raycast_many(hedra.Sphere(1), np.eye(4), np.zeros((4, 3)), np.ones((2, 3)))


def test_batch_inputs_are_not_modified_and_outputs_are_new(rng):
    poses = random_poses(rng, 20)
    before = poses.copy()
    r = hedra.distance_many(hedra.Box([0.5, 0.5, 0.5]), poses, hedra.Sphere(0.2), pose7((0, 0, 3)))
    assert np.array_equal(poses, before)
    assert all(v.flags.owndata and v.flags.c_contiguous for v in r.values())
    # non-contiguous and integer input is converted
    ints = np.zeros((5, 7), dtype=np.int32)
    ints[:, 3] = 1
    ints[:, 2] = np.arange(5) * 3
    s = hedra.distance_many(hedra.Sphere(1.0), ints, hedra.Sphere(1.0), poses[0])
    strided = np.asfortranarray(np.tile(poses[0], (5, 1)))
    t = hedra.distance_many(hedra.Sphere(1.0), ints, hedra.Sphere(1.0), strided)
    assert np.array_equal(s["distance"], t["distance"])


def test_rows_across_blocks(rng):
    """Batches run in blocks of rows: rows on both sides of every block boundary equal the single query."""
    a, b = hedra.Box([0.4, 0.3, 0.2]), hedra.Capsule(0.2, 0.3)
    n = 3 * 4096 + 17
    pa, pb = random_poses(rng, n, 0.8), random_poses(rng, n, 0.8)
    runs = [hedra.penetration_many(a, pa, b, pb, threads=t) for t in (1, 2, 0)]
    for run in runs[1:]:
        assert all(same_bits(runs[0][k], run[k]) for k in run)
    for i in [0, 4095, 4096, 4097, 8191, 8192, 12287, 12288, n - 1]:
        single = hedra.penetration(a, pa[i], b, pb[i])
        assert same_bits(runs[0]["distance"][i], np.float64(single.distance))
        assert same_bits(runs[0]["normal"][i], single.normal)
    broadcast = hedra.penetration_many(a, pa[5], b, pb)
    assert same_bits(broadcast["distance"][9000], np.float64(hedra.penetration(a, pa[5], b, pb[9000]).distance))
    pb[9000, 3:] = 0.0  # a bad pose in the third block
    with pytest.raises(ValueError, match=r"poses_b\[9000\]: zero quaternion"):
        hedra.penetration_many(a, pa, b, pb)
