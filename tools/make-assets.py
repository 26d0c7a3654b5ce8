#!/usr/bin/env python3
"""Makes the scenes in assets/ (chapter 05 on): OBJ files written by code, gzip-compressed.

    tools/make-assets.py           write every asset into assets/
    tools/make-assets.py --check   regenerate in memory and compare with the files in assets/

The output is the same on every run: no randomness, numbers written with a fixed number of
decimals, and gzip headers without a time stamp or a file name (mtime=0). Only the standard
library is used.

    torus_knot_100k.obj.gz  a (2,3) torus knot tube with twisted ridges: 50 000 vertices,
                            100 000 triangles, closed; the "100k triangles" model
    cornell_room.obj.gz     a closed room (red and green side walls), a ceiling light and two
    cornell_room.mtl        blocks; objects (o), materials (usemtl, mtllib), negative indices
    smooth_torus.obj.gz     a torus of 2 048 quads with normals (vn) and texture coordinates
                            (vt): corners written v/vt/vn, with vt numbered apart from v
"""
import argparse
import gzip
import io
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
ASSETS = ROOT / "assets"


def number(x, decimals):
    """Fixed decimals, and never "-0.000": the same text for +0 and -0."""
    text = f"{x:.{decimals}f}"
    return text[1:] if text.startswith("-") and text.strip("-0.") == "" else text


def vertex_line(keyword, p, decimals):
    return f"{keyword} " + " ".join(number(c, decimals) for c in p) + "\n"


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def torus_knot(along=500, around=100, p=2, q=3):
    """A tube around the (p, q) torus knot; the knot lies on a torus of radii 2 and 0.8 that
    stands in the x-y plane, facing +z. The tube's radius carries six ridges that twist twelve times around the knot.
    The grid closes in both directions, so the mesh is closed: along * around * 2 triangles."""
    big, small, tube = 2.0, 0.8, 0.3

    def centre(phi):
        r = big + small * math.cos(q * phi)
        return (r * math.cos(p * phi), r * math.sin(p * phi), small * math.sin(q * phi))

    out = io.StringIO()
    out.write(f"# A ({p},{q}) torus knot tube with twisted ridges, made by tools/make-assets.py\n")
    out.write(f"# {along * around} vertices, {2 * along * around} triangles, closed\n")
    out.write("o torus_knot\n")
    h = 1e-4
    for i in range(along):
        phi = 2 * math.pi * i / along
        c = centre(phi)
        tangent = normalize(sub(centre(phi + h), centre(phi - h)))
        # The frame turns with the torus the knot lies on: from the torus's core circle out to
        # the knot, made perpendicular to the tangent. It comes back to itself after one loop,
        # so the tube has no seam.
        core = (big * math.cos(p * phi), big * math.sin(p * phi), 0.0)
        out_of_core = sub(c, core)
        d = dot(out_of_core, tangent)
        normal = normalize(sub(out_of_core, (tangent[0] * d, tangent[1] * d, tangent[2] * d)))
        binormal = cross(tangent, normal)
        for j in range(around):
            theta = 2 * math.pi * j / around
            radius = tube * (1 + 0.12 * math.cos(6 * theta + 12 * phi))
            cs, sn = math.cos(theta) * radius, math.sin(theta) * radius
            out.write(vertex_line("v", tuple(c[k] + normal[k] * cs + binormal[k] * sn
                                             for k in range(3)), 4))
    index = lambda i, j: (i % along) * around + (j % around) + 1
    for i in range(along):
        for j in range(around):
            a, b = index(i, j), index(i + 1, j)
            c, d = index(i + 1, j + 1), index(i, j + 1)
            out.write(f"f {a} {c} {b}\nf {a} {d} {c}\n")
    return out.getvalue()


def cornell_room():
    """A closed box room 2 x 2 x 2 (x and z from -1 to 1, y from 0 to 2) whose walls are grids
    of 4 x 4 squares sharing their edge vertices; a light quad just under the ceiling; a short
    and a tall block standing on the floor, turned. Materials in the order white, red, green,
    light (material ids 0 to 3)."""
    out = io.StringIO()
    out.write("# A Cornell-style room, made by tools/make-assets.py\n")
    out.write("mtllib cornell_room.mtl\n")
    vertices, faces = [], []  # faces: (material, [1-based vertex indices]) for the room
    ids = {}

    def vertex(p):
        key = tuple(round(c, 9) for c in p)
        if key not in ids:
            vertices.append(p)
            ids[key] = len(vertices)
        return ids[key]

    cells = 4
    # Each wall: an origin corner and two edge vectors whose cross product points out of the
    # room; the quads run the other way round, so their normals point into the room.
    walls = [
        ("white", (-1, 0, -1), (2, 0, 0), (0, 0, 2)),  # floor
        ("white", (-1, 2, -1), (0, 0, 2), (2, 0, 0)),  # ceiling
        ("white", (-1, 0, -1), (0, 2, 0), (2, 0, 0)),  # back wall
        ("white", (-1, 0, 1), (2, 0, 0), (0, 2, 0)),  # front wall, behind the camera
        ("red", (-1, 0, -1), (0, 0, 2), (0, 2, 0)),  # left wall
        ("green", (1, 0, -1), (0, 2, 0), (0, 0, 2)),  # right wall
    ]
    for material, origin, eu, ev in walls:
        def at(u, v):
            return vertex(tuple(origin[k] + eu[k] * u / cells + ev[k] * v / cells
                                for k in range(3)))
        for u in range(cells):
            for v in range(cells):
                faces.append((material, [at(u, v), at(u, v + 1), at(u + 1, v + 1), at(u + 1, v)]))
    out.write("o room\n")
    for p in vertices:
        out.write(vertex_line("v", p, 4))
    current = None
    for material, corners in faces:
        if material != current:
            out.write(f"usemtl {material}\n")
            current = material
        out.write("f " + " ".join(str(c) for c in corners) + "\n")

    # The light and the blocks: their vertices, then faces with negative indices, which count
    # back from the latest vertex (-1 is the one just written).
    out.write("o light\nusemtl light\n")
    for p in [(-0.25, 1.98, -0.2), (0.25, 1.98, -0.2), (0.25, 1.98, 0.2), (-0.25, 1.98, 0.2)]:
        out.write(vertex_line("v", p, 4))
    out.write("f -4 -3 -2 -1\n")

    def block(name, cx, cz, half, height, degrees):
        a = math.radians(degrees)
        ca, sa = math.cos(a), math.sin(a)
        out.write(f"o {name}\nusemtl white\n")
        for y in (0.0, height):
            for dx, dz in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                x, z = dx * half, dz * half
                out.write(vertex_line("v", (cx + ca * x - sa * z, y, cz + sa * x + ca * z), 4))
        # Corners 1-4 at the bottom, 5-8 on top, as offsets -8..-1; outward normals.
        for quad in ((1, 2, 3, 4), (5, 8, 7, 6), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 8, 4),
                     (4, 8, 5, 1)):
            out.write("f " + " ".join(str(k - 9) for k in quad) + "\n")

    block("short_block", 0.36, -0.1, 0.27, 0.54, -17.0)
    block("tall_block", -0.36, -0.5, 0.27, 1.14, 20.0)
    return out.getvalue()


