#!/usr/bin/env python3
"""Where a query's instructions go, per family: callgrind's exclusive counts
of every function under hedra's query, grouped by the phase it belongs to.

  instruction_breakdown.py PROFILE DUMPS [--query penetration|distance|intersect] [FAMILY...]

PROFILE is build/bin/penetration_profile, DUMPS a folder of FAMILY.txt files
written by `build/bin/penetration_cases dump DUMPS/FAMILY.txt FAMILY`. Prints a
Markdown table: instructions per query and the share of each phase. Phases
are told apart by function name (inlined code counts where it was inlined:
the rotation of B's support direction inside GJK's loop, for instance):
  supports      support mappings (the scans and climbs of hulls, curved cores)
  simplex       GJK's signed-volume sub-algorithm (s1d/s2d/s3d, area vectors, adopt)
  gjk loop      the rest of GJK (its loop, start, finish, B's rotation)
  epa           EPA's polytope (expansion, horizon, face scan, nearest face)
  curved        exact curved-pair paths (revolution, tilted, peg-in-hole, closed forms)
  setup         validation, poses, dispatch, world witnesses, everything else
"""
import os
import re
import subprocess
import sys
import tempfile

PHASES = [
    ("supports", re.compile(r"support|first_block_max|cold_start|climb|accurate_hypot|hypot")),
    ("simplex", re.compile(r"gjk_detail::(s1d|s2d|s3d|adopt|vertex|signed_volumes)|area_vector")),
    ("gjk loop", re.compile(r"gjk_detail::|gjk_distance|gjk_intersect")),
    ("epa", re.compile(r"epa")),
    ("curved", re.compile(r"revolution|tilted|closed_form|peg|branch_and_bound|azimuth")),
]
SHARED = re.compile(r"area_vector")
FAMILIES = ["poly-separated", "poly-penetrating", "touching", "deep", "parallel", "thin", "scale", "far",
            "large-hull", "rounded", "curved", "degenerate"]


def phase_of(function):
    for name, pattern in PHASES:
        if pattern.search(function):
            return name
    return "setup"


def measure(profile, dump, query):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "cg.out")
        args = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out,
                "--toggle-collect=hedra::collision::%s(*" % query, profile, "run", dump]
        if query != "penetration":
            args += ["--query", query]
        run = subprocess.run(args, capture_output=True, text=True, check=True)
        queries = int(re.search(r"queries +(\d+)", run.stdout).group(1))
        table = subprocess.run(["callgrind_annotate", "--threshold=100", "--show-percs=no", "--tree=caller", out],
                               capture_output=True, text=True, check=True).stdout
    # Blocks of "<" lines (a caller and the inclusive cost it spent in the
    # function) closed by the function's "*" line (its exclusive cost). A
    # function shared between phases (area vectors: GJK's triangles and EPA's
    # faces) is split between its callers' phases, pro rata.
    totals, callers = {}, []
    for line in table.splitlines():
        m = re.match(r"^\s*([\d,]+)\s+([<*])\s+(\S.*)$", line)
        if not m:
            if not line.strip():
                callers = []
            continue
        cost = int(m.group(1).replace(",", ""))
        function = m.group(3).split(":", 1)[1] if ":" in m.group(3) else m.group(3)
        if m.group(2) == "<":
            callers.append((cost, phase_of(function)))
            continue
        if SHARED.search(function) and callers:
            spent = sum(c for c, _ in callers)
            for c, phase in callers:
                totals[phase] = totals.get(phase, 0) + cost * c / spent
        else:
            totals[phase_of(function)] = totals.get(phase_of(function), 0) + cost
        callers = []
    return queries, totals


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    profile, dumps, rest = argv[1], argv[2], argv[3:]
    query = "penetration"
    if "--query" in rest:
        i = rest.index("--query")
        query = rest[i + 1]
        rest = rest[:i] + rest[i + 2:]
    families = rest or FAMILIES
    names = [name for name, _ in PHASES] + ["setup"]
    print("| family | instructions per query | " + " | ".join(names) + " |")
    print("|---|---:|" + "---:|" * len(names))
    for family in families:
        queries, totals = measure(profile, os.path.join(dumps, family + ".txt"), query)
        whole = sum(totals.values())
        shares = " | ".join("%.0f %%" % (100.0 * totals.get(n, 0) / whole) if whole else "-" for n in names)
        print("| %s | %d | %s |" % (family, whole / max(queries, 1), shares), flush=True)


if __name__ == "__main__":
    main(sys.argv)
