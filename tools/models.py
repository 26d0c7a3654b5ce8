#!/usr/bin/env python3
"""The real models the course measures on (chapter 07 on): where each one comes from, how it
becomes the NAME.obj.gz file the programs read, and how a copy is checked. Run it through
tools/get-models.sh, which documents the options (tools/get-models.sh --help).

A copy is right when its vertex count, its triangle count (faces fanned in file order, as
chapter 05's loader fans them) and its bounding box are those below. The box is compared to
1e-5 of the model's largest extent, since copies differ in how many digits they print; the
counts must be exact. A download is checked more strictly still: the bytes fetched against a
SHA-256 where the source is a fixed file, and the converted vertex and face lines against a
SHA-256 of the same conversion made from a copy of the same source.

Only the standard library is used.
"""
import argparse
import gzip
import hashlib
import os
import pathlib
import shutil
import sys
import tarfile
import tempfile
import urllib.request
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT_DEST = ROOT / "models"
BOX_TOLERANCE = 1e-5  # of the largest extent
DOWNLOAD_TIMEOUT_S = 120

STANFORD_TERMS = (
    "Stanford 3D Scanning Repository terms: free for research, may be mirrored and "
    "redistributed free of charge, images may be published with credit to the Stanford "
    "Computer Graphics Laboratory; no commercial use without Stanford's permission"
)


class Model:
    def __init__(self, name, benchmark, vertices, triangles, lo, hi, origin, terms,
                 url=None, kind=None, member=None, sha256=None, lines_sha256=None,
                 mtl=None, note=None):
        self.name = name
        self.benchmark = benchmark  # one of the five scenes of the benchmark protocol
        self.vertices = vertices
        self.triangles = triangles  # after fanning every face in file order
        self.lo, self.hi = lo, hi  # bounding box of the vertices
        self.origin = origin  # who made it, and where this copy comes from
        self.terms = terms
        self.url = url  # None: no public source serves this exact file
        self.kind = kind  # "obj" (the file itself), "obj-in-zip", "ply-in-tar"
        self.member = member  # the file inside the archive
        self.sha256 = sha256  # of the fetched file, for kind "obj"
        self.lines_sha256 = lines_sha256  # of the converted file's v and f lines
        self.mtl = mtl  # (url, sha256) of a material file that goes beside it
        self.note = note  # why there is no download, where there is none


