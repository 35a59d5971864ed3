"""Bad input: a ValueError or TypeError naming the argument, never a crash or a NaN; a seeded fuzz of the checks."""
import math

import numpy as np
import pytest

import hedra
from conftest import pose7

BOX, BALL = hedra.Box([0.5, 0.5, 0.5]), hedra.Sphere(0.25)
GOOD = pose7((0, 0, 2))


@pytest.mark.parametrize(
    "make,error,words",
    [
        (lambda: hedra.Sphere(-1.0), ValueError, "radius: must be >= 0"),
        (lambda: hedra.Sphere(float("nan")), ValueError, "radius: NaN"),
        (lambda: hedra.Sphere(math.inf), ValueError, "radius: infinity"),
        (lambda: hedra.Sphere(None), TypeError, "radius"),
        (lambda: hedra.Sphere("1"), TypeError, "radius"),
        (lambda: hedra.Sphere(1j), TypeError, "radius"),
        (lambda: hedra.Sphere(True), TypeError, "radius: expected a real number, got a bool"),
        (lambda: hedra.Sphere([1.0]), TypeError, "radius"),
        (lambda: hedra.Sphere(1.0, margin=-0.1), ValueError, "margin: must be >= 0"),
        (lambda: hedra.Sphere(1e300), ValueError, "1e+60"),
        (lambda: hedra.Box([1, 2]), ValueError, r"half_extents: expected shape \(3,\), got \(2,\)"),
        (lambda: hedra.Box([1, -2, 3]), ValueError, "half_extents: must be >= 0"),
        (lambda: hedra.Box([1, np.nan, 3]), ValueError, r"half_extents: NaN at \[1\]"),
        (lambda: hedra.Box("abc"), TypeError, "half_extents"),
        (lambda: hedra.Box([1, "a", 3]), TypeError, "half_extents: expected an array of real numbers, got strings"),
        (lambda: hedra.Box([1, None, 3]), TypeError, "half_extents"),
        (lambda: hedra.Box([1, 2j, 3]), TypeError, "complex"),
        (lambda: hedra.Box([[1, 2], [3]]), ValueError, "half_extents: cannot be read"),
        (lambda: hedra.Capsule(0.1, -1), ValueError, "half_length: must be >= 0"),
        (lambda: hedra.Cone(np.float32("nan"), 1), ValueError, "radius: NaN"),
        (lambda: hedra.ConvexHull(np.zeros((0, 3))), ValueError, "points: no points"),
        (lambda: hedra.ConvexHull(np.zeros((5, 2))), ValueError, r"points: expected shape \(N, 3\)"),
        (lambda: hedra.ConvexHull([[0, 0, np.inf]]), ValueError, r"points: infinity at \[0, 2\]"),
        (lambda: hedra.ConvexHull(None), TypeError, "points"),
        (lambda: hedra.ConvexHull([[1, 2, 3]], margin=np.nan), ValueError, "margin: NaN"),
        (lambda: hedra.distance("box", np.eye(4), BALL, GOOD), TypeError, "a: expected a hedra shape"),
        (lambda: hedra.distance(BOX, np.eye(4), None, GOOD), TypeError, "b: expected a hedra shape"),
        (lambda: hedra.distance(BOX, None, BALL, GOOD), TypeError, "pose_a"),
        (lambda: hedra.distance(BOX, "eye", BALL, GOOD), TypeError, "pose_a"),
        (lambda: hedra.distance(BOX, np.eye(3), BALL, GOOD), ValueError, r"pose_a: expected a pose.*\(3, 3\)"),
        (lambda: hedra.distance(BOX, np.eye(4), BALL, [0, 0, 0, 0, 0, 0, 0]), ValueError, "pose_b: zero quaternion"),
        (lambda: hedra.distance(BOX, np.eye(4), BALL, [0, 0, 0, 1e-13, 0, 0, 0]), ValueError, "pose_b: zero quat"),
        (lambda: hedra.distance(BOX, np.eye(4), BALL, [0, 0, np.nan, 1, 0, 0, 0]), ValueError, r"pose_b: NaN at \[2\]"),
        (lambda: hedra.distance(BOX, np.diag([1, 1, 2, 1.0]), BALL, GOOD), ValueError, "pose_a: .*not orthonormal"),
        (lambda: hedra.distance(BOX, np.diag([1, 1, -1, 1.0]), BALL, GOOD), ValueError, "pose_a: .*reflection"),
        (lambda: hedra.distance(BOX, np.vstack([np.eye(4)[:3], [0, 0, 1, 1]]), BALL, GOOD), ValueError, "last row"),
        (lambda: hedra.distance(BOX, np.eye(4), BALL, [1e61, 0, 0, 1, 0, 0, 0]), ValueError, "pose_b: translation"),
        (lambda: hedra.distance(BOX, np.eye(4) + 0j, BALL, GOOD), TypeError, "pose_a: .*complex"),
        (lambda: hedra.distance(BOX, np.eye(4).astype(bool), BALL, GOOD), TypeError, "pose_a: .*booleans"),
        (lambda: hedra.distance(BOX, np.array([object()] * 7), BALL, GOOD), TypeError, "pose_a"),
        (lambda: hedra.contact(BOX, np.eye(4), BALL, GOOD, contact_distance=-1), ValueError, "contact_distance"),
        (lambda: hedra.contact(BOX, np.eye(4), BALL, GOOD, 0.1), TypeError, ""),  # keyword-only
        (lambda: hedra.raycast(BOX, np.eye(4), [0, 0], [1, 0, 0]), ValueError, "origin"),
        (lambda: hedra.raycast(BOX, np.eye(4), [0, 0, 0], [1, 0, np.inf]), ValueError, "direction: infinity"),
        (lambda: hedra.raycast(BOX, np.eye(4), [0, 0, 0], [1, 0, 0], max_fraction=-1), ValueError, "max_fraction"),
        (lambda: hedra.shape_cast(BOX, np.eye(4), [0, 0], BALL, GOOD, [0, 0, 1]), ValueError, "translation_a"),
        (lambda: hedra.time_of_impact(BOX, np.eye(4), None, BALL, GOOD, GOOD), TypeError, "end_a"),
        (lambda: hedra.penetration_many(BOX, np.zeros((3, 6)), BALL, GOOD), ValueError, "poses_a: expected a batch"),
        (lambda: hedra.penetration_many(BOX, np.eye(4), BALL, GOOD, threads=-1), ValueError, "threads"),
        (lambda: hedra.penetration_many(BOX, np.eye(4), BALL, GOOD, threads=1.5), TypeError, "threads"),
        (lambda: hedra.penetration_many(BOX, np.eye(4), BALL, GOOD, threads=None), TypeError, "threads"),
        (lambda: hedra.raycast_many(BOX, np.eye(4), np.zeros((2, 2)), [1, 0, 0]), ValueError, "origins"),
        (lambda: hedra.raycast(BOX, np.eye(4), [0, 0, 3], [0, 0, 0]), ValueError, "direction: a zero vector"),
        (lambda: hedra.raycast_many(BOX, np.eye(4), np.ones((3, 3)), np.eye(3) * [1, 0, 1]), ValueError,
         r"directions\[1\]: a zero vector"),
    ],
)
def test_bad_input_raises_with_a_message(make, error, words):
    with pytest.raises(error, match=words) as info:
        make()
    assert str(info.value)


