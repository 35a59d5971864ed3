#!/usr/bin/python3
"""Compares two `resting_contact_benchmark --answers FILE` files (two builds,
same pairs): per family and motion, how many answers differ at all, in their
path or point count, and the largest change of the distance, of a point and
of a depth over the pair's size.

Usage: contact_answers_compare.py OLD NEW
"""
import sys
from collections import defaultdict


def read(path):
    answers = {}
    with open(path) as f:
        for line in f:
            w = line.split()
            key = tuple(w[0:3])
            status, route, count = w[3], w[4], int(w[5])
            size, distance = float(w[6]), float(w[7])
            normal = [float(x) for x in w[8:11]]
            points = [[float(x) for x in w[11 + 4 * k:15 + 4 * k]] for k in range(count)]
            answers[key] = (status, route, count, size, distance, normal, points, line)
    return answers


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    old, new = read(sys.argv[1]), read(sys.argv[2])
    if old.keys() != new.keys():
        sys.exit("the files hold different pairs")
    rows = defaultdict(lambda: [0, 0, 0, 0.0, 0.0, 0.0])
    for key in sorted(old):
        o, n = old[key], new[key]
        row = rows[key[0]]
        row[0] += 1
        if o[7] == n[7]:
            continue
        row[1] += 1
        if o[0] != n[0] or o[1] != n[1] or o[2] != n[2]:
            row[2] += 1
            continue
        size = o[3]
        row[3] = max(row[3], abs(o[4] - n[4]) / size)
        for p, q in zip(o[6], n[6]):
            row[4] = max(row[4], max(abs(a - b) for a, b in zip(p[:3], q[:3])) / size)
            row[5] = max(row[5], abs(p[3] - q[3]) / size)
    print("| family/motion | answers | changed | other path or count | max abs(d distance)/size "
          "| max abs(d point)/size | max abs(d depth)/size |")
    print("|---|---|---|---|---|---|---|")
    for family, (total, changed, other, dd, dp, dz) in rows.items():
        print(f"| {family} | {total} | {changed} | {other} | {dd:.1e} | {dp:.1e} | {dz:.1e} |")


if __name__ == "__main__":
    main()
