#!/usr/bin/env python3
"""A capsule swept along an arc across a tilted box: signed distance, contact depth and the first contact.

Every pose of the trajectory goes through one batch call each (penetration_many, contact_many), the
first contact through time_of_impact on each step. The figure shows the motion seen from the side
(coloured by signed distance, with the contact points of the deepest frame) and the curves along it.

    PYTHONPATH=build/python MPLBACKEND=Agg /usr/bin/python3 tools/python/examples/trajectory.py --out trajectory.png
"""
import argparse
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import hedra


def about_y(angle):
    """Scalar-first quaternion of a rotation by `angle` about the y axis."""
    return [math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0]


def trajectory(n):
    """n poses (n, 7) of the capsule: an arc over the box, dipping into it, turning as it goes."""
    t = np.linspace(0.0, 1.0, n)
    x = -2.2 + 4.4 * t
    z = 1.25 - 1.0 * np.sin(math.pi * t) ** 2
    angle = math.pi / 2 + 1.2 * (t - 0.5)  # lying along x, rocking
    return t, np.array([[xi, 0.0, zi, *about_y(a)] for xi, zi, a in zip(x, z, angle)])


def box_outline(half, pose):
    """The box's x-z section through y = 0 (it is rotated about y only)."""
    w, _, s, _ = pose[3:]
    angle = 2 * math.atan2(s, w)
    corners = np.array([[-half[0], -half[2]], [half[0], -half[2]], [half[0], half[2]], [-half[0], half[2]]])
    c, si = math.cos(angle), math.sin(angle)
    # x' = c x + s z, z' = -s x + c z (rotation about y)
    return np.column_stack([c * corners[:, 0] + si * corners[:, 1], -si * corners[:, 0] + c * corners[:, 1]]) + [
        pose[0],
        pose[2],
    ]


def capsule_outline(radius, half_length, pose, samples=24):
    w, _, s, _ = pose[3:]
    angle = 2 * math.atan2(s, w)
    axis = np.array([math.sin(angle), math.cos(angle)])  # local z in the x-z plane
    centre = np.array([pose[0], pose[2]])
    normal = np.array([axis[1], -axis[0]])
    phi = np.linspace(-math.pi / 2, math.pi / 2, samples)
    top = centre + half_length * axis + radius * (np.outer(np.cos(phi), axis) + np.outer(np.sin(phi), normal))
    bottom = centre - half_length * axis - radius * (np.outer(np.cos(phi), axis) + np.outer(np.sin(phi), normal))
    return np.vstack([top, bottom, top[:1]])  # closed


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="trajectory.png", help="the PNG to write")
    parser.add_argument("--frames", type=int, default=400)
    args = parser.parse_args()

    half = np.array([0.9, 0.6, 0.35])
    box = hedra.Box(half, margin=0.0)
    box_pose = np.array([0.0, 0.0, 0.0, *about_y(0.35)])
    capsule = hedra.Capsule(0.18, 0.45)

    t, poses = trajectory(args.frames)
    signed = hedra.penetration_many(capsule, poses, box, box_pose)
    manifold = hedra.contact_many(capsule, poses, box, box_pose, contact_distance=0.1)
    assert np.all(signed["status"] == 0) and np.all(manifold["status"] == 0)
    used = np.arange(4)[None, :] < manifold["count"][:, None]
    deepest = np.where(manifold["count"] > 0, np.where(used, manifold["depths"], -np.inf).max(axis=1), np.nan)

    # The first contact: time_of_impact on each step of the trajectory (a sweep between consecutive poses).
    first = None
    for i in range(len(t) - 1):
        toi = hedra.time_of_impact(capsule, poses[i], poses[i + 1], box, box_pose, box_pose)
        if toi.hit:
            first = t[i] + toi.fraction * (t[i + 1] - t[i])
            break

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 8), gridspec_kw={"height_ratios": [1.1, 1]})
    top.fill(*box_outline(half, box_pose).T, color="0.8", edgecolor="0.3", label="box")
    limit = np.abs(signed["distance"]).max()
    cmap = plt.get_cmap("coolwarm_r")
    for i in np.linspace(0, len(t) - 1, 11).astype(int):
        d = signed["distance"][i]
        top.plot(*capsule_outline(0.18, 0.45, poses[i]).T, color=cmap(0.5 + 0.5 * d / limit), lw=1.5)
    k = int(np.nanargmax(deepest))
    top.fill(*capsule_outline(0.18, 0.45, poses[k]).T, color=cmap(0.5 + 0.5 * signed["distance"][k] / limit),
             alpha=0.35)
    pts = manifold["points"][k][: manifold["count"][k]]
    top.plot(pts[:, 0], pts[:, 2], "k.", ms=9, label=f"contact points at t = {t[k]:.2f}")
    n = manifold["normal"][k]
    for p in pts:
        top.annotate("", xy=(p[0] - 0.3 * n[0], p[2] - 0.3 * n[2]), xytext=(p[0], p[2]),
                     arrowprops={"arrowstyle": "->", "color": "k"})
    top.plot(poses[:, 0], poses[:, 2], ":", color="0.4", lw=1, label="capsule centre")
    top.set_aspect("equal")
    top.set_xlabel("x")
    top.set_ylabel("z")
    top.set_title("A capsule swept over a tilted box (side view, colour: signed distance)")
    top.plot([], [], color="k", marker=r"$\rightarrow$", ls="none", label="-normal: out of the box")
    top.legend(loc="lower left", fontsize=8)

    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.plot(t, signed["distance"], label="signed distance (penetration_many)")
    bottom.plot(t, deepest, label="deepest contact depth (contact_many, contact_distance 0.1)")
    bottom.fill_between(t, 0, signed["distance"], where=signed["distance"] < 0, alpha=0.2, color="C3",
                        label="overlapping")
    if first is not None:
        bottom.axvline(first, color="k", ls="--", lw=1, label=f"first contact (time_of_impact), t = {first:.4f}")
    counts = bottom.twinx()
    counts.step(t, manifold["count"], where="mid", color="C2", alpha=0.5)
    counts.set_ylabel("contact points", color="C2")
    counts.set_ylim(0, 8)
    bottom.set_xlabel("t along the trajectory")
    bottom.set_ylabel("length")
    bottom.legend(loc="upper center", fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    fig.savefig(args.out, dpi=110)
    print(f"{args.out}: {len(t)} poses, deepest {np.nanmax(deepest):.4f} at t = {t[k]:.3f}, "
          f"first contact at t = {first:.4f}" if first is not None else f"{args.out}: no contact")


if __name__ == "__main__":
    main()
