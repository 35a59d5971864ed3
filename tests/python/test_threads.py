"""The GIL is released during batches and scene queries; a Scene shared between Python threads stays consistent."""
import threading

import numpy as np

import hedra
from conftest import random_poses, shape_zoo


def python_progress_during(call):
    """How many iterations a Python loop in this thread makes while `call` runs in another thread."""
    started, done = threading.Event(), threading.Event()
    out = {}

    def worker():
        started.set()
        out["result"] = call()
        done.set()

    thread = threading.Thread(target=worker)
    thread.start()
    started.wait()
    count = 0
    while not done.is_set():
        count += 1
    thread.join()
    return count, out["result"]


def test_batches_release_the_gil():
    rng = np.random.default_rng(11)
    hull = hedra.ConvexHull(rng.normal(size=(200, 3)))
    poses = random_poses(rng, 50000, 1.5)
    # the batch takes tenths of a second; with the GIL held this thread could not count meanwhile
    count, result = python_progress_during(lambda: hedra.penetration_many(hull, poses, hull, np.eye(4), threads=1))
    assert len(result["distance"]) == 50000
    assert count > 10000, count


def test_scene_pairs_release_the_gil():
    rng = np.random.default_rng(12)
    zoo = shape_zoo(rng)
    scene = hedra.Scene()
    for k, p in enumerate(random_poses(rng, 4000, 6.0)):
        scene.add(zoo[k % len(zoo)], p)
    count, result = python_progress_during(lambda: scene.pairs(query="contact", max_distance=0.05, threads=1))
    assert len(result["a"]) > 100
    assert count > 1000, count


def test_scene_shared_between_threads():
    rng = np.random.default_rng(13)
    zoo = shape_zoo(rng)
    poses = random_poses(rng, 300, 3.0)
    scene = hedra.Scene()
    for k, p in enumerate(poses):
        scene.add(zoo[k % len(zoo)], p)
    expected = scene.pairs(query="penetration")
    errors = []

    def query():
        for _ in range(5):
            got = scene.pairs(query="penetration")
            if got["a"].tobytes() != expected["a"].tobytes() or got["distance"].tobytes() != expected[
                    "distance"].tobytes():
                errors.append("pairs changed while only equal poses were set")

    def move():
        for _ in range(20):
            for i in range(0, 300, 7):
                scene.set_pose(i, poses[i])  # the same pose: the answer must not change
            scene.set_poses(poses)

    threads = [threading.Thread(target=query) for _ in range(2)] + [threading.Thread(target=move)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
