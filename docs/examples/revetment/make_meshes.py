#!/usr/bin/env python3
"""Writes the meshes of the revetment example scene (stdlib only; run from this folder).

Built on 2026-12-07 as a held-out scene for issue 34's sloped-face fusion, after its
parameters were chosen on the breakwater (whose armour faces are 25 degrees from vertical):
faces at other slopes, and a vertical reference. A rock revetment at 1:1.5 (56 degrees from
vertical), a quay wall standing on a 45-degree apron, a scour-protection mound with
39-degree faces, and a row of round piles.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from meshgen import cylinder, prism, write_obj  # noqa: E402


# Revetment: the seaward face rises 7.5 m over 11.25 m (1:1.5) from the seabed (z 0) to a
# crest 0.5 m above the surface, 3 m of crest behind it; x along the shore.
v, f = prism([(-11.25, 0.0), (3.0, 0.0), (3.0, 7.5), (0.0, 7.5)], 70.0)
write_obj("revetment.obj", "rock revetment 1:1.5, 7.5 m high, 70 m long", v, f)

# Quay on an apron: a 45-degree apron from the seabed to 4 m, then a vertical wall to 7.5 m.
v, f = prism([(-4.0, 0.0), (3.0, 0.0), (3.0, 7.5), (0.0, 7.5), (0.0, 4.0)], 30.0)
write_obj("apron_quay.obj", "quay wall on a 45-degree apron, 7.5 m high, 30 m long", v, f)

# Scour mound: a truncated square pyramid, 12 m at the base, 4 m at the top, 5 m high.
b, t, hgt = 6.0, 2.0, 5.0
verts = [(-b, -b, 0.0), (b, -b, 0.0), (b, b, 0.0), (-b, b, 0.0),
         (-t, -t, hgt), (t, -t, hgt), (t, t, hgt), (-t, t, hgt)]
faces = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7)]
for i in range(4):
    j = (i + 1) % 4
    faces += [(i, j, 4 + j), (i, 4 + j, 4 + i)]
write_obj("mound.obj", "scour mound 12/4 x 5 m, faces 39 degrees from vertical", verts, faces)

v, f = cylinder(0.3, 8.5, 12)
write_obj("pile.obj", "round pile r 0.3 h 8.5 m", v, f)