CATALOGUE = [
    Model(
        "stanford-bunny", True, 35947, 69451,
        (-0.09469, 0.032987, -0.061874), (0.061009, 0.187321, 0.0588),
        "the Stanford Bunny (Turk & Levoy 1994), bun_zipper.ply, Stanford 3D Scanning "
        "Repository",
        STANFORD_TERMS,
        url="http://graphics.stanford.edu/pub/3Dscanrep/bunny.tar.gz",
        kind="ply-in-tar", member="bun_zipper.ply",
        lines_sha256="205b80d216a4c4fd0a7e9a313e1ac37af0df0df068f1291cb969d4028136075c"),
    Model(
        "armadillo-100k", True, 49990, 99976,
        (-63.497261, -54.220013, -57.714516), (63.51741, 97.087029, 57.696472),
        "the Stanford Armadillo (Krishnamurthy & Levoy 1996), decimated to 49,990 vertices; "
        "this copy is data/armadillo.obj of github.com/Profactor/continuous-remeshing",
        STANFORD_TERMS + " (the repository's MIT licence covers its code, not the mesh)",
        url="https://raw.githubusercontent.com/Profactor/continuous-remeshing/"
            "11fd2218ed86f54ee65c9aa536d0a79af36ee947/data/armadillo.obj",
        kind="obj",
        sha256="fd25edd020bef63a5999073774ef4f0775d6ce96b7b17370e69019585f953508"),
    Model(
        "stanford-dragon", True, 437645, 871414,
        (-0.108324, 0.0527295, -0.0504143), (0.0965662, 0.197173, 0.0412075),
        "the Stanford Dragon (Curless & Levoy 1996), dragon_vrip.ply, Stanford 3D Scanning "
        "Repository",
        STANFORD_TERMS + "; the dragon is a symbol of Chinese culture, and Stanford asks that "
        "it not be used in ways that disrespect it",
        url="http://graphics.stanford.edu/pub/3Dscanrep/dragon/dragon_recon.tar.gz",
        kind="ply-in-tar", member="dragon_vrip.ply",
        lines_sha256="4d18c14be010eb705d94cc36a08ee60137c86dae3d13a523f616dd6f7b51b755"),
    Model(
        "conference", True, 194399, 331179,
        (-1020.13, -2.7924, -1055.66), (1685.81, 650.293, 668.489),
        "Greg Ward and Anat Grynberg's conference room (about 1991), as rebuilt by Kenzie "
        "Lamar; Morgan McGuire's Computer Graphics Archive (casual-effects.com/data), "
        "conference.zip; units of 3 mm",
        "public domain; McGuire asks that work using the archive cite it",
        url="https://casual-effects.com/g3d/data10/research/model/conference/conference.zip",
        kind="obj-in-zip", member="conference.obj",
        lines_sha256="52930e5459e3cde18c7adee25914e07db8686cf08305ae1c0ecddd5b8f8f6a21"),
    Model(
        "sponza-dabrovic", True, 39999, 66454,
        (-17.40276, -0.906689, -7.798512), (17.41724, 15.653312, 7.801489),
        "Marko Dabrovic's Sponza atrium (2002), his own OBJ release (Max2Obj export) made for "
        "the CGTechniques rendering competition",
        "(c) 2002 Marko Dabrovic; free for non-commercial use with credit (McGuire's archive "
        "lists it as CC BY-NC)",
        note="the original release is no longer served where it was published, and the "
             "public Sponza of McGuire's archive is a later conversion with other triangles "
             "(66,450); copy the original sponza-dabrovic.obj.gz into the models folder, or "
             "run with --from on a folder that holds it"),
    Model(
        "teapot", False, 3644, 6320, (-3.0, 0.0, -2.0), (3.434, 3.15, 2.0),
        "Martin Newell's Utah teapot (1975), tessellated; this copy is data/teapot.obj of "
        "github.com/alecjacobson/common-3d-test-models",
        "Newell's patch data is freely used; the repository states no licence of its own",
        url="https://raw.githubusercontent.com/alecjacobson/common-3d-test-models/"
            "8a4f8642acaf43f9cd7b67858a1502e1055ef202/data/teapot.obj",
        kind="obj",
        sha256="1b5396fedd74b577e32cef41146582c2f2e1a050d5b4915193c0ac1ad4187ed4"),
    Model(
        "suzanne", False, 507, 968, (-3.86125, 0.267311, 3.25233),
        (-1.126875, 2.236061, 4.955455),
        "Blender's monkey head (Willem-Paul van Overbruggen, 2002); this copy is "
        "data/suzanne.obj of github.com/alecjacobson/common-3d-test-models",
        "part of Blender, GPL-2.0-or-later",
        url="https://raw.githubusercontent.com/alecjacobson/common-3d-test-models/"
            "8a4f8642acaf43f9cd7b67858a1502e1055ef202/data/suzanne.obj",
        kind="obj",
        sha256="d8684326f9bd8cfc24d3d302c1042fa16f63d2e66e49ed56b413fa20bed271e6"),
    Model(
        "cornell_box", False, 76, 36, (0.0, 0.0, 0.0), (556.0, 548.8, 559.2),
        "the Cornell box as measured by the Cornell Program of Computer Graphics, in the OBJ "
        "file that tinyobjloader ships (models/cornell_box.obj and .mtl, taken from Embree)",
        "tinyobjloader's MIT licence",
        url="https://raw.githubusercontent.com/tinyobjloader/tinyobjloader/"
            "72ef6cbb76bea690288f20e9d6fa61241ee3e0be/models/cornell_box.obj",
        kind="obj",
        sha256="e3bacf2d9c9b058a423d96ec1ae7c686da7e71699f66c2dd5e2cf121610ec044",
        mtl=("https://raw.githubusercontent.com/tinyobjloader/tinyobjloader/"
             "72ef6cbb76bea690288f20e9d6fa61241ee3e0be/models/cornell_box.mtl",
             "fd63222ca010b32a66e592ea95637abd39e61c74dd48ea40adf23b51a96e422b")),
]
BY_NAME = {m.name: m for m in CATALOGUE}


class ModelError(Exception):
    """What is wrong with one model; the others are still processed."""


# ---------------------------------------------------------------------------------------------
# Counting and measuring an OBJ file: what the checks compare.

def is_line(line, keyword):
    return line.startswith(keyword) and line[len(keyword):len(keyword) + 1] in (b" ", b"\t")


