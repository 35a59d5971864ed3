#!/usr/bin/env python3
"""Markdown tables from collision_benchmark's JSON output.

Usage:
  collision_benchmark --benchmark_repetitions=3 --benchmark_format=json \
      --benchmark_out=collision.json --benchmark_out_format=json
  python3 tools/microbench/collision_table.py collision.json

Collision table: family, method, median ns/query over the repetitions,
ratio to hedra's median on the same family, median and max error against
the exact reference (counters error_median / error_max), pairs answered with
a distance and failures. Support table: median ns per call of the scan and
the climb, cold and warm, and the crossover (the smallest vertex count from
which the climb is faster in both modes).
"""
import json
import statistics
import sys
from collections import defaultdict


def load(path):
    with open(path) as f:
        data = json.load(f)
    times = defaultdict(list)
    counters = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        name = b.get("run_name", b["name"])
        scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b.get("time_unit", "ns")]
        times[name].append(b["real_time"] * scale)
        counters[name] = b
    return {name: statistics.median(v) for name, v in times.items()}, counters, {n: len(v) for n, v in times.items()}


def fmt_err(x):
    return "—" if x is None else f"{x:.1e}"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    medians, counters, reps = load(sys.argv[1])
    families = defaultdict(list)
    support = defaultdict(dict)
    for name in medians:
        parts = name.split("/")
        if parts[0] == "collision":
            families[parts[1]].append(parts[2])
        elif parts[0] == "support":
            support[int(parts[3])][(parts[1], parts[2])] = medians[name]
    print(f"repetitions per case: {min(reps.values()) if reps else 0} (median shown)\n")
    print("| family | method | median ns/query | × hedra | median error | max error | answered | failures |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for family, methods in families.items():
        base = medians.get(f"collision/{family}/hedra")
        methods = sorted(methods, key=lambda m: (m != "hedra", medians[f"collision/{family}/{m}"]))
        for m in methods:
            name = f"collision/{family}/{m}"
            c = counters[name]
            ratio = f"{medians[name] / base:.2f}" if base else "—"
            print(f"| {family} | {m} | {medians[name]:.0f} | {ratio} | {fmt_err(c.get('error_median'))} | "
                  f"{fmt_err(c.get('error_max'))} | {c.get('answered', 0):.0f}/{c.get('pairs', 0):.0f} | "
                  f"{c.get('failures', 0):.0f} |")
    if support:
        print("\n| vertices | scan cold | climb cold | scan warm | climb warm | scan/climb cold | scan/climb warm |")
        print("|---:|---:|---:|---:|---:|---:|---:|")
        crossover = None
        for n in sorted(support):
            s = support[n]
            sc, cc, sw, cw = (s.get(k) for k in [("cold", "scan"), ("cold", "climb"), ("warm", "scan"), ("warm", "climb")])
            print(f"| {n} | {sc:.1f} | {cc:.1f} | {sw:.1f} | {cw:.1f} | {sc / cc:.1f} | {sw / cw:.1f} |")
            if crossover is None and cc < sc and cw < sw:
                crossover = n
            elif not (cc < sc and cw < sw):
                crossover = None
        print(f"\ncrossover (climb faster cold and warm from here on): {crossover} vertices")


if __name__ == "__main__":
    main()
