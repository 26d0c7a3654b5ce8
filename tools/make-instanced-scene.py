#!/usr/bin/env python3
"""Makes the instanced shelf in assets/: a glTF 2.0 scene whose few meshes are placed many times
by nested node transforms, for chapter 12's loader that keeps the node graph and chapter 13's
instancing.

    tools/make-instanced-scene.py           write the two files into assets/
    tools/make-instanced-scene.py --check   regenerate in memory and compare, write nothing

    instanced_shelf.gltf   the scene: 5 meshes, 35 instances, 46 nodes, 5 materials, a camera
    instanced_shelf.bin    its buffer (positions and indices)

The meshes, each stored once in its own space:
    floor   a square 8 x 8 on y = 0                                     2 triangles
    light   a square 1.6 x 1.6 facing down                             2 triangles
    box     the cube [-1, 1]^3, 8 shared corners                       12 triangles
    ball    an icosphere, radius 1, the icosahedron split twice       320 triangles
    ring    a torus of radii 1 and 0.35 in the x-z plane, 32 x 16   1 024 triangles
            in all                                                 1 360 triangles stored
The nodes: a root `shelves` (moved back by 0.5) holds three shelf units side by side, each
turned about y (+25, 0 and -25 degrees) and moved; a unit holds three boards and two uprights
(the box, scaled unevenly: 15 boxes in all) and two levels, moved up to their boards' tops,
each holding three items: balls and rings under rotations, uniform scales and uneven ones
(squashed balls, stretched rings). Four levels deep from the root to an item. The floor, the
light and the camera are roots of their own.
    instances: 1 floor + 1 light + 15 boxes + 9 balls + 9 rings = 35,
    placed: 2 + 2 + 180 + 2 880 + 9 216 = 12 280 triangles (the flattened scene's).

Every mesh is closed or a single square, wound counter-clockwise seen from outside (checked
below). Coordinates are rounded to 5 decimals before they become floats, and the rotations'
numbers to 7, so the output is the same on every run (--check compares it with assets/, through
make-assets.py's write_or_check). Only the standard library is used.
"""
import importlib.util
import json
import math
import pathlib
import struct
import sys

from gltf_buffers import BufferViews

ROOT = pathlib.Path(__file__).resolve().parent.parent

_spec = importlib.util.spec_from_file_location("make_assets", ROOT / "tools" / "make-assets.py")
make_assets = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_assets)

NAME = "instanced_shelf"
DECIMALS = 5  # of every vertex coordinate
ANGLE_DECIMALS = 7  # of every quaternion's numbers (the loader makes them unit again)

MATERIALS = [
    {"name": "floor", "pbrMetallicRoughness": {
        "baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9}},
    {"name": "wood", "pbrMetallicRoughness": {
        "baseColorFactor": [0.45, 0.28, 0.15, 1.0], "metallicFactor": 0.0,
        "roughnessFactor": 0.7}},
    {"name": "gold", "pbrMetallicRoughness": {
        "baseColorFactor": [0.99, 0.766, 0.336, 1.0], "metallicFactor": 1.0,
        "roughnessFactor": 0.3}},
    {"name": "red", "pbrMetallicRoughness": {
        "baseColorFactor": [0.7, 0.08, 0.06, 1.0], "metallicFactor": 0.0,
        "roughnessFactor": 0.4}},
    {"name": "light", "pbrMetallicRoughness": {
        "baseColorFactor": [0.78, 0.78, 0.78, 1.0], "metallicFactor": 0.0,
        "roughnessFactor": 1.0},
     "emissiveFactor": [1.0, 0.9, 0.75],
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12.0}}},
]

# The camera: in front of the shelves and above them, looking down at their middle.
CAMERA_EYE, CAMERA_TARGET, CAMERA_YFOV_DEGREES = (0.0, 1.5, 4.0), (0.0, 0.45, -0.4), 45.0


def rounded(p):
    return tuple(float(make_assets.number(c, DECIMALS)) for c in p)


def square(half, y, down):
    """A square of side 2 half on the plane y, facing +y (or -y where `down`)."""
    points = [(-half, y, -half), (half, y, -half), (half, y, half), (-half, y, half)]
    faces = [(0, 2, 1), (0, 3, 2)] if not down else [(0, 1, 2), (0, 2, 3)]
    return points, faces


def box():
    """The cube [-1, 1]^3: 8 corners shared by 12 triangles, two a face."""
    points = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    at = lambda x, y, z: 4 * (x > 0) + 2 * (y > 0) + (z > 0)
    faces = []
    for axis in range(3):
        for side in (-1, 1):
            # The face's corners in counter-clockwise order seen from outside (from +axis for
            # side 1): along u, then v, where (u, v, axis) is a right-handed frame.
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0, 0, 0]
                p[axis], p[u], p[v] = side, a, b
                corners.append(at(*p))
            if side < 0:
                corners.reverse()
            faces += [(corners[0], corners[1], corners[2]), (corners[0], corners[2], corners[3])]
    return points, faces