CORNELL_MTL = """\
# Materials of cornell_room.obj.gz, made by tools/make-assets.py
newmtl white
Kd 0.73 0.73 0.73

newmtl red
Kd 0.65 0.05 0.05

newmtl green
Kd 0.12 0.45 0.15

newmtl light
Kd 0.78 0.78 0.78
Ke 17 12 4
"""


def smooth_torus(around=64, tube_around=32, big=1.0, small=0.4):
    """A torus in the x-z plane: quads with a normal per vertex (vn, numbered like v) and
    texture coordinates (vt) on a grid one wider in each direction, because the texture's seam
    needs u = 0 and u = 1 at the same vertex."""
    out = io.StringIO()
    out.write("# A smooth torus with normals and texture coordinates, made by "
              "tools/make-assets.py\n")
    out.write(f"# {around * tube_around} quads: {2 * around * tube_around} triangles\n")
    out.write("o smooth_torus\n")
    for i in range(around):
        phi = 2 * math.pi * i / around
        for j in range(tube_around):
            theta = 2 * math.pi * j / tube_around
            r = big + small * math.cos(theta)
            out.write(vertex_line("v", (r * math.cos(phi), small * math.sin(theta),
                                        r * math.sin(phi)), 5))
    for i in range(around):
        phi = 2 * math.pi * i / around
        for j in range(tube_around):
            theta = 2 * math.pi * j / tube_around
            out.write(vertex_line("vn", (math.cos(theta) * math.cos(phi), math.sin(theta),
                                         math.cos(theta) * math.sin(phi)), 5))
    for i in range(around + 1):
        for j in range(tube_around + 1):
            out.write(vertex_line("vt", (i / around, j / tube_around), 5))
    out.write("s 1\n")  # a smoothing group: valid OBJ that the loader skips
    v = lambda i, j: (i % around) * tube_around + (j % tube_around) + 1
    vt = lambda i, j: i * (tube_around + 1) + j + 1
    for i in range(around):
        for j in range(tube_around):
            corners = [(i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j)]
            out.write("f " + " ".join(f"{v(a, b)}/{vt(a, b)}/{v(a, b)}" for a, b in corners)
                      + "\n")
    return out.getvalue()


def gzipped(text):
    buffer = io.BytesIO()
    with gzip.GzipFile(filename="", mode="wb", fileobj=buffer, compresslevel=9, mtime=0) as f:
        f.write(text.encode("ascii"))
    return buffer.getvalue()


def assets():
    """{file name: bytes} of every asset."""
    return {
        "torus_knot_100k.obj.gz": gzipped(torus_knot()),
        "cornell_room.obj.gz": gzipped(cornell_room()),
        "cornell_room.mtl": CORNELL_MTL.encode("ascii"),
        "smooth_torus.obj.gz": gzipped(smooth_torus()),
    }


def write_or_check(files, same_content=None):
    """Writes {name: bytes} into assets/, or with --check compares them with the files there.
    same_content(name, old, new) may call two different byte strings the same content (and say
    why, in the line it returns); a gzip file's text is compared here. Returns the exit status."""
    parser = argparse.ArgumentParser(description=sys.modules["__main__"].__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="compare with the files in assets/, write nothing")
    args = parser.parse_args()
    status = 0
    for name, data in files.items():
        path = ASSETS / name
        if not args.check:
            path.write_bytes(data)
            print(f"wrote assets/{name} ({len(data):,} bytes)")
            continue
        old = path.read_bytes() if path.exists() else None
        same = same_content(name, old, data) if same_content and old is not None else None
        if old == data:
            print(f"assets/{name}: identical")
        elif old is not None and name.endswith(".gz") and \
                gzip.decompress(old) == gzip.decompress(data):
            # The OBJ text is the same; this Python's zlib compresses it differently.
            print(f"assets/{name}: same text, different gzip bytes (another zlib)")
        elif same:
            print(f"assets/{name}: {same}")
        else:
            print(f"assets/{name}: DIFFERS")
            status = 1
    return status


def main():
    return write_or_check(assets())


if __name__ == "__main__":
    sys.exit(main())
