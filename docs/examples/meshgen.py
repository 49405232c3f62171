"""Shared by the example scenes' make_meshes.py (stdlib only): the OBJ writer and the faces of
a closed cylinder whose two vertex rings and two end centres are laid out as
[ring 0 (sides), ring 1 (sides), centre 0, centre 1]."""


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