def icosphere(subdivisions=2):
    """An icosahedron whose faces are split in four `subdivisions` times, on the unit sphere:
    20 * 4^subdivisions triangles; a new vertex at each edge's middle, shared by both faces."""
    t = (1 + math.sqrt(5)) / 2
    points = [make_assets.normalize(p) for p in [
        (-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
        (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        middle = {}

        def middle_of(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                pa, pb = points[a], points[b]
                points.append(make_assets.normalize(
                    ((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2)))
                middle[key] = len(points) - 1
            return middle[key]

        split = []
        for a, b, c in faces:
            ab, bc, ca = middle_of(a, b), middle_of(b, c), middle_of(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    return points, faces


def torus(around=32, tube=16, big=1.0, small=0.35):
    """A torus in the x-z plane around the y axis: `around` x `tube` quads, two triangles each;
    the grid closes in both directions."""
    points = []
    for i in range(around):
        phi = 2 * math.pi * i / around
        for j in range(tube):
            theta = 2 * math.pi * j / tube
            r = big + small * math.cos(theta)
            points.append((r * math.cos(phi), small * math.sin(theta), -r * math.sin(phi)))
    at = lambda i, j: (i % around) * tube + j % tube
    faces = []
    for i in range(around):
        for j in range(tube):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            faces += [(a, b, c), (a, c, d)]
    return points, faces


MESHES = [  # name, (points, faces), material, the winding check's centre of a point
    ("floor", square(4.0, 0.0, down=False), 0, None),
    ("light", square(0.8, 3.0, down=True), 4, None),
    ("box", box(), 1, lambda p: (0.0, 0.0, 0.0)),
    ("ball", icosphere(), 2, lambda p: (0.0, 0.0, 0.0)),
    # A torus face looks away from the tube's centre circle, the point of radius 1 below it.
    ("ring", torus(), 3, lambda p: make_assets.normalize((p[0], 0.0, p[2]))),
]


def check_winding():
    """Each triangle's normal (counter-clockwise) points away from its centre; the floor's up,
    the light's down."""
    for name, (points, faces), _, centre_of in MESHES:
        for face in faces:
            a, b, c = (points[k] for k in face)
            normal = make_assets.cross(make_assets.sub(b, a), make_assets.sub(c, a))
            middle = tuple((a[k] + b[k] + c[k]) / 3 for k in range(3))
            if centre_of is None:
                outward = (0.0, -1.0 if name == "light" else 1.0, 0.0)
            else:
                outward = make_assets.sub(middle, centre_of(middle))
            if make_assets.dot(normal, outward) <= 0:
                raise SystemExit(f"{name}: triangle {face} is wound inward")


def quaternion(axis, degrees):
    """The unit quaternion (x, y, z, w) of a turn by `degrees` about `axis`, rounded."""
    axis = make_assets.normalize(axis)
    half = math.radians(degrees) / 2
    q = [axis[0] * math.sin(half), axis[1] * math.sin(half), axis[2] * math.sin(half),
         math.cos(half)]
    return [round(c, ANGLE_DECIMALS) + 0.0 for c in q]


BOARD_TOPS = (0.04, 0.5, 0.96)  # the three boards of a unit, 0.04 thick: their top faces
UNIT_HALF_WIDTH, UNIT_HALF_DEPTH, UPRIGHT_HALF = 0.6, 0.2, 0.02


def unit_boxes():
    """A shelf unit's boards and uprights: the box scaled unevenly and moved."""
    nodes = []
    for k, top in enumerate(BOARD_TOPS):
        nodes.append({"name": f"board {k}", "mesh": 2,
                      "translation": [0.0, top - 0.02, 0.0],
                      "scale": [UNIT_HALF_WIDTH, 0.02, UNIT_HALF_DEPTH]})
    for side in (-1, 1):
        nodes.append({"name": "upright", "mesh": 2,
                      "translation": [side * (UNIT_HALF_WIDTH + UPRIGHT_HALF), 0.5, 0.0],
                      "scale": [UPRIGHT_HALF, 0.5, UNIT_HALF_DEPTH]})
    return nodes


# The items of a level, in the level's space (its origin on the board's top, at its middle):
# (mesh, translation, rotation (axis, degrees) or None, scale). A ball of radius 1 scaled by
# s rests on the board at height s_y; a flat ring at 0.35 s_y; a ring stood up (turned 90
# degrees about x) at 1.35 s; one tilted by 30 degrees at (1.35 sin 30 + 0.35 cos 30) s, 0.98 s.
LEVELS = [
    [(3, (-0.38, 0.12, 0.0), None, (0.12, 0.12, 0.12)),
     (4, (0.0, 1.35 * 0.11, 0.02), ((1, 0, 0), 90), (0.11, 0.11, 0.11)),
     (3, (0.38, 0.08, -0.02), ((0, 1, 0), 30), (0.16, 0.08, 0.12))],
    [(4, (-0.36, 0.35 * 0.2, 0.0), ((0, 1, 0), 15), (0.16, 0.2, 0.12)),
     (3, (0.0, 0.1, 0.0), ((1, 1, 0), 40), (0.1, 0.1, 0.1)),
     (4, (0.36, 0.12, 0.0), ((0, 0, 1), 30), (0.12, 0.12, 0.12))],
]

# The shelf units: translation and turn about y.
UNITS = [((-1.45, 0.0, 0.35), 25.0), ((0.0, 0.0, 0.0), 0.0), ((1.45, 0.0, 0.35), -25.0)]


def nodes():
    """The node list: the shelves' tree first (depth first, as the loaders walk it), then the
    floor, the light and the camera."""
    out = [{"name": "shelves", "translation": [0.0, 0.0, -0.5], "children": []}]
    for u, (translation, turn) in enumerate(UNITS):
        unit = len(out)
        out[0]["children"].append(unit)
        out.append({"name": f"shelf {u}", "translation": list(translation),
                     "rotation": quaternion((0, 1, 0), turn), "children": []})
        for box_node in unit_boxes():
            out[unit]["children"].append(len(out))
            out.append(box_node)
        for k, items in enumerate(LEVELS):
            level = len(out)
            out[unit]["children"].append(level)
            out.append({"name": f"shelf {u} level {k}", "translation": [0.0, BOARD_TOPS[k], 0.0],
                        "children": []})
            for mesh, translation, rotation, scale in items:
                item = {"name": MESHES[mesh][0], "mesh": mesh,
                        "translation": [float(make_assets.number(c, DECIMALS))
                                        for c in translation]}
                if rotation is not None:
                    item["rotation"] = quaternion(*rotation)
                item["scale"] = list(scale)
                out[level]["children"].append(len(out))
                out.append(item)
    # The camera's node turns -z (where a glTF camera looks) towards the target: a turn about
    # x by the angle the view makes with the horizontal (the target is straight ahead in x).
    dy = CAMERA_TARGET[1] - CAMERA_EYE[1]
    dz = CAMERA_TARGET[2] - CAMERA_EYE[2]
    pitch = math.degrees(math.atan2(dy, -dz))
    out += [{"name": "floor", "mesh": 0}, {"name": "light", "mesh": 1},
            {"name": "camera", "camera": 0, "translation": list(CAMERA_EYE),
             "rotation": quaternion((1, 0, 0), pitch)}]
    return out


def gltf_files():
    blocks = BufferViews()
    add = blocks.add
    accessors, meshes = [], []

    for name, (points, faces), material, _ in MESHES:
        floats = [struct.unpack("<f", struct.pack("<f", c))[0]
                  for p in points for c in rounded(p)]
        view = add(struct.pack(f"<{len(floats)}f", *floats), 34962)
        accessors.append({"bufferView": view, "componentType": 5126, "count": len(points),
                          "type": "VEC3", "min": [min(floats[k::3]) for k in range(3)],
                          "max": [max(floats[k::3]) for k in range(3)]})
        corners = [c for face in faces for c in face]
        view = add(struct.pack(f"<{len(corners)}H", *corners), 34963)
        accessors.append({"bufferView": view, "componentType": 5123, "count": len(corners),
                          "type": "SCALAR"})
        meshes.append({"name": name, "primitives": [{
            "attributes": {"POSITION": len(accessors) - 2}, "indices": len(accessors) - 1,
            "material": material, "mode": 4}]})

    node_list = nodes()
    roots = [0] + list(range(len(node_list) - 3, len(node_list)))
    gltf = {
        "asset": {"version": "2.0", "generator": "tools/make-instanced-scene.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"name": "instanced shelf", "nodes": roots}],
        "nodes": node_list,
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": round(math.radians(CAMERA_YFOV_DEGREES), ANGLE_DECIMALS), "znear": 0.01}}],
        "meshes": meshes,
        "materials": MATERIALS,
        "buffers": [{"byteLength": len(blocks.buffer), "uri": NAME + ".bin"}],
        "bufferViews": blocks.views,
        "accessors": accessors,
    }
    return json.dumps(gltf, indent=1) + "\n", bytes(blocks.buffer)


def counts(gltf_text):
    """Instances and triangles stored and placed, read back from the file's JSON."""
    gltf = json.loads(gltf_text)
    triangles = [gltf["accessors"][m["primitives"][0]["indices"]]["count"] // 3
                 for m in gltf["meshes"]]
    placed = [n["mesh"] for n in gltf["nodes"] if "mesh" in n]
    return len(placed), sum(triangles), sum(triangles[m] for m in placed), len(gltf["nodes"])


def assets():
    check_winding()
    text, buffer = gltf_files()
    instances, stored, placed, node_count = counts(text)
    print(f"{NAME}: {instances} instances, {node_count} nodes, {stored} triangles stored, "
          f"{placed} placed")
    return {NAME + ".gltf": text.encode("ascii"), NAME + ".bin": buffer}


def main():
    return make_assets.write_or_check(assets())


if __name__ == "__main__":
    sys.exit(main())
