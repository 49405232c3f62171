#!/usr/bin/env python3
"""Writes the meshes of the jacket example scene (stdlib only; run from this folder).

Built for issue 20's untuned-scene target on 2026-12-03, after the robust loop loss became a
default: an offshore jacket (four battered legs, horizontal and X bracing), a monopile with a
rock scour apron, and a subsea manifold with a spool to the jacket. Thin members seen from
every side, the opposite of the quay's and the breakwater's one long face.
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from meshgen import closed_cylinder_faces, write_obj  # noqa: E402


def tube(p, q, r, sides=10):
    """A closed cylinder of radius r from point p to point q."""
    d = [q[i] - p[i] for i in range(3)]
    n = math.sqrt(sum(c * c for c in d))
    d = [c / n for c in d]
    a = [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0]
    u = [d[1] * a[2] - d[2] * a[1], d[2] * a[0] - d[0] * a[2], d[0] * a[1] - d[1] * a[0]]
    un = math.sqrt(sum(c * c for c in u))
    u = [c / un for c in u]
    w = [d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2], d[0] * u[1] - d[1] * u[0]]
    verts = []
    for end in (p, q):
        for k in range(sides):
            t = 2 * math.pi * k / sides
            verts.append(tuple(end[i] + r * (math.cos(t) * u[i] + math.sin(t) * w[i]) for i in range(3)))
    verts += [tuple(p), tuple(q)]
    return verts, closed_cylinder_faces(sides)


def merge(parts):
    verts, faces = [], []
    for v, f in parts:
        off = len(verts)
        verts += v
        faces += [(a + off, b + off, c + off) for a, b, c in f]
    return verts, faces


def box(sx, sy, sz):
    v = [(x, y, z) for z in (0.0, sz) for y in (-sy / 2, sy / 2) for x in (-sx / 2, sx / 2)]
    f = [(0, 3, 1), (0, 2, 3), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (1, 3, 7), (1, 7, 5),
         (3, 2, 6), (3, 6, 7), (2, 0, 4), (2, 4, 6)]
    return v, f


# Jacket: legs from a 14 m square at the seabed (z 0) to a 10 m square at z 14 (above the
# surface in 12 m of water); bracing rings at z 4 and 9, X braces on each face between them.
def leg_xy(k, z):
    half = 7.0 - 2.0 * z / 14.0
    sx, sy = ((1, 1), (-1, 1), (-1, -1), (1, -1))[k]
    return (sx * half, sy * half, z)


parts = [tube(leg_xy(k, 0.0), leg_xy(k, 14.0), 0.6, 12) for k in range(4)]
for z in (4.0, 9.0):
    parts += [tube(leg_xy(k, z), leg_xy((k + 1) % 4, z), 0.25) for k in range(4)]
for k in range(4):
    j = (k + 1) % 4
    parts += [tube(leg_xy(k, 4.0), leg_xy(j, 9.0), 0.2), tube(leg_xy(j, 4.0), leg_xy(k, 9.0), 0.2)]
write_obj("jacket.obj", "four-legged jacket, 14 m base, braces at 4 and 9 m", *merge(parts))

# Monopile r 2.5 m standing 14 m, with a rock apron (a low cone, r 9 m, 1.2 m high).
pile_v, pile_f = tube((0.0, 0.0, 0.0), (0.0, 0.0, 14.0), 2.5, 24)
apron_v = [(9.0 * math.cos(2 * math.pi * k / 24), 9.0 * math.sin(2 * math.pi * k / 24), 0.0) for k in range(24)]
apron_v += [(2.6 * math.cos(2 * math.pi * k / 24), 2.6 * math.sin(2 * math.pi * k / 24), 1.2) for k in range(24)]
apron_f = []
for k in range(24):
    j = (k + 1) % 24
    apron_f += [(k, j, 24 + j), (k, 24 + j, 24 + k)]
write_obj("monopile.obj", "monopile r 2.5 h 14 m with a rock apron r 9 x 1.2 m", *merge([(pile_v, pile_f), (apron_v, apron_f)]))

# Manifold: a 6 x 4 x 3 m box with a 20 m spool (r 0.3) along x at 0.5 m.
mv, mf = box(6.0, 4.0, 3.0)
write_obj("manifold.obj", "manifold 6 x 4 x 3 m with a 20 m spool", *merge([(mv, mf), tube((3.0, 0.0, 0.5), (23.0, 0.0, 0.5), 0.3)]))
