#!/usr/bin/env python3
"""Writes the meshes of the breakwater example scene (stdlib only; run from this folder).

Built for issue 20's untuned-scene target on 2026-12-03, after every default was chosen:
a sloped rubble-mound arm with a bend, a beacon tower, a wreck lying heeled on the seabed,
three three-pile dolphins and a seabed pipeline. Shapes the four built-in scenes and the
quay do not have: sloped faces, a 135-degree bend, a heeled hull, pile clusters.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from meshgen import cylinder, prism, write_obj  # noqa: E402


# Rubble-mound arm: trapezoid 10 m wide at the seabed, 3 m at the crest, 7.5 m high
# (seabed at -7 m, crest 0.5 m above the surface); x along the arm, origin at one end.
arm = [(-5.0, 0.0), (5.0, 0.0), (1.5, 7.5), (-1.5, 7.5)]
for name, length in (("arm_a.obj", 36.0), ("arm_b.obj", 30.0)):
    v, f = prism(arm, length)
    write_obj(name, f"rubble-mound arm, trapezoid 10/3 x 7.5 m, {length:.0f} m long", v, f)

# Wreck: a hull 14 m long, 4.5 m beam, 3.5 m deep, with a pointed bow (x forward).
hull = [(-7.0, -2.25), (4.5, -2.25), (7.0, 0.0), (4.5, 2.25), (-7.0, 2.25)]  # plan view (x, y)
n = len(hull)
verts = [(x, y, 0.0) for x, y in hull] + [(x, y, 3.5) for x, y in hull]
faces = []
for i in range(1, n - 1):
    faces.append((0, i + 1, i))
    faces.append((n, n + i, n + i + 1))
for i in range(n):
    j = (i + 1) % n
    faces += [(i, j, n + j), (i, n + j, n + i)]
write_obj("wreck.obj", "hull 14 x 4.5 x 3.5 m, pointed bow", verts, faces)

v, f = cylinder(1.2, 9.5, 8)
write_obj("beacon.obj", "octagonal beacon tower r 1.2 h 9.5 m", v, f)

# Dolphin: three piles r 0.35 on a 1.2 m triangle, 8 m high.
verts, faces = [], []
for k in range(3):
    a = 2 * math.pi * k / 3
    pv, pf = cylinder(0.35, 8.0, 12)
    off = len(verts)
    verts += [(x + 0.7 * math.cos(a), y + 0.7 * math.sin(a), z) for x, y, z in pv]
    faces += [(p + off, q + off, r + off) for p, q, r in pf]
write_obj("dolphin.obj", "three piles r 0.35 h 8 m on a 1.4 m triangle", verts, faces)

# Pipeline lying on the seabed, r 0.4, 40 m, along x.
section = [(0.4 * math.cos(2 * math.pi * k / 10), 0.4 + 0.4 * math.sin(2 * math.pi * k / 10)) for k in range(10)]
v, f = prism(section, 40.0)
write_obj("pipeline.obj", "pipe r 0.4 x 40 m on the seabed", v, f)
