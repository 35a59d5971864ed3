#!/usr/bin/env python3
"""What a single query costs from Python beyond the same query in C++ (not a test: a measurement).

Times the queries of overhead.cpp on the same pairs with a timeit loop (poses as float64 numpy
7-vectors, and as 4x4 matrices; the thread's CPU time, as the C++ side, so that a loaded machine's
descheduling stays out), runs the C++ program in the same run, and prints both and their
difference per call (medians of `--repeats` loops each).

    PYTHONPATH=build/python /usr/bin/python3 tools/python/bench/overhead.py build/bin/python_overhead_cpp
"""
import argparse
import math
import statistics
import subprocess
import time
import timeit

import numpy as np

import hedra


def fibonacci_points(n):
    golden = math.pi * (3.0 - math.sqrt(5.0))
    out = []
    for i in range(n):
        z = 1.0 - 2.0 * (i + 0.5) / n
        r, phi = math.sqrt(1.0 - z * z), golden * i
        out.append([0.5 * r * math.cos(phi), 0.5 * r * math.sin(phi), 0.5 * z])
    return np.array(out)


def as_matrix(p):
    w, x, y, z = np.array(p[3:]) / np.linalg.norm(p[3:])
    m = np.eye(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                 [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                 [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = p[:3]
    return m


def median_ns(call, calls, repeats):
    """Median over `repeats` loops of `calls` calls, in the thread's CPU time (as overhead.cpp)."""
    timer = timeit.Timer(call, timer=time.thread_time)
    return statistics.median(t / calls * 1e9 for t in timer.repeat(number=calls, repeat=repeats))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cpp", help="the C++ program (build/bin/python_overhead_cpp)")
    parser.add_argument("--calls", type=int, default=200000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()

    sphere, box = hedra.Sphere(0.5), hedra.Box([0.5, 0.4, 0.3])
    hull = hedra.ConvexHull(fibonacci_points(32))
    identity = np.array([0, 0, 0, 1.0, 0, 0, 0])
    moved = np.array([1.2, 0.3, 0.1, 0.9, 0.1, 0.3, 0.2])
    overlapping = np.array([0.6, 0.2, 0.1, 0.9, 0.1, 0.3, 0.2])
    cases = {
        "sphere_sphere_distance": (hedra.distance, sphere, sphere, moved),
        "box_box_intersect": (hedra.intersect, box, box, moved),
        "box_box_penetration": (hedra.penetration, box, box, overlapping),
        "hull_hull_distance": (hedra.distance, hull, hull, moved),
    }
    cpp = subprocess.run([args.cpp, str(args.calls), str(args.repeats)], check=True, capture_output=True, text=True)
    cpp_ns = {name: float(ns) for name, ns in (line.split() for line in cpp.stdout.splitlines())}
    print(f"{'case':24} {'C++ ns':>8} {'Python ns (7-vector)':>21} {'overhead':>9} "
          f"{'Python ns (4x4)':>16} {'overhead':>9}")
    for name, (query, a, b, pose) in cases.items():
        m_identity, m_pose = as_matrix(identity), as_matrix(pose)
        py7 = median_ns(lambda: query(a, identity, b, pose).status, args.calls, args.repeats)
        py4 = median_ns(lambda: query(a, m_identity, b, m_pose).status, args.calls, args.repeats)
        c = cpp_ns[name]
        print(f"{name:24} {c:8.1f} {py7:21.1f} {py7 - c:9.1f} {py4:16.1f} {py4 - c:9.1f}")
    # the cost of the loop itself (a Python call of a trivial builtin and the attribute read)
    empty = median_ns(lambda: len(cases), args.calls, args.repeats)
    print(f"(the timing loop's own cost, a lambda calling len(): {empty:.1f} ns per call, included above)")


if __name__ == "__main__":
    main()