def measure_obj(data_lines):
    """Vertices, triangles (faces fanned), bounding box and the SHA-256 of the v and f lines
    of an OBJ file given as an iterable of byte lines. Refuses a face index that names no
    vertex, and a face of fewer than three corners."""
    lo = [float("inf")] * 3
    hi = [-float("inf")] * 3
    vertices = triangles = highest_index = 0
    lines_hash = hashlib.sha256()
    for number, line in enumerate(data_lines, 1):
        if is_line(line, b"v"):
            fields = line.split()
            try:
                point = [float(fields[1]), float(fields[2]), float(fields[3])]
            except (IndexError, ValueError):
                raise ModelError(f"line {number}: a vertex without three numbers")
            for axis in range(3):
                lo[axis] = min(lo[axis], point[axis])
                hi[axis] = max(hi[axis], point[axis])
            vertices += 1
            lines_hash.update(line.rstrip() + b"\n")
        elif is_line(line, b"f"):
            corners = line.split()[1:]
            if len(corners) < 3:
                raise ModelError(f"line {number}: a face of {len(corners)} corners")
            for corner in corners:
                try:
                    index = int(corner.split(b"/", 1)[0])
                except ValueError:
                    raise ModelError(f"line {number}: a face corner {corner!r} names no vertex")
                if index < 0:
                    index += vertices + 1  # relative to the vertices read so far
                if index < 1:
                    raise ModelError(f"line {number}: a face names vertex {index}")
                highest_index = max(highest_index, index)
            triangles += len(corners) - 2
            lines_hash.update(line.rstrip() + b"\n")
    if highest_index > vertices:
        raise ModelError(f"a face names vertex {highest_index} of {vertices}")
    return vertices, triangles, (tuple(lo), tuple(hi)), lines_hash.hexdigest()


def check_measurements(model, measured, strict_lines):
    vertices, triangles, (lo, hi), lines_sha256 = measured
    problems = []
    if vertices != model.vertices:
        problems.append(f"{vertices:,} vertices, expected {model.vertices:,}")
    if triangles != model.triangles:
        problems.append(f"{triangles:,} triangles, expected {model.triangles:,}")
    extent = max(h - l for l, h in zip(model.lo, model.hi))
    for got, want, corner in ((lo, model.lo, "lower"), (hi, model.hi, "upper")):
        if any(not abs(g - w) <= BOX_TOLERANCE * extent for g, w in zip(got, want)):
            problems.append(f"{corner} box corner {format_point(got)}, expected "
                            f"{format_point(want)}")
    if strict_lines and model.lines_sha256 and lines_sha256 != model.lines_sha256:
        problems.append(f"vertex and face lines hash to {lines_sha256}, expected "
                        f"{model.lines_sha256}")
    if problems:
        raise ModelError("; ".join(problems))


def format_point(p):
    return "(" + ", ".join(f"{c:.9g}" for c in p) + ")"


def verify_file(model, path, strict_lines=False):
    try:
        with gzip.open(path, "rb") as stream:
            measured = measure_obj(stream)
    except (OSError, EOFError, ValueError) as error:
        raise ModelError(f"{path}: cannot be read as a gzip'd OBJ file ({error})")
    except ModelError as error:
        raise ModelError(f"{path}: {error}")
    check_measurements(model, measured, strict_lines)
    return measured


# ---------------------------------------------------------------------------------------------
# Converting: a Stanford PLY file to OBJ, and an OBJ file to the positions the course reads.

def ply_to_obj(ply_lines, out):
    """Writes an ASCII PLY file (the Stanford scans are ASCII) as OBJ: one `v x y z` line per
    vertex with the coordinates copied as text, digit for digit, and one `f` line per face
    with the indices counted from 1, both in the PLY's order, so triangle k of the OBJ is
    face k of the PLY. Other vertex properties (confidence, intensity) are dropped. Binary
    PLY files, and elements other than vertex and face, are refused rather than guessed at."""
    lines = iter(ply_lines)
    if next(lines, b"").strip() != b"ply":
        raise ModelError("not a PLY file")
    elements = []  # [name, count, [property names]]
    for line in lines:
        fields = line.split()
        if not fields or fields[0] in (b"comment", b"obj_info"):
            continue
        if fields[0] == b"format" and fields[1:2] != [b"ascii"]:
            raise ModelError(f"PLY format {fields[1:2]} is not ascii")
        elif fields[0] == b"element":
            elements.append([fields[1], int(fields[2]), []])
        elif fields[0] == b"property":
            elements[-1][2].append(fields[-1])
        elif fields[0] == b"end_header":
            break
    names = [e[0] for e in elements]
    if names != [b"vertex", b"face"]:
        raise ModelError(f"PLY elements {names}, expected vertex then face")
    (_, vertex_count, vertex_properties), (_, face_count, face_properties) = elements
    try:
        xyz = [vertex_properties.index(axis) for axis in (b"x", b"y", b"z")]
    except ValueError:
        raise ModelError("the PLY vertices have no x, y, z")
    if face_properties not in ([b"vertex_indices"], [b"vertex_index"]):
        raise ModelError(f"PLY face properties {face_properties}, expected one index list")
    for _ in range(vertex_count):
        fields = next(lines, b"").split()
        if len(fields) != len(vertex_properties):
            raise ModelError("a PLY vertex line of the wrong length, or the file ends early")
        out.write(b"v " + b" ".join(fields[i] for i in xyz) + b"\n")
    for _ in range(face_count):
        fields = next(lines, b"").split()
        if not fields or len(fields) != int(fields[0]) + 1:
            raise ModelError("a PLY face line of the wrong length, or the file ends early")
        out.write(b"f " + b" ".join(str(int(i) + 1).encode() for i in fields[1:]) + b"\n")


