#!/usr/bin/python3
"""The table of docs/mujoco.md: every scene of tools/mujoco/scenes/ with
hedra, MuJoCo's own single-point MPR and MuJoCo with multiccd, from the same
start, REPEAT times (the step time is the median of the runs' medians; the
other figures are the same in every repeat: the runs are deterministic).

  /usr/bin/python3 tools/mujoco/make_table.py build/bin/hedra_mujoco [--seconds 10] [--repeat 3] [--only NAME]
"""
import argparse
import glob
import json
import os
import statistics
import subprocess

here = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("program")
parser.add_argument("--seconds", type=float, default=10.0)
parser.add_argument("--repeat", type=int, default=3)
parser.add_argument("--only", default="*", help="scene name pattern (default: every scene)")
args = parser.parse_args()


def runs(scene, *flags):
    out = subprocess.run([args.program, scene, "--seconds", str(args.seconds), "--json", *flags],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["runs"]


print("| scene | narrowphase | max_drift (m) | max_displacement (m) | max_penetration (m) | contacts/step "
      "| step_us | vs multiccd | vs MPR | nan |")
print("|---|---|---|---|---|---|---|---|---|---|")
for scene in sorted(glob.glob(os.path.join(here, "scenes", args.only + ".xml"))):
    table = {}
    for _ in range(args.repeat):
        for r in runs(scene, "--narrowphase", "both") + runs(scene, "--narrowphase", "mujoco", "--multiccd"):
            table.setdefault(r["narrowphase"], []).append(r)
    step = {k: statistics.median(r["step_us"] for r in v) for k, v in table.items()}
    name = os.path.splitext(os.path.basename(scene))[0]
    for k in ("hedra", "mujoco-multiccd", "mujoco"):
        r = table[k][0]
        print(f"| {name} | {k} | {r['max_drift']:.2g} | {r['max_displacement']:.2g} | {r['max_penetration']:.2g} "
              f"| {r['mean_contacts']:.1f} | {step[k]:.1f} | {step[k] / step['mujoco-multiccd']:.2f} "
              f"| {step[k] / step['mujoco']:.2f} | {'yes' if r['nan'] else 'no'} |")
