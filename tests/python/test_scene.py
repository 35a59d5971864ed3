"""Scenes: pairs() against brute force on random scenes, filters, ignored pairs, moving bodies, threads."""
import itertools

import numpy as np
import pytest

import hedra
from conftest import random_poses, shape_zoo


def random_scene(rng, n, extent):
    zoo = shape_zoo(rng) + [hedra.Box([0.9, 0.05, 0.05]), hedra.Sphere(0.05)]
    shapes = [zoo[i] for i in rng.integers(0, len(zoo), size=n)]
    poses = random_poses(rng, n, extent)
    return shapes, poses


def brute_force(shapes, poses, max_distance, skip=lambda i, j: False):
    pairs = []
    for i, j in itertools.combinations(range(len(shapes)), 2):
        if skip(i, j):
            continue
        d = hedra.distance(shapes[i], poses[i], shapes[j], poses[j])
        if d.distance <= max_distance:
            pairs.append((i, j))
    return pairs


@pytest.mark.parametrize("seed,n,extent,max_distance", [(1, 60, 2.0, 0.0), (2, 80, 3.0, 0.1), (3, 40, 1.0, 0.0)])
def test_pairs_equal_brute_force(seed, n, extent, max_distance):
    rng = np.random.default_rng(seed)
    shapes, poses = random_scene(rng, n, extent)
    scene = hedra.Scene()
    for k, (s, p) in enumerate(zip(shapes, poses)):
        assert scene.add(s, p) == k
    assert len(scene) == n
    expected = brute_force(shapes, poses, max_distance)
    assert len(expected) > 5
    for query in ("intersect", "distance", "penetration", "contact"):
        got = scene.pairs(max_distance=max_distance, query=query)
        found = list(zip(got["a"].tolist(), got["b"].tolist()))
        if query == "intersect":
            # intersect answers overlap only: with max_distance 0 the same pairs
            if max_distance == 0.0:
                assert found == expected
            continue
        assert found == expected, query
        assert got["a"].dtype == np.int64 and np.all(got["a"] < got["b"])
        for k, (i, j) in enumerate(found):
            single = {
                "distance": hedra.distance,
                "penetration": hedra.penetration,
                "contact": lambda *a: hedra.contact(*a, contact_distance=max_distance),
            }[query](shapes[i], poses[i], shapes[j], poses[j])
            assert got["distance"][k] == pytest.approx(single.distance, abs=1e-9)
            assert got["error_bound"][k] == pytest.approx(single.error_bound, rel=1e-6, abs=1e-9), query


def test_same_bits_for_any_thread_count():
    rng = np.random.default_rng(4)
    shapes, poses = random_scene(rng, 150, 3.0)
    scene = hedra.Scene()
    for s, p in zip(shapes, poses):
        scene.add(s, p)
    for query in ("penetration", "contact"):
        runs = [scene.pairs(max_distance=0.05, query=query, threads=t) for t in (1, 2, 0)]
        for run in runs[1:]:
            assert sorted(run) == sorted(runs[0])
            for k in run:
                assert run[k].tobytes() == runs[0][k].tobytes(), (query, k)


def test_filters_and_ignored_pairs():
    rng = np.random.default_rng(5)
    shapes, poses = random_scene(rng, 50, 1.2)
    groups = rng.integers(1, 4, size=50)
    masks = np.where(rng.random(50) < 0.3, 0b01, 0xFFFFFFFF)
    scene = hedra.Scene()
    for s, p, g, m in zip(shapes, poses, groups, masks):
        scene.add(s, p, group=int(g), mask=int(m))
    all_pairs = brute_force(shapes, poses, 0.0)
    ignored = set(all_pairs[::4])
    for i, j in ignored:
        scene.ignore_pair(j, i)  # either order
    passes = lambda i, j: (groups[i] & masks[j]) and (groups[j] & masks[i]) and (i, j) not in ignored
    expected = [p for p in all_pairs if passes(*p)]
    got = scene.pairs()
    assert list(zip(got["a"].tolist(), got["b"].tolist())) == expected
    assert len(expected) < len(all_pairs)


def test_moving_bodies():
    rng = np.random.default_rng(6)
    shapes, poses = random_scene(rng, 70, 2.5)
    scene = hedra.Scene()
    for s, p in zip(shapes, poses):
        scene.add(s, p)
    for frame in range(4):
        poses = poses + np.hstack([rng.normal(scale=0.2, size=(70, 3)), np.zeros((70, 4))])
        if frame % 2:
            scene.set_poses(poses)
        else:
            for i, p in enumerate(poses):
                scene.set_pose(i, p)
        got = scene.pairs(query="penetration")
        assert list(zip(got["a"].tolist(), got["b"].tolist())) == brute_force(shapes, poses, 0.0)
        assert np.all(got["distance"] <= 1e-12)


def test_scene_errors():
    scene = hedra.Scene()
    with pytest.raises(ValueError, match="no bodies"):
        scene.set_pose(0, np.eye(4))
    scene.add(hedra.Sphere(1), np.eye(4))
    scene.add(hedra.Sphere(1), np.eye(4))
    with pytest.raises(ValueError, match="i: must be an integer in"):
        scene.set_pose(2, np.eye(4))
    with pytest.raises(ValueError, match="same body"):
        scene.ignore_pair(1, 1)
    with pytest.raises(ValueError, match="expected 2 poses"):
        scene.set_poses(np.zeros((3, 7)) + [0, 0, 0, 1, 0, 0, 0])
    with pytest.raises(ValueError, match="query"):
        scene.pairs(query="overlap")
    with pytest.raises(TypeError, match="query"):
        scene.pairs(query=3)
    with pytest.raises(ValueError, match="max_distance"):
        scene.pairs(max_distance=-1.0)
    with pytest.raises(TypeError, match="shape"):
        scene.add("sphere", np.eye(4))
    with pytest.raises(ValueError, match="mask"):
        scene.add(hedra.Sphere(1), np.eye(4), mask=-1)
    assert len(scene) == 2
    assert scene.pairs()["a"].tolist() == [0]
