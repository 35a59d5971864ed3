#!/usr/bin/python3
"""Instructions per call of resting_contact_benchmark's timed queries, under
callgrind (repeatable where timings are noisy): for each family and motion,
hedra's contact() cold and warm and Bullet's dispatched algorithm (warm, on
plain shapes and with polyhedral features), each counted inside its timed
call only (--toggle-collect) and divided by the number of calls.

Usage: resting_contact_instructions.py BENCHMARK [pairs=2] [frames=50] [family-prefix] [--modes cold,warm,...]
BENCHMARK is build/bin/resting_contact_benchmark (another build's binary
gives its own figures: before and after).
"""
import re
import subprocess
import sys
import tempfile

FAMILIES = ["hull8", "hull24", "equal_hull24", "hull200", "hull1000", "rounded_hull24", "box_hull24", "box_hull200", "hull_box200",
            "rounded_box_hull24", "sphere_box", "sphere_hull", "capsule_box", "capsule_hull", "cylinder_box",
            "cylinder_hull"]
MOTIONS = ["still", "sliding", "settling"]


def instructions(binary, pairs, frames, family, mode):
    with tempfile.NamedTemporaryFile(suffix=".callgrind") as out:
        run = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out.name}",
                              "--toggle-collect=*timed_query*", binary, str(pairs), str(frames), "1", family,
                              "--callgrind", mode], capture_output=True, text=True)
        refs = re.search(r"refs:\s+([\d,]+)", run.stderr)
        calls = re.search(r"(\d+) calls", run.stdout)
        if not refs or not calls or int(calls.group(1)) == 0:
            return float("nan")
        return int(refs.group(1).replace(",", "")) / int(calls.group(1))


def main():
    args = [a for a in sys.argv[1:]]
    modes = ["cold", "warm", "bullet", "bullet_polyhedral"]
    if "--modes" in args:
        k = args.index("--modes")
        modes = args[k + 1].split(",")
        del args[k:k + 2]
    if not args:
        sys.exit(__doc__)
    binary = args[0]
    pairs = int(args[1]) if len(args) > 1 else 2
    frames = int(args[2]) if len(args) > 2 else 50
    only = args[3] if len(args) > 3 else ""
    print("| pair | motion | " + " | ".join(f"{m} instructions" for m in modes) + " |")
    print("|---|---|" + "---|" * len(modes))
    for family in FAMILIES:
        if only and not family.startswith(only):
            continue
        for motion in MOTIONS:
            row = [instructions(binary, pairs, frames, f"{family}/{motion}", m) for m in modes]
            print(f"| {family} | {motion} | " + " | ".join(f"{x:,.0f}" for x in row) + " |", flush=True)


if __name__ == "__main__":
    main()