def obj_positions(obj_lines, out):
    """Keeps the vertex positions and the faces of an OBJ file, in order, and drops the rest
    (texture coordinates, normals, materials, groups): what the benchmark reads. A corner
    v/vt/vn becomes v, so the triangles, fanned in file order, are the same ones."""
    for line in obj_lines:
        if is_line(line, b"v"):
            out.write(b"v " + b" ".join(line.split()[1:4]) + b"\n")
        elif is_line(line, b"f"):
            corners = [c.split(b"/", 1)[0] for c in line.split()[1:]]
            out.write(b"f " + b" ".join(corners) + b"\n")


# ---------------------------------------------------------------------------------------------
# Downloading.

def fetch(url, path):
    request = urllib.request.Request(url, headers={"User-Agent": "get-models"})
    try:
        with urllib.request.urlopen(request, timeout=DOWNLOAD_TIMEOUT_S) as response, \
                open(path, "wb") as out:
            shutil.copyfileobj(response, out, 1 << 20)
    except (OSError, ValueError) as error:
        raise ModelError(f"cannot download {url}: {error}")


def sha256_of(path):
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def check_sha256(what, path, expected):
    actual = sha256_of(path)
    if actual != expected:
        raise ModelError(f"{what} has SHA-256 {actual}, expected {expected}: the source has "
                         "changed, or the download was damaged")


def archive_member(archive, kind, member, workdir):
    """Extracts the file whose name is `member` (in whatever folder of the archive)."""
    target = workdir / member
    try:
        if kind == "ply-in-tar":
            with tarfile.open(archive) as tar:
                found = [m for m in tar.getmembers()
                         if m.isfile() and pathlib.PurePosixPath(m.name).name == member]
                if found:
                    with tar.extractfile(found[0]) as src, open(target, "wb") as dst:
                        shutil.copyfileobj(src, dst, 1 << 20)
        else:
            with zipfile.ZipFile(archive) as zipped:
                found = [n for n in zipped.namelist()
                         if pathlib.PurePosixPath(n).name == member]
                if found:
                    with zipped.open(found[0]) as src, open(target, "wb") as dst:
                        shutil.copyfileobj(src, dst, 1 << 20)
    except (OSError, tarfile.TarError, zipfile.BadZipFile) as error:
        raise ModelError("cannot read the downloaded archive: " + " ".join(str(error).split()))
    if not found:
        raise ModelError(f"the downloaded archive holds no {member}")
    return target


def write_gzip(path, write_body, header):
    """gzip without a time stamp or a file name: the same input gives the same bytes."""
    with open(path, "wb") as raw, \
            gzip.GzipFile(filename="", mode="wb", fileobj=raw, mtime=0) as out:
        out.write(header)
        write_body(out)


def download(model, dest, workdir):
    if model.url is None:
        raise ModelError("no download: " + model.note)
    source = workdir / ("source" + pathlib.PurePosixPath(model.url).suffix)
    print(f"  downloading {model.url}", flush=True)
    fetch(model.url, source)
    staged = workdir / f"{model.name}.obj.gz"
    header = f"# {model.name}: {model.origin}\n# from {model.url}".encode()
    if model.kind == "obj":
        check_sha256(model.url, source, model.sha256)
        with open(source, "rb") as stream:
            write_gzip(staged, lambda out: shutil.copyfileobj(stream, out), b"")
    else:
        member = archive_member(source, model.kind, model.member, workdir)
        header += f" ({model.member})\n".encode()
        convert = ply_to_obj if model.kind == "ply-in-tar" else obj_positions
        with open(member, "rb") as stream:
            write_gzip(staged, lambda out: convert(stream, out), header)
    verify_file(model, staged, strict_lines=True)
    outputs = [(staged, dest / staged.name)]
    if model.mtl:
        mtl_url, mtl_sha256 = model.mtl
        mtl = workdir / f"{model.name}.mtl"
        fetch(mtl_url, mtl)
        check_sha256(mtl_url, mtl, mtl_sha256)
        outputs.append((mtl, dest / mtl.name))
    for staged_file, final in outputs:  # only now, every file checked, replace the old ones
        os.replace(staged_file, final)