# Values a fuzzed argument may take: right and wrong types, shapes and numbers.
def candidate_values(rng):
    q = rng.normal(size=4)
    return [
        None, "x", b"x", 1j, True, object(), {}, [], (), 0, -1, 1.5, -0.5, math.nan, math.inf, 2**80,
        np.float32(0.3), np.int64(2), np.nan * np.ones(7), np.eye(4), np.eye(4)[:3], np.zeros(7),
        np.array([0, 0, 1, *q]), np.array([0, 0, 1, *q]).astype(np.float32), np.eye(4) * 2,
        rng.normal(size=(5, 7)), rng.normal(size=(5, 4, 4)), np.zeros((0, 7)), np.zeros((5, 3)), np.ones(3),
        [1, 2, 3], [[1, 2, 3]], [[1, 2], [3]], np.array(["a"] * 7), np.ones(7, dtype=complex),
        np.ones((2, 7)) * [0, 0, 0, 1, 0, 0, 0], np.full(3, np.inf), rng.normal(size=(20, 3)),
        hedra.Sphere(0.5), hedra.Box([0.2, 0.3, 0.4]), hedra.GjkSettings(),
    ]


CALLS = [
    (hedra.Sphere, 1), (hedra.Box, 1), (hedra.Capsule, 2), (hedra.Cylinder, 2), (hedra.Cone, 2),
    (hedra.ConvexHull, 1), (hedra.intersect, 4), (hedra.distance, 4), (hedra.penetration, 4), (hedra.contact, 4),
    (hedra.raycast, 4), (hedra.shape_cast, 6), (hedra.time_of_impact, 6), (hedra.intersect_many, 4),
    (hedra.distance_many, 4), (hedra.penetration_many, 4), (hedra.contact_many, 4), (hedra.raycast_many, 4),
]
KEYWORDS = ["margin", "threads", "contact_distance", "max_fraction", "settings", "target_distance"]


