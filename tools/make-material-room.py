#!/usr/bin/env python3
"""Makes chapter 12's material room in assets/, in two formats that describe the same scene.

    tools/make-material-room.py           write the four files into assets/
    tools/make-material-room.py --check   regenerate in memory and compare, write nothing

    material_room.obj.gz       chapter 11's Cornell room (its walls and light, without the
    material_room.mtl          blocks) with three spheres: smooth glass, rough gold and rough
    material_room.gltf         glass, and a floor textured with a checkerboard; OBJ + MTL
    material_room_floor.png    with the PBR extension (Pm, Pr), Ni, Tf and illum 7, and the
                               same scene as glTF 2.0 (its buffer in a base64 data URI), which
                               also carries a camera

Both files hold the same triangles in the same order (OBJ quads are split into the fans
(0 1 2), (0 2 3) that chapter 05's loader makes of them), the same numbers (the glTF's floats
are the OBJ's decimals rounded to float) and the same materials, and the floor's texture
coordinates agree once the OBJ's v is flipped: glTF's v runs down the image, OBJ's up, so a
corner with glTF uv (u, v) is written `vt u 1-v`.

The room's geometry is tools/make-assets.py's (imported, not copied). Only the standard
library is used; the output is the same on every run (fixed decimals, gzip without a time
stamp, the PNG compressed by zlib at level 9).
"""
import base64
import importlib.util
import io
import json
import math
import pathlib
import struct
import sys
import zlib

from gltf_buffers import BufferViews

ROOT = pathlib.Path(__file__).resolve().parent.parent
ASSETS = ROOT / "assets"

_spec = importlib.util.spec_from_file_location("make_assets", ROOT / "tools" / "make-assets.py")
make_assets = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_assets)

DECIMALS = 5
TEXTURE = "material_room_floor.png"

# name: (MTL statements after Kd, glTF material). Base colours stay at or below chapter 11's
# largest albedo, 0.99, which the OBJ loader would otherwise lower (gold's red F0 is 1.0 in
# most tables, 0.99 here; the glasses are 0.99 white). Every material gives a PBR statement
# (Pr at least), so that the OBJ loader makes each one glTF's metallic-roughness model, as the
# glTF file does.
MATERIALS = {
    "white": dict(kd=(0.73, 0.73, 0.73), metallic=0.0, roughness=1.0),
    "red": dict(kd=(0.65, 0.05, 0.05), metallic=0.0, roughness=1.0),
    "green": dict(kd=(0.12, 0.45, 0.15), metallic=0.0, roughness=1.0),
    "light": dict(kd=(0.78, 0.78, 0.78), metallic=0.0, roughness=1.0, ke=(17, 12, 4)),
    "floor": dict(kd=(0.73, 0.73, 0.73), metallic=0.0, roughness=1.0, texture=TEXTURE),
    "gold": dict(kd=(0.99, 0.766, 0.336), metallic=1.0, roughness=0.5),
    "glass": dict(kd=(0.99, 0.99, 0.99), metallic=0.0, roughness=0.0, ior=1.5,
                  transmission=1.0),
    "rough_glass": dict(kd=(0.99, 0.99, 0.99), metallic=0.0, roughness=0.4, ior=1.5,
                        transmission=1.0),
}

# (material, centre, radius) of the spheres: on the floor, apart from each other and the walls.
SPHERES = [
    ("gold", (-0.5, 0.3, -0.4), 0.3),
    ("glass", (0.48, 0.3, -0.3), 0.3),
    ("rough_glass", (0.0, 0.3, 0.25), 0.3),
]
SPHERE_SEGMENTS, SPHERE_RINGS = 64, 32  # 2 * 64 * 31 = 3 968 triangles a sphere

# The camera of the glTF file: inside the room by its front wall, as chapter 11's Cornell
# camera, looking a little down at the spheres. yfov is glTF's vertical field of view.
CAMERA_EYE, CAMERA_TARGET, CAMERA_YFOV_DEGREES = (0.0, 1.0, 0.98), (0.0, 0.85, 0.0), 78.0