def link_from(model, folder, dest):
    names = [f"{model.name}.obj.gz"] + ([f"{model.name}.mtl"] if model.mtl else [])
    sources = [(folder / n).resolve() for n in names]
    for source in sources:
        if not source.is_file():
            raise ModelError(f"{source} is missing")
    verify_file(model, sources[0])
    for source, name in zip(sources, names):
        if (dest / name).resolve() == source:
            continue
        temporary = dest / f".{name}.link"
        if temporary.is_symlink() or temporary.exists():
            temporary.unlink()
        temporary.symlink_to(source)
        os.replace(temporary, dest / name)


# ---------------------------------------------------------------------------------------------

HELP_EPILOG = """\
The programs look for the models in models/ at the repository's root (git ignores it);
chapter 07's and chapter 08's --models option points them elsewhere. The book's appendix A
(book/appendix_a_benchmark_protocol.md) names every source and its terms.

Without --from, each model is downloaded from its original public source, converted (the
Stanford PLY files to OBJ, vertices and faces in file order; the conference room reduced to
positions and faces) and checked before it replaces anything in the models folder: a failed
model leaves nothing behind and the others go on. The Sponza atrium has no download (its
original release is no longer served); copy it in, or use --from.

The download path was written without network access: its sources, checksums and converters
were checked against copies of the same files, but the downloads themselves have not been run
from here. If one fails, the error names the model and the address.
"""


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="tools/get-models.sh",
        description="Gets the real models the course measures on, or checks copies of them.",
        epilog=HELP_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help="models to get (default: all; 'benchmark': the five of the "
                             "benchmark set)")
    parser.add_argument("--from", dest="folder", metavar="DIR", type=pathlib.Path,
                        help="check DIR/NAME.obj.gz instead of downloading (no network), then "
                             "link them into the models folder")
    parser.add_argument("--dest", metavar="DIR", type=pathlib.Path, default=DEFAULT_DEST,
                        help="the models folder (default: models/ in the repository)")
    parser.add_argument("--list", action="store_true",
                        help="print the models, their sources and terms, and exit")
    return parser.parse_args(argv)


def chosen_models(names):
    if not names:
        return list(CATALOGUE)
    chosen = []
    for name in names:
        if name == "benchmark":
            chosen += [m for m in CATALOGUE if m.benchmark]
        elif name in BY_NAME:
            chosen.append(BY_NAME[name])
        else:
            raise SystemExit(f"get-models: no model called {name!r} (known: "
                             + ", ".join(BY_NAME) + ")")
    return chosen


def describe(model):
    print(f"{model.name}: {model.triangles:,} triangles, {model.vertices:,} vertices, box "
          f"{format_point(model.lo)} to {format_point(model.hi)}")
    print(f"  source: {model.origin}")
    print(f"  terms: {model.terms}")
    print(f"  download: {model.url or 'none (' + model.note + ')'}")


def main(argv):
    args = parse_arguments(argv)
    models = chosen_models(args.names)
    if args.list:
        for model in models:
            describe(model)
        return 0
    if args.folder is not None and not args.folder.is_dir():
        raise SystemExit(f"get-models: {args.folder} is not a folder")
    args.dest.mkdir(parents=True, exist_ok=True)
    failed = []
    for model in models:
        print(f"{model.name}: {model.origin}; terms: {model.terms}", flush=True)
        try:
            if args.folder is not None:
                link_from(model, args.folder, args.dest)
            else:
                with tempfile.TemporaryDirectory(dir=args.dest, prefix=".download-") as work:
                    download(model, args.dest, pathlib.Path(work))
            print(f"  ok: {model.triangles:,} triangles, {model.vertices:,} vertices, box as "
                  "expected", flush=True)
        except ModelError as error:
            print(f"  FAILED: {error}", flush=True)
            failed.append(model.name)
    print(f"get-models: {len(models) - len(failed)} of {len(models)} models ready in "
          f"{args.dest}" + (f"; failed: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
