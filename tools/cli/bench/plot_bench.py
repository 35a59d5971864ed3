#!/usr/bin/env python3
"""Figures of a `hedra bench` run: python3 plot_bench.py OUT_DIR

Reads OUT_DIR/summary.csv and OUT_DIR/stability.csv (written by `hedra
bench`, which also writes this script beside them) and writes, each as PNG
and SVG:
  error_vs_time   one panel per family: max relative error (y, log) against
                  the median time per query (x, log), one marker per method,
                  a bar down to the median error, hedra's tolerance sweep as
                  a line; a method's failures are written beside its marker
  stability       one panel per extreme family: each method's max relative
                  error (y, log) against the family's swept parameter (x, log)
Errors below 1e-17 (exact answers) are drawn at 1e-17. Each figure is saved
to a temporary file and renamed, so a figure is whole or absent.
Needs matplotlib (Debian: python3-matplotlib).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-17


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) else None


def save(fig, out_dir, stem):
    for ext in ("png", "svg"):
        target = os.path.join(out_dir, stem + "." + ext)
        temporary = os.path.join(out_dir, "." + stem + ".tmp." + ext)
        fig.savefig(temporary, dpi=110, bbox_inches="tight")
        os.replace(temporary, target)
    plt.close(fig)


def colours(methods):
    peers = [m for m in methods if not m.startswith("hedra")]
    cmap = plt.get_cmap("tab10")
    table = {m: cmap(i % 10) for i, m in enumerate(peers)}
    for m in methods:
        if m.startswith("hedra"):
            table[m] = "black"
    return table


def markers(methods):
    shapes = "os^vD<>ph*"
    peers = [m for m in methods if not m.startswith("hedra")]
    table = {m: shapes[i % len(shapes)] for i, m in enumerate(peers)}
    for m in methods:
        if m.startswith("hedra"):
            table[m] = "*" if m == "hedra" else "."
    return table


def grid(n):
    cols = min(4, max(1, n))
    rows = (n + cols - 1) // cols
    return rows, cols


def sweep_tolerance(row):
    value = number(row.get("tolerance"))
    return value if value is not None else 0.0


def error_vs_time(summary, out_dir):
    families = list(dict.fromkeys(r["family"] for r in summary))
    methods = list(dict.fromkeys(r["method"] for r in summary))
    colour, marker = colours(methods), markers(methods)
    rows, cols = grid(len(families))
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    handles = {}
    for index, family in enumerate(families):
        ax = axes[index // cols][index % cols]
        entries = [r for r in summary if r["family"] == family]
        sweep = []
        for r in entries:
            t, e_max, e_med = number(r["time_median_ns"]), number(r["rel_error_max"]), number(r["rel_error_median"])
            if t is None or e_max is None:
                continue
            e_max, e_med = max(e_max, FLOOR), max(e_med if e_med is not None else e_max, FLOOR)
            m = r["method"]
            if m.startswith("hedra"):
                sweep.append((sweep_tolerance(r), t, e_max))
            ax.plot([t, t], [e_med, e_max], color=colour[m], linewidth=0.8, alpha=0.6)
            size = 11 if m == "hedra" else 7
            (h,) = ax.plot([t], [e_max], marker=marker[m], color=colour[m], markersize=size, linestyle="none",
                           label=m)
            if m == "hedra" or not m.startswith("hedra"):
                handles.setdefault(m, h)
            failures = int(r["failures"] or 0)
            if failures:
                ax.annotate(f"{failures} fail", (t, e_max), textcoords="offset points", xytext=(4, 3), fontsize=7,
                            color=colour[m])
        if sweep:
            sweep.sort()
            (h,) = ax.plot([s[1] for s in sweep], [s[2] for s in sweep], color="black", linewidth=1, alpha=0.7,
                           label="hedra tolerance sweep")
            handles.setdefault("hedra tolerance sweep", h)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(family, fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        if index % cols == 0:
            ax.set_ylabel("max relative error")
        if index // cols == rows - 1:
            ax.set_xlabel("median time per query (ns)")
    for index in range(len(families), rows * cols):
        axes[index // cols][index % cols].axis("off")
    fig.legend(list(handles.values()), list(handles.keys()), loc="lower center", ncol=min(6, len(handles)),
               fontsize=8, bbox_to_anchor=(0.5, -0.02 - 0.02 * (len(handles) // 6)))
    fig.suptitle("hedra bench: error against time (bar: median to max error over the family's cases)")
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    save(fig, out_dir, "error_vs_time")


def stability_plot(rows_in, out_dir):
    families = list(dict.fromkeys(r["family"] for r in rows_in))
    if not families:
        return False
    methods = [m for m in dict.fromkeys(r["method"] for r in rows_in) if m == "hedra" or not m.startswith("hedra")]
    colour, marker = colours(methods), markers(methods)
    rows, cols = grid(len(families))
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    handles = {}
    for index, family in enumerate(families):
        ax = axes[index // cols][index % cols]
        name = ""
        for m in methods:
            points = []
            for r in rows_in:
                if r["family"] != family or r["method"] != m:
                    continue
                name = r["parameter_name"]
                p, e = number(r["parameter"]), number(r["rel_error_max"])
                if p is None or p <= 0 or e is None:
                    continue
                points.append((p, max(e, FLOOR)))
            if not points:
                continue
            points.sort()
            (h,) = ax.plot([p for p, _ in points], [e for _, e in points], marker=marker[m], color=colour[m],
                           linewidth=2 if m == "hedra" else 1, markersize=5, label=m)
            handles.setdefault(m, h)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(family, fontsize=10)
        ax.set_xlabel(name)
        ax.grid(True, which="major", alpha=0.3)
        if index % cols == 0:
            ax.set_ylabel("max relative error")
    for index in range(len(families), rows * cols):
        axes[index // cols][index % cols].axis("off")
    fig.legend(list(handles.values()), list(handles.keys()), loc="lower center", ncol=min(5, len(handles)),
               fontsize=8, bbox_to_anchor=(0.5, -0.04))
    fig.suptitle("hedra bench: stability (max relative error against each family's extreme parameter)")
    fig.tight_layout(rect=(0, 0.06, 1, 0.96))
    save(fig, out_dir, "stability")
    return True


def main(argv):
    if len(argv) != 2:
        print("usage: plot_bench.py OUT_DIR", file=sys.stderr)
        return 2
    out_dir = argv[1]
    try:
        summary = read_rows(os.path.join(out_dir, "summary.csv"))
        stability = read_rows(os.path.join(out_dir, "stability.csv"))
    except OSError as error:
        print(f"plot_bench.py: {error}", file=sys.stderr)
        return 2
    if not summary:
        print(f"plot_bench.py: {out_dir}/summary.csv has no rows", file=sys.stderr)
        return 2
    error_vs_time(summary, out_dir)
    stability_plot(stability, out_dir)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