def rounded(p):
    """The coordinates as the OBJ text holds them (and the glTF's floats are made from)."""
    return tuple(float(make_assets.number(c, DECIMALS)) for c in p)


def parse_room():
    """The Cornell room of make-assets.py (objects `room` and `light`; its blocks are left
    out): its vertices and its faces as (material, [0-based vertex indices])."""
    vertices, faces, obj = [], [], None
    material = None
    for line in make_assets.cornell_room().splitlines():
        words = line.split()
        if not words or words[0] == "#":
            continue
        if words[0] == "v":
            vertices.append(tuple(float(w) for w in words[1:4]))
        elif words[0] == "o":
            obj = words[1]
        elif words[0] == "usemtl":
            material = words[1]
        elif words[0] == "f" and obj in ("room", "light"):
            corners = [int(w) for w in words[1:]]
            corners = [c - 1 if c > 0 else len(vertices) + c for c in corners]
            faces.append((material, corners))
    return vertices, faces


def sphere(centre, radius):
    """A UV sphere: a vertex at each pole and SPHERE_RINGS - 1 rings of SPHERE_SEGMENTS;
    triangles at the poles, quads between the rings, all counter-clockwise seen from outside."""
    points = [(centre[0], centre[1] + radius, centre[2])]
    for ring in range(1, SPHERE_RINGS):
        theta = math.pi * ring / SPHERE_RINGS
        for s in range(SPHERE_SEGMENTS):
            phi = 2 * math.pi * s / SPHERE_SEGMENTS
            points.append((centre[0] + radius * math.sin(theta) * math.cos(phi),
                           centre[1] + radius * math.cos(theta),
                           centre[2] - radius * math.sin(theta) * math.sin(phi)))
    points.append((centre[0], centre[1] - radius, centre[2]))
    bottom = len(points) - 1
    at = lambda ring, s: 1 + (ring - 1) * SPHERE_SEGMENTS + s % SPHERE_SEGMENTS
    faces = []
    for s in range(SPHERE_SEGMENTS):
        faces.append([0, at(1, s), at(1, s + 1)])
        for ring in range(1, SPHERE_RINGS - 1):
            faces.append([at(ring, s), at(ring + 1, s), at(ring + 1, s + 1), at(ring, s + 1)])
        faces.append([at(SPHERE_RINGS - 1, s), bottom, at(SPHERE_RINGS - 1, s + 1)])
    return points, faces


def scene():
    """Groups of faces, one per material, in the order both files write them: each group is
    (material, vertices, faces as lists of local vertex indices, uv per vertex or None)."""
    room_vertices, room_faces = parse_room()
    groups = []
    order = ["floor", "white", "red", "green", "light"]
    for name in order:
        picked = []
        for material, corners in room_faces:
            on_floor = all(room_vertices[c][1] == 0.0 for c in corners)
            wanted = "floor" if material == "white" and on_floor else material
            if wanted == name:
                picked.append(corners)
        used = list(dict.fromkeys(c for corners in picked for c in corners))  # first use
        local = {c: k for k, c in enumerate(used)}
        vertices = [rounded(room_vertices[c]) for c in used]
        faces = [[local[c] for c in corners] for corners in picked]
        uv = None
        if name == "floor":  # glTF uv: u along x, v along z (down the image), 0..1 over it
            uv = [((p[0] + 1) / 2, (p[2] + 1) / 2) for p in vertices]
        groups.append((name, vertices, faces, uv))
    for name, centre, radius in SPHERES:
        points, faces = sphere(centre, radius)
        groups.append((name, [rounded(p) for p in points], faces, None))
    return groups


def triangles_of(faces):
    """Chapter 05's fans: (0 k k+1) for k = 1 .. n-2."""
    return [(f[0], f[k], f[k + 1]) for f in faces for k in range(1, len(f) - 1)]