def no_nan(result):
    if isinstance(result, dict):
        return all(not np.issubdtype(v.dtype, np.floating) or np.all(np.isfinite(v)) for v in result.values())
    for name in ("distance", "normal", "point_a", "point_b", "fraction", "point", "points", "depths"):
        if hasattr(result, name) and not np.all(np.isfinite(getattr(result, name))):
            return False
    return True


def test_fuzz_argument_checking():
    rng = np.random.default_rng(20261128)
    values = candidate_values(rng)
    good = {
        hedra.Sphere: [0.5], hedra.Box: [[0.3, 0.2, 0.1]], hedra.Capsule: [0.2, 0.3], hedra.Cylinder: [0.2, 0.3],
        hedra.Cone: [0.2, 0.3], hedra.ConvexHull: [rng.normal(size=(10, 3))],
        hedra.raycast: [BOX, np.eye(4), [0, 0, 3], [0, 0, -1]],
        hedra.raycast_many: [BOX, np.eye(4), np.zeros((4, 3)) + [0, 0, 3], [0, 0, -1]],
        hedra.shape_cast: [BOX, np.eye(4), [0, 0, 0], BALL, GOOD, [0, 0, -2]],
        hedra.time_of_impact: [BOX, np.eye(4), np.eye(4), BALL, GOOD, pose7()],
    }
    outcomes = {"ok": 0, "TypeError": 0, "ValueError": 0}
    for trial in range(3000):
        function, arity = CALLS[rng.integers(len(CALLS))]
        args = list(good.get(function, [BOX, np.eye(4), BALL, GOOD]))
        mutated = 1 if rng.random() < 0.8 else rng.integers(1, arity + 1)
        for k in rng.choice(arity, size=mutated, replace=False):
            args[k] = values[rng.integers(len(values))]
        kwargs = {}
        if rng.random() < 0.3:
            kwargs[KEYWORDS[rng.integers(len(KEYWORDS))]] = values[rng.integers(len(values))]
        try:
            result = function(*args, **kwargs)
        except (TypeError, ValueError) as e:
            assert str(e), (function, args, kwargs)
            outcomes[type(e).__name__] += 1
            continue
        outcomes["ok"] += 1
        assert no_nan(result), (function, args, kwargs, result)
    # the fuzz reaches every outcome
    assert min(outcomes.values()) > 100, outcomes
