"""Shared by the example scenes' make_meshes.py (stdlib only): the OBJ writer, the faces of
a closed cylinder whose two vertex rings and two end centres are laid out as
[ring 0 (sides), ring 1 (sides), centre 0, centre 1], a closed vertical cylinder and a prism
of a polygonal section."""
import math


def write_obj(path, comment, verts, faces):
    with open(path, "w") as f:
        f.write(f"# orthosonar example: {comment}\n")
        for v in verts:
            f.write("v %.4f %.4f %.4f\n" % v)
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


def closed_cylinder_faces(sides):
    c0, c1 = 2 * sides, 2 * sides + 1
    faces = []
    for k in range(sides):
        j = (k + 1) % sides
        faces += [(k, j, sides + j), (k, sides + j, sides + k), (c0, j, k), (c1, sides + k, sides + j)]
    return faces


def prism(section, length):
    """A prism along x from 0 to length with the (y, z) polygon `section` (counter-clockwise)."""
    n = len(section)
    verts = [(0.0, y, z) for y, z in section] + [(length, y, z) for y, z in section]
    faces = []
    for i in range(1, n - 1):  # two end caps, fanned
        faces.append((0, i + 1, i))
        faces.append((n, n + i, n + i + 1))
    for i in range(n):
        j = (i + 1) % n
        faces.append((i, j, n + j))
        faces.append((i, n + j, n + i))
    return verts, faces


def cylinder(r, h, sides):
    """A closed vertical cylinder of radius r from z 0 to h, `sides` faces round."""
    ring = [(r * math.cos(2 * math.pi * k / sides), r * math.sin(2 * math.pi * k / sides)) for k in range(sides)]
    verts = [(x, y, 0.0) for x, y in ring] + [(x, y, h) for x, y in ring] + [(0.0, 0.0, 0.0), (0.0, 0.0, h)]
    return verts, closed_cylinder_faces(sides)
