#!/usr/bin/python3
"""Writes the MuJoCo scenes of tools/mujoco/scenes/ (hedra_mujoco's table,
docs/mujoco.md): /usr/bin/python3 tools/mujoco/make_scenes.py

Every scene uses MuJoCo's defaults (timestep 0.002 s, Newton solver,
friction 1) on a plane; meshes are written inline (<mesh vertex=...>),
boxes as their 8 corners, rocks as the hull of random points (seeded)."""
import math
import os
import random

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")


def box_vertices(hx, hy, hz):
    return " ".join(f"{sx * hx:g} {sy * hy:g} {sz * hz:g}"
                    for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1))


def scene(name, comment, assets, bodies, extra=""):
    text = f"""<!-- {comment}
     Written by tools/mujoco/make_scenes.py. -->
<mujoco model="{name}">
  <asset>
{assets}  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
{bodies}  </worldbody>
{extra}</mujoco>
"""
    with open(os.path.join(HERE, name + ".xml"), "w") as f:
        f.write(text)


def stack(n):
    assets = f'    <mesh name="cube" vertex="{box_vertices(0.05, 0.05, 0.05)}"/>\n'
    bodies = "".join(f'    <body name="cube{i}" pos="0 0 {0.05 + 0.1 * i:g}"><freejoint/>'
                     f'<geom type="mesh" mesh="cube"/></body>\n' for i in range(n))
    scene(f"stack_{n}", f"{n} mesh cubes of 10 cm stacked on a plane.", assets, bodies)