def check_winding(groups):
    """Every sphere triangle faces away from its centre; the room's face into the room."""
    centres = {name: centre for name, centre, _ in SPHERES}
    for name, vertices, faces, _ in groups:
        centre = centres.get(name, (0.0, 1.0, 0.0))  # the room's middle
        for a, b, c in triangles_of(faces):
            pa, pb, pc = vertices[a], vertices[b], vertices[c]
            normal = make_assets.cross(make_assets.sub(pb, pa), make_assets.sub(pc, pa))
            mid = tuple((pa[k] + pb[k] + pc[k]) / 3 - centre[k] for k in range(3))
            outward = make_assets.dot(normal, mid) > 0
            assert outward == (name in centres), f"{name}: triangle {a} {b} {c} faces wrongly"


def obj_text(groups):
    out = io.StringIO()
    out.write("# Chapter 12's material room, made by tools/make-material-room.py\n")
    out.write("mtllib material_room.mtl\n")
    base, vt_base = 1, 1
    for name, vertices, faces, uv in groups:
        out.write(f"o {name}\n")
        for p in vertices:
            out.write(make_assets.vertex_line("v", p, DECIMALS))
        if uv is not None:  # OBJ's v runs up the image: flipped
            for u, v in uv:
                out.write(make_assets.vertex_line("vt", (u, 1 - v), DECIMALS))
        out.write(f"usemtl {name}\n")
        for f in faces:
            if uv is None:
                out.write("f " + " ".join(str(base + c) for c in f) + "\n")
            else:
                out.write("f " + " ".join(f"{base + c}/{vt_base + c}" for c in f) + "\n")
        base += len(vertices)
        vt_base += len(uv) if uv is not None else 0
    return out.getvalue()


def mtl_text():
    out = io.StringIO()
    out.write("# Materials of material_room.obj.gz, made by tools/make-material-room.py\n")
    out.write("# Pm metallic, Pr roughness (the PBR extension), Ni index of refraction,\n")
    out.write("# Tf and illum 7: glass that transmits and refracts\n")
    for name, m in MATERIALS.items():
        out.write(f"\nnewmtl {name}\n")
        out.write("Kd " + " ".join(f"{c:g}" for c in m["kd"]) + "\n")
        if "ke" in m:
            out.write("Ke " + " ".join(f"{c:g}" for c in m["ke"]) + "\n")
        out.write(f"Pm {m['metallic']:g}\nPr {m['roughness']:g}\n")
        if "ior" in m:
            out.write(f"Ni {m['ior']:g}\n")
        if m.get("transmission", 0) > 0:
            t = m["transmission"]
            out.write(f"Tf {t:g} {t:g} {t:g}\nillum 7\n")
        if "texture" in m:
            out.write(f"map_Kd {m['texture']}\n")
    return out.getvalue()


