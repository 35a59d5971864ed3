#!/usr/bin/env python3
"""Markdown table from hull_benchmark's JSON output (standard library only).

    build/bin/hull_benchmark --benchmark_format=json > hull.json
    python3 tools/microbench/hull_table.py hull.json   # or: ... | python3 tools/microbench/hull_table.py

One row per point set: points, hedra ms, qhull ms (default options: merged
facets, comparable to hedra's faces), hedra/qhull ratio, qhull "Qt" ms, and
whether hedra's vertex set equals qhull's, and hedra's peak heap bytes per
input point in one build (counters the benchmark computes once per set,
outside timing). Times are medians over repetitions (the
benchmark's "median" aggregates; without them, the median of the individual
runs). CPU time by default, which a machine shared with other jobs disturbs
less than wall time; --real for wall time.
"""
import argparse
import json
import statistics
import sys


def parse_run_name(run_name):
    """'ball/1000/hedra/repeats:5/real_time' -> ('ball/1000', 'hedra')."""
    parts = [p for p in run_name.split("/") if ":" not in p and p not in ("real_time", "process_time")]
    return "/".join(parts[:-1]), parts[-1]


def to_ms(value, unit):
    return value * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[unit]


def collect(benchmarks, time_key):
    """{(set, implementation): {'ms': median, 'points': n, 'equal': 0/1, 'bytes': per point}}"""
    medians = {}
    runs = {}
    for b in benchmarks:
        if b.get("error_occurred"):
            key = parse_run_name(b.get("run_name", b["name"]))
            medians[key] = {"ms": None, "points": b.get("points"), "equal": b.get("vertex_sets_equal"), "bytes": b.get("bytes_per_point"), "error": b.get("error_message", "error")}
            continue
        key = parse_run_name(b.get("run_name", b["name"]))
        entry = {"ms": to_ms(b[time_key], b.get("time_unit", "ns")), "points": b.get("points"), "equal": b.get("vertex_sets_equal"), "bytes": b.get("bytes_per_point")}
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                medians[key] = entry
        else:
            runs.setdefault(key, []).append(entry)
    for key, entries in runs.items():
        if key not in medians:
            medians[key] = dict(entries[0], ms=statistics.median(e["ms"] for e in entries))
    return medians


def fmt_ms(ms):
    if ms is None:
        return "failed"
    return f"{ms:.3f}" if ms < 10 else f"{ms:.1f}"


def table(medians):
    sets = []
    for set_name, _ in medians:
        if set_name not in sets:
            sets.append(set_name)
    lines = [
        "| set | points | hedra ms | qhull ms | hedra/qhull | qhull Qt ms | vertex sets equal | hedra bytes/point |",
        "|---|---:|---:|---:|---:|---:|:---:|---:|",
    ]
    for s in sets:
        hedra = medians.get((s, "hedra"), {})
        qhull = medians.get((s, "qhull"), {})
        qhull_qt = medians.get((s, "qhull_Qt"), {})
        points = next((e["points"] for e in (hedra, qhull, qhull_qt) if e.get("points") is not None), None)
        equal = next((e["equal"] for e in (hedra, qhull, qhull_qt) if e.get("equal") is not None), None)
        per_point = next((e["bytes"] for e in (hedra, qhull, qhull_qt) if e.get("bytes") is not None), None)
        h, q = hedra.get("ms"), qhull.get("ms")
        ratio = f"{h / q:.2f}" if h is not None and q else "-"
        lines.append(
            "| {} | {} | {} | {} | {} | {} | {} | {} |".format(
                s,
                f"{int(points):,}" if points is not None else "-",
                fmt_ms(h) if hedra else "-",
                fmt_ms(q) if qhull else "-",
                ratio,
                fmt_ms(qhull_qt.get("ms")) if qhull_qt else "-",
                "-" if equal is None else ("yes" if equal >= 0.5 else "**no**"),
                "-" if per_point is None else f"{per_point:,.0f}",
            )
        )
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("json", nargs="?", help="hull_benchmark --benchmark_format=json output (default: stdin)")
    parser.add_argument("--real", action="store_true", help="wall time instead of CPU time")
    args = parser.parse_args()
    data = json.load(open(args.json) if args.json else sys.stdin)
    print(table(collect(data["benchmarks"], "real_time" if args.real else "cpu_time")))


if __name__ == "__main__":
    main()