def main():
    for n in (3, 5, 8, 10):
        stack(n)
    # A cylinder (radius 5 cm, 30 cm long) lying on a static box and on the plane.
    lying = 'quat="0.70710678 0 0.70710678 0"'
    scene("cylinder_on_box", "A cylinder lying on a static box (a box-cylinder pair: libccd's MPR in MuJoCo 2.x).", "",
          '    <geom name="table" type="box" size="0.4 0.4 0.1" pos="0 0 0.1"/>\n'
          f'    <body name="cylinder" pos="0 0 0.25"><freejoint/><geom type="cylinder" size="0.05 0.15" {lying}/></body>\n')
    scene("cylinder_on_plane", "A cylinder lying on the plane.", "",
          f'    <body name="cylinder" pos="0 0 0.05"><freejoint/><geom type="cylinder" size="0.05 0.15" {lying}/></body>\n')
    # A long thin mesh box yawed 30 degrees on a static box.
    yaw = math.radians(30)
    scene("thin_box_yawed", "A long thin mesh box (60 x 4 x 2 cm) yawed 30 degrees on a static box.",
          f'    <mesh name="plank" vertex="{box_vertices(0.3, 0.02, 0.01)}"/>\n',
          '    <geom name="table" type="box" size="0.4 0.4 0.1" pos="0 0 0.1"/>\n'
          f'    <body name="plank" pos="0 0 0.21" quat="{math.cos(yaw / 2):.8f} 0 0 {math.sin(yaw / 2):.8f}">'
          '<freejoint/><geom type="mesh" mesh="plank"/></body>\n')
    # A capsule lying on a static mesh slab.
    scene("capsule_on_slab", "A capsule (radius 4 cm, 40 cm long) lying on a static mesh slab.",
          f'    <mesh name="slab" vertex="{box_vertices(0.4, 0.4, 0.05)}"/>\n',
          '    <geom name="slab" type="mesh" mesh="slab" pos="0 0 0.05"/>\n'
          f'    <body name="capsule" pos="0 0 0.14"><freejoint/><geom type="capsule" size="0.04 0.2" {lying}/></body>\n')
    # 30 convex rocks (six meshes, each the hull of 16 random points in an
    # ellipsoid about 8 x 6 x 5 cm) dropped in five layers into a pile.
    rng = random.Random(31)
    assets = ""
    for k in range(6):
        points = []
        while len(points) < 16:
            p = [rng.uniform(-1, 1) for _ in range(3)]
            if sum(c * c for c in p) <= 1.0:
                points.append(f"{0.04 * p[0]:.4f} {0.03 * p[1]:.4f} {0.025 * p[2]:.4f}")
        assets += f'    <mesh name="rock{k}" vertex="{" ".join(points)}"/>\n'
    bodies = ""
    for i in range(30):
        layer, slot = divmod(i, 6)
        x, y = (slot % 3 - 1) * 0.09, (slot // 3 - 0.5) * 0.08
        z = 0.05 + 0.07 * layer
        q = [rng.gauss(0, 1) for _ in range(4)]
        norm = math.sqrt(sum(c * c for c in q))
        quat = " ".join(f"{c / norm:.6f}" for c in q)
        bodies += (f'    <body name="rock{i}" pos="{x:g} {y + 0.01 * (layer % 2):g} {z:g}" quat="{quat}">'
                   f'<freejoint/><geom type="mesh" mesh="rock{i % 6}"/></body>\n')
    scene("rocks_30", "A pile of 30 convex mesh rocks (six meshes shared) dropped on a plane.", assets, bodies,
          "  <size nconmax=\"1000\" njmax=\"4000\"/>\n")
    # A light mesh box (0.1 kg) under a heavy one (100 kg): with MuJoCo's
    # default contact impedance (its stiffness follows the light box's mass)
    # and with harder contacts (solimp 0.99 0.999 0.0001, MuJoCo's way to
    # carry such a ratio).
    for name, extra in (("light_under_heavy", ""),
                        ("light_under_heavy_stiff", '  <default><geom solimp="0.99 0.999 0.0001"/></default>\n')):
        scene(name, "A light mesh box (10 cm, 0.1 kg) under a heavy mesh box (20 cm, 100 kg) on the plane"
              + (", harder contacts." if extra else "."),
              f'    <mesh name="small" vertex="{box_vertices(0.05, 0.05, 0.05)}"/>\n'
              f'    <mesh name="large" vertex="{box_vertices(0.1, 0.1, 0.1)}"/>\n',
              '    <body name="light" pos="0 0 0.05"><freejoint/><geom type="mesh" mesh="small" mass="0.1"/></body>\n'
              '    <body name="heavy" pos="0 0 0.2"><freejoint/><geom type="mesh" mesh="large" mass="100"/></body>\n',
              extra)
    # A mesh box (5 cm, 0.1 kg, friction 0.5) held in the air between two
    # mesh fingers on slide joints, each pushed inward by a constant 2 N
    # (a general actuator with a constant bias force and some damping): the
    # friction can hold 2 N against the box's 0.98 N weight, if the contacts
    # let it. gripper: MuJoCo's settings for grasping (elliptic cones,
    # impratio 10, noslip iterations); gripper_default_solver: MuJoCo's
    # defaults, whose soft friction lets any grasp creep.
    finger = box_vertices(0.01, 0.03, 0.05)
    for name, option in (("gripper", '  <option cone="elliptic" impratio="10" noslip_iterations="10"/>\n'),
                         ("gripper_default_solver", "")):
        scene(name, "A mesh box held between two mesh fingers on slide joints, squeezed by 2 N each"
              + (" (MuJoCo's grasping settings)." if option else " (MuJoCo's default solver settings)."),
              f'    <mesh name="finger" vertex="{finger}"/>\n'
              f'    <mesh name="part" vertex="{box_vertices(0.025, 0.025, 0.025)}"/>\n',
              '    <body name="part" pos="0 0 0.5"><freejoint/>'
              '<geom type="mesh" mesh="part" mass="0.1" friction="0.5"/></body>\n'
              '    <body name="left" pos="-0.035 0 0.5"><joint name="left" type="slide" axis="1 0 0" damping="1"/>'
              '<geom type="mesh" mesh="finger" mass="0.05" friction="0.5"/></body>\n'
              '    <body name="right" pos="0.035 0 0.5"><joint name="right" type="slide" axis="-1 0 0" damping="1"/>'
              '<geom type="mesh" mesh="finger" mass="0.05" friction="0.5"/></body>\n',
              option +
              '  <actuator>\n'
              '    <general joint="left" gainprm="0" biastype="affine" biasprm="2 0 -1"/>\n'
              '    <general joint="right" gainprm="0" biastype="affine" biasprm="2 0 -1"/>\n'
              '  </actuator>\n')

if __name__ == "__main__":
    main()