def gltf_text(groups):
    names = list(MATERIALS)
    blocks = BufferViews()
    add = blocks.add
    accessors, primitives = [], []

    for name, vertices, faces, uv in groups:
        floats = [struct.unpack("<f", struct.pack("<f", c))[0] for p in vertices for c in p]
        view = add(struct.pack(f"<{len(floats)}f", *floats), 34962)
        position = len(accessors)
        accessors.append({"bufferView": view, "componentType": 5126, "count": len(vertices),
                          "type": "VEC3", "min": [min(floats[k::3]) for k in range(3)],
                          "max": [max(floats[k::3]) for k in range(3)]})
        corners = [c for t in triangles_of(faces) for c in t]
        wide = len(vertices) > 65535
        view = add(struct.pack(f"<{len(corners)}{'I' if wide else 'H'}", *corners), 34963)
        accessors.append({"bufferView": view, "componentType": 5125 if wide else 5123,
                          "count": len(corners), "type": "SCALAR"})
        primitive = {"attributes": {"POSITION": position}, "indices": len(accessors) - 1,
                     "material": names.index(name), "mode": 4}
        if uv is not None:
            flat = [c for t in uv for c in t]
            view = add(struct.pack(f"<{len(flat)}f", *flat), 34962)
            primitive["attributes"]["TEXCOORD_0"] = len(accessors)
            accessors.append({"bufferView": view, "componentType": 5126, "count": len(uv),
                              "type": "VEC2"})
        primitives.append(primitive)

    materials = []
    for name, m in MATERIALS.items():
        pbr = {"baseColorFactor": list(m["kd"]) + [1.0], "metallicFactor": m["metallic"],
               "roughnessFactor": m["roughness"]}
        material = {"name": name, "pbrMetallicRoughness": pbr}
        extensions = {}
        if "texture" in m:
            pbr["baseColorTexture"] = {"index": 0}
        if "ke" in m:  # glTF's emissiveFactor lies in [0, 1]: the rest is the strength
            strength = max(m["ke"])
            material["emissiveFactor"] = [c / strength for c in m["ke"]]
            extensions["KHR_materials_emissive_strength"] = {"emissiveStrength": strength}
        if "ior" in m:
            extensions["KHR_materials_ior"] = {"ior": m["ior"]}
        if m.get("transmission", 0) > 0:
            extensions["KHR_materials_transmission"] = {"transmissionFactor": m["transmission"]}
        if extensions:
            material["extensions"] = extensions
        materials.append(material)

    # The camera's node turns -z (where a glTF camera looks) towards the target: a rotation
    # about x by the angle the view direction makes with the horizontal.
    dy = CAMERA_TARGET[1] - CAMERA_EYE[1]
    dz = CAMERA_TARGET[2] - CAMERA_EYE[2]
    pitch = math.atan2(dy, -dz)
    camera_node = {"name": "camera", "camera": 0, "translation": list(CAMERA_EYE),
                   "rotation": [math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2)]}
    gltf = {
        "asset": {"version": "2.0", "generator": "tools/make-material-room.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_ior",
                           "KHR_materials_transmission"],
        "scene": 0,
        "scenes": [{"name": "material room", "nodes": [0, 1]}],
        "nodes": [{"name": "room", "mesh": 0}, camera_node],
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": math.radians(CAMERA_YFOV_DEGREES), "znear": 0.01}}],
        "meshes": [{"name": "material room", "primitives": primitives}],
        "materials": materials,
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": TEXTURE}],
        "buffers": [{"byteLength": len(blocks.buffer),
                     "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(bytes(blocks.buffer)).decode("ascii")}],
        "bufferViews": blocks.views,
        "accessors": accessors,
    }
    return json.dumps(gltf, indent=1) + "\n"


def png_bytes(width, height, rows):
    """A PNG file of 8-bit RGB rows, written by hand: signature, IHDR, one IDAT, IEND."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    raw = b"".join(b"\x00" + bytes(row) for row in rows)  # filter type 0 (none) each row
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checkerboard(side=128, squares=8, light=240, dark=64):
    """side x side texels, squares x squares squares, sRGB greys, light in the top-left."""
    cell = side // squares
    rows = []
    for y in range(side):
        row = []
        for x in range(side):
            value = light if (x // cell + y // cell) % 2 == 0 else dark
            row.extend((value, value, value))
        rows.append(row)
    return png_bytes(side, side, rows)


def assets():
    groups = scene()
    check_winding(groups)
    return {
        "material_room.obj.gz": make_assets.gzipped(obj_text(groups)),
        "material_room.mtl": mtl_text().encode("ascii"),
        "material_room.gltf": gltf_text(groups).encode("ascii"),
        TEXTURE: checkerboard(),
    }


def png_pixels(data):
    """The decompressed IDAT of a PNG written by png_bytes."""
    at, idat = 8, b""
    while at < len(data):
        length = struct.unpack(">I", data[at:at + 4])[0]
        if data[at + 4:at + 8] == b"IDAT":
            idat += data[at + 8:at + 8 + length]
        at += 12 + length
    return zlib.decompress(idat)


def same_texels(name, old, new):
    """A PNG whose texels are the same is the same texture, whatever zlib packed it."""
    if name.endswith(".png") and png_pixels(old) == png_pixels(new):
        return "same texels, different zlib bytes (another zlib)"
    return None


def main():
    return make_assets.write_or_check(assets(), same_texels)


if __name__ == "__main__":
    sys.exit(main())
