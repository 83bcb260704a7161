#!/usr/bin/env python3
"""Hostile and awkward inputs, end to end (session 8, brief ROB8).

Generates malformed files (every reader) and awkward-but-valid acquisitions from the real contour
files in /work/shared/data/contours and from simulated slices (`heartmesh simulate`), runs
`heartmesh reconstruct X -o out.obj --report r.json` on each with a time limit, and prints one row
per case with what went wrong, if anything:

  PANIC    exit 101 or a Rust panic message
  HANG     the time limit was hit
  EXIT     an exit status other than 0 or 2
  VAGUE    exit 2 but the message is not one line naming the file
  MESH     exit 0 but the mesh is not closed, manifold and outward
  C2M      exit 0 but the contour-to-mesh mean is above the case's bound
  SELFX    exit 0 but triangles of the mesh pass through each other
  EXPECT   an error where a mesh was expected, or a mesh where an error was expected

Standard library only, seeded (same seed -> same files). Usage:
  scripts/hostile.py [OUT_DIR] [--seed S] [--only SUBSTRING] [--timeout SECONDS]
                     [--args "EXTRA CLI FLAGS"]   (added to every reconstruct, e.g. "--end-caps auto")
"""

import json
import math
import os
import random
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("HEARTMESH", os.path.join(ROOT, "wasm-core/target/release/heartmesh"))
DATA = os.environ.get("HEARTMESH_DATA", "/work/shared/data")
CONTOURS = os.path.join(DATA, "contours")
MESHES = os.path.join(DATA, "meshes")


# ---------------------------------------------------------------------------------------------
# Canonical CSV in and out


def read_csv(path):
    """[(id, surface, [(x, y, z)])] in file order, one entry per consecutive block."""
    blocks = []
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        has_surface = len(header) > 4
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cols = line.split(",")
            cid, x, y, z = cols[0], float(cols[1]), float(cols[2]), float(cols[3])
            surf = cols[4] if has_surface and len(cols) > 4 else None
            if blocks and blocks[-1][0] == cid and blocks[-1][1] == surf:
                blocks[-1][2].append((x, y, z))
            else:
                blocks.append((cid, surf, [(x, y, z)]))
    return blocks


def write_csv(blocks, sep=",", eol="\n", fmt="{:.5f}"):
    with_surface = any(b[1] for b in blocks)
    head = ["contour", "x", "y", "z"] + (["surface"] if with_surface else [])
    out = [sep.join(head)]
    for cid, surf, pts in blocks:
        for p in pts:
            row = [cid] + [fmt.format(v) for v in p]
            if with_surface:
                row.append(surf or "")
            out.append(sep.join(row))
    return (eol.join(out) + eol).encode()


def surface(blocks, name):
    return [b for b in blocks if b[1] == name]


def is_sax(cid):
    return "SAX" in cid.upper()


# ---------------------------------------------------------------------------------------------
# Geometry helpers (no numpy)


def centroid(pts):
    n = len(pts)
    return tuple(sum(p[i] for p in pts) / n for i in range(3))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def norm(a):
    return math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def rotate(p, axis, angle):
    """Rodrigues rotation of p about the unit axis."""
    c, s = math.cos(angle), math.sin(angle)
    return add(add(scale(p, c), scale(cross(axis, p), s)), scale(axis, dot(axis, p) * (1 - c)))


def normal_of(pts):
    """Newell normal of a ring (unit)."""
    n = [0.0, 0.0, 0.0]
    for i, p in enumerate(pts):
        q = pts[(i + 1) % len(pts)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    length = norm(n) or 1.0
    return (n[0] / length, n[1] / length, n[2] / length)


def resample(pts, spacing, closed=True):
    """Points every `spacing` mm along the polyline (linear)."""
    ring = pts + [pts[0]] if closed else list(pts)
    out = [ring[0]]
    carry = 0.0
    for a, b in zip(ring, ring[1:]):
        seg = norm(sub(b, a))
        t = spacing - carry
        while t <= seg:
            out.append(add(a, scale(sub(b, a), t / seg)))
            t += spacing
        carry = seg - (t - spacing)
    if closed and len(out) > 1 and norm(sub(out[-1], out[0])) < spacing * 0.5:
        out.pop()
    return out


def tilt(pts, degrees, rng):
    """Rotate a contour about an in-plane axis through its centroid."""
    c = centroid(pts)
    n = normal_of(pts)
    helper = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = cross(n, helper)
    u = scale(u, 1 / norm(u))
    v = cross(n, u)
    phi = rng.uniform(0, 2 * math.pi)
    axis = add(scale(u, math.cos(phi)), scale(v, math.sin(phi)))
    return [add(c, rotate(sub(p, c), axis, math.radians(degrees))) for p in pts]


# ---------------------------------------------------------------------------------------------
# Cases


class Case:
    def __init__(self, name, data, ext="csv", args=(), expect="error", c2m=3.0, extra=None,
                 open_mesh=False):
        self.name = name
        self.data = data  # bytes
        self.ext = ext
        self.args = list(args)
        self.expect = expect  # "ok", "error" or "any"
        self.c2m = c2m  # bound on the contour-to-mesh mean (mm) when a mesh is made
        self.extra = extra or {}  # other files to write beside it: name -> bytes
        self.open_mesh = open_mesh  # --lids none: manifold and oriented, but not closed


def run(cmd, timeout=600):
    return subprocess.run(cmd, capture_output=True, timeout=timeout)


def simulate(out_dir, name, truth, args, seed):
    path = os.path.join(out_dir, "sim-" + name + ".csv")
    if not os.path.exists(path):
        r = run([BIN, "simulate", truth, "-o", path, "--seed", str(seed), "--quiet"] + args)
        if r.returncode != 0:
            raise RuntimeError("simulate failed: " + r.stderr.decode(errors="replace"))
    return path


def malformed(p1, surfco, rng):
    """Cases that must fail with exit 2 and one clear line (or, where noted, still work)."""
    lines = surfco.decode().splitlines(keepends=True)
    body = lines[1:]
    cases = []

    def with_row(i, row, expect="error", note=""):
        new = lines[:1 + i] + [row + "\n"] + lines[1 + i + 1:]
        cases.append(Case("row-" + note, "".join(new).encode(), expect=expect))

    mid = len(body) // 2
    with_row(mid, "c3,-30.1,-20.2", note="missing-column")
    with_row(mid, "c3,-30.1,abc,35.0", note="text-in-number")
    with_row(mid, "c3,-30.1,nan,35.0", expect="any", note="nan")
    with_row(mid, "c3,-30.1,inf,35.0", expect="any", note="inf")
    with_row(mid, "c3,-30.1,1e400,35.0", expect="any", note="overflow")
    with_row(mid, "c3,-30.1,-20.2,35.0,extra,more", expect="any", note="extra-columns")
    with_row(mid, ",-30.1,-20.2,35.0", expect="any", note="empty-id")
    with_row(mid, "c3,,,", note="empty-fields")
    with_row(mid, "c3;-30.1;-20.2;35.0", note="mixed-separator")
    with_row(mid, "c3,1.2.3,-20.2,35.0", note="two-dots")
    with_row(mid, "c3,0x1A,-20.2,35.0", note="hex")
    cut = len(surfco) // 2
    cut = surfco.index(b",", cut) + 4
    cases.append(Case("truncated-row", surfco[:cut], expect="any"))
    cases.append(Case("truncated-mid-number", surfco[:cut - 2] + b",", expect="error"))
    cases.append(Case("empty-file", b""))
    cases.append(Case("header-only", b"contour,x,y,z\n"))
    cases.append(Case("header-only-crlf-bom", b"\xef\xbb\xbfcontour,x,y,z\r\n"))
    cases.append(Case("bom", b"\xef\xbb\xbf" + surfco, expect="ok"))
    cases.append(Case("crlf", surfco.replace(b"\n", b"\r\n"), expect="ok"))
    cases.append(Case("cr-only", surfco.replace(b"\n", b"\r"), expect="any"))
    cases.append(Case("utf16", b"\xff\xfe" + surfco.decode().encode("utf-16-le"), expect="ok"))
    cases.append(Case("binary-garbage", bytes(rng.randrange(256) for _ in range(4096))))
    cases.append(Case("long-line", surfco + b"c9," + b"1" * 5_000_000 + b",2,3\n", expect="error"))
    cases.append(Case("long-comment", b"#" + b"x" * 5_000_000 + b"\n" + surfco, expect="ok"))
    cases.append(Case("nul-bytes", surfco[:200] + b"\x00" * 50 + surfco[200:], expect="error"))
    cases.append(Case("semicolon", surfco.replace(b",", b";"), expect="ok"))
    cases.append(Case("tab", surfco.replace(b",", b"\t"), expect="ok"))
    cases.append(Case("decimal-comma", surfco.replace(b",", b";").replace(b".", b","), expect="any"))
    # A heart in centimetres (warns, still works) and in metres (refused: says which units).

    # Degenerate contours, alone and next to good ones.
    good = read_csv_bytes(surfco)
    ring = good[0][2]
    c = centroid(ring)
    degenerate = {
        "single-point": [ring[0]],
        "two-points": ring[:2],
        "identical-points": [ring[0]] * 30,
        "collinear": [add(c, (t, 0.0, 0.0)) for t in range(-20, 21)],
    }
    for name, pts in degenerate.items():
        cases.append(Case("only-" + name, write_csv([("c1", None, pts)])))
        cases.append(Case("plus-" + name, write_csv(good + [("bad", None, pts)]), expect="any"))
    cases.append(Case("one-contour", write_csv(good[:1])))
    far = [("far", None, [(1e308, 1e308, 1e308), (-1e308, -1e308, -1e308), (1e308, -1e308, 0)])]
    cases.append(Case("overflowing-span", write_csv(good + far, fmt="{:.6g}")))
    # A contour column holding a point index: every row its own contour.
    per_point = [(f"p{i}", None, [p]) for i, p in enumerate(q for b in good for q in b[2])]
    cases.append(Case("id-per-point", write_csv(per_point)))
    many = [(f"c{k}", None, [(20 * math.cos(k + 2.1 * i), 20 * math.sin(k + 2.1 * i), k * 1e-3)
                             for i in range(3)]) for k in range(100_000)]
    cases.append(Case("100k-tiny-contours", write_csv(many, fmt="{:.4f}")))
    cases.append(Case("two-sax", write_csv(good[:2]), expect="any"))

    # Duplicate ids in separate blocks (the second block is another curve with the same name).
    dup = [(b[0] if i != 3 else good[0][0], b[1], b[2]) for i, b in enumerate(good)]
    cases.append(Case("duplicate-id-blocks", write_csv(dup), expect="any"))

    # 10^6 points: one contour of the real file resampled very densely, and many points overall.
    perimeter = sum(norm(sub(pts[(i + 1) % len(pts)], p)) for _, _, pts in good
                    for i, p in enumerate(pts))
    step = perimeter / 1_000_000
    dense = [(cid, s, resample(pts, step)) for cid, s, pts in good]
    cases.append(Case("million-points", write_csv(dense, fmt="{:.4f}"), expect="any", c2m=1.5))

    # Patient 1: only LAX, only one SAX, one SAX plus LAX.
    lv = surface(p1, "LV_ENDO")
    lax = [b for b in lv if not is_sax(b[0])]
    sax = [b for b in lv if is_sax(b[0])]
    cases.append(Case("only-lax", write_csv(lax)))
    cases.append(Case("only-one-sax", write_csv(sax[len(sax) // 2:len(sax) // 2 + 1])))
    cases.append(Case("one-sax-plus-lax", write_csv(sax[:1] + lax), expect="any"))
    cases.append(Case("no-surface-choice", write_csv(p1), args=[]))
    cases.append(Case("unknown-surface", write_csv(p1), args=["--surface", "LA"]))
    return cases


def read_csv_bytes(data):
    tmp = "/tmp/hostile-parse.csv"
    with open(tmp, "wb") as f:
        f.write(data)
    return read_csv(tmp)


def corruptions(name, data, ext, rng, count, extra=None, args=()):
    """Seeded truncations and byte corruptions of a real file of another format."""
    cases = [Case(name + "-intact", data, ext=ext, expect="ok", extra=extra, args=args)]
    for k in range(count):
        cut = rng.randrange(len(data))
        cases.append(Case(f"{name}-trunc{k}@{cut}", data[:cut], ext=ext, expect="any",
                          extra=extra, args=args))
    for k in range(count):
        b = bytearray(data)
        for _ in range(rng.randrange(1, 8)):
            b[rng.randrange(len(b))] = rng.randrange(256)
        cases.append(Case(f"{name}-corrupt{k}", bytes(b), ext=ext, expect="any", extra=extra,
                          args=args))
    return cases


def other_readers(out_dir, rng):
    p1dir = os.path.join(CONTOURS, "bivme-example-patient1")
    with open(os.path.join(p1dir, "GPFile_000.txt"), "rb") as f:
        gp = f.read()
    with open(os.path.join(p1dir, "SliceInfoFile.txt"), "rb") as f:
        si = f.read()
    with open(os.path.join(CONTOURS, "surfco-example.mat"), "rb") as f:
        mat = f.read()
    cases = []
    cases += corruptions("gpfile", gp, "txt", rng, 4, extra={"SliceInfoFile.txt": si},
                         args=["--surface", "LV_ENDO"])
    cases += corruptions("sliceinfo", si, "txt", rng, 3, args=["--surface", "LV_ENDO"])
    # The GPFile case is the one named GPFile_*.txt; swap roles for the SliceInfo corruptions.
    for c in cases[-7:]:
        c.extra = {"SliceInfoFile.txt": c.data}
        c.data = gp
    # A newer biv-me's types (session 20): valve phantoms, apex points per wall, extents, atria,
    # the outflow tract and removed points, no header, a phantom point first: read, reconstructed.
    rows = gp.decode().splitlines()[1:]
    newer = []
    for row in rows:
        f = row.split("\t")
        if len(f) > 3 and f[3] == "MITRAL_VALVE":
            newer.append("\t".join(f[:3] + ["MITRAL_PHANTOM"] + f[4:]))
        if len(f) > 3 and f[3] == "APEX_POINT":
            row = "\t".join(f[:3] + ["APEX_ENDO_POINT"] + f[4:])
            newer.append("\t".join(f[:3] + ["APEX_EPI_POINT"] + f[4:]))
        if len(f) > 3 and f[3] == "LAX_LV_EPICARDIAL" and rng.random() < 0.3:
            newer.append("\t".join(f[:3] + [rng.choice(["LAX_LA", "LAX_RA", "REMOVED"])] + f[4:]))
        newer.append(row)
    newer.sort(key=lambda r: "PHANTOM" not in r)  # a phantom point is the file's first row
    cases.append(Case("gpfile-newer-bivme-types", ("\n".join(newer) + "\n").encode(), "txt",
                      args=["--surface", "LV_ENDO", "--lids", "apex"], expect="ok", c2m=1.0))
    cases += corruptions("mat", mat, "mat", rng, 5)
    # Segment studies (session 40): the core's fixture as saved (compressed, with its image), and
    # the fuzz seed stored uncompressed, so that corruptions reach the struct of stacks too.
    with open(os.path.join(ROOT, "wasm-core/crates/heartmesh-core/tests/data/segment-patient1/patient1.mat"), "rb") as f:
        seg = f.read()
    with open(os.path.join(ROOT, "wasm-core/fuzz/corpus/mat/segment-plain.mat"), "rb") as f:
        seg_plain = f.read()
    cases += corruptions("segment", seg, "mat", rng, 4, args=["--surface", "LV_ENDO"])
    cases += corruptions("segment-plain", seg_plain, "mat", rng, 12, args=["--surface", "LV_ENDO"])
    cases += label_maps(rng)
    cases += label_map_views(out_dir, rng)
    cases += nrrd_maps(out_dir, rng)
    src = os.path.join(CONTOURS, "surfco-example.csv")
    for ext in ("vtk", "vtp", "json", "dcm"):
        path = os.path.join(out_dir, "surfco." + ext)
        if not os.path.exists(path):
            r = run([BIN, "convert", src, path])
            if r.returncode != 0:
                print(f"convert to {ext} failed: {r.stderr.decode(errors='replace')}")
                continue
        with open(path, "rb") as f:
            cases += corruptions(ext, f.read(), ext, rng, 5)
    return cases


def label_maps(rng):
    """NIfTI label maps (session 21): the bundled segmentation gzip-compressed and plain, cut and
    corrupted, and headers that lie (sizes, offsets, types, magic, placement)."""
    import gzip
    import struct
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(os.path.join(root, "public", "samples", "cardiomesh-spasm-seg.nii.gz"), "rb") as f:
        gz = f.read()
    raw = gzip.decompress(gz)
    lv = ["--surface", "LV_ENDO"]
    cases = corruptions("nifti-gz", gz, "nii.gz", rng, 4, args=lv)
    cases += corruptions("nifti", raw, "nii", rng, 4, args=lv)

    def patched(name, edits, expect="error", args=lv):
        b = bytearray(raw)
        for at, fmt, value in edits:
            struct.pack_into(fmt, b, at, *value)
        cases.append(Case("nifti-" + name, bytes(b), "nii", args=args, expect=expect))

    patched("dims-huge", [(42, "<3h", (32767, 32767, 32767))])
    patched("dims-zero", [(42, "<h", (0,))])
    patched("rank-9", [(40, "<h", (9,))])
    patched("offset-past-end", [(108, "<f", (1e9,))])
    patched("offset-nan", [(108, "<f", (float("nan"),))])
    patched("type-complex", [(70, "<hh", (32, 64))])
    patched("type-float-image", [(70, "<hh", (16, 32))])
    patched("nifti2-magic", [(0, "<i", (540,)), (4, "<4s", (b"n+2\0",))])
    patched("hdr-pair", [(344, "<4s", (b"ni1\0",))])
    patched("sform-flat", [(280, "<12f", (1.0,) * 12)])
    patched("sform-nan", [(280, "<f", (float("nan"),))])
    patched("scale-half", [(112, "<ff", (0.5, 0.0))])
    patched("scale-int", [(112, "<ff", (2.0, 0.0))], expect="ok")
    patched("metres", [(123, "<B", (1,))])  # an sform in mm read as metres: refused
    patched("no-sform-no-qform", [(252, "<hh", (0, 0))], expect="ok")
    patched("frame-missing", [], args=lv + ["--frame", "3"])
    patched("all-background", [], expect="error")
    cases[-1].data = raw[:352] + bytes(len(raw) - 352)
    cases.append(Case("nifti-header-only", raw[:348], "nii", args=lv))
    return cases


def label_map_views(out_dir, rng):
    """A segmented study with long-axis views (session 22): the spasm stack with three views
    (`segment --lax 3`); views cut, corrupted, from another patient, lying in their headers, a
    second stack. Views are passed as further inputs (`@extra:NAME`, written beside the stack)."""
    import gzip
    import struct
    seg = os.path.join(out_dir, "views", "seg.nii.gz")
    if not os.path.exists(seg):
        os.makedirs(os.path.dirname(seg), exist_ok=True)
        r = run([BIN, "segment", "--lv-endo", os.path.join(MESHES, "cardiomesh-spasm-LV_endo.obj"),
                 "--lv-epi", os.path.join(MESHES, "cardiomesh-spasm-LV_epi.obj"),
                 "--rv-free-wall", os.path.join(MESHES, "cardiomesh-spasm-RV_endo.obj"),
                 "-o", seg, "--lax", "3", "--quiet"])
        if r.returncode != 0:
            raise RuntimeError("segment failed: " + r.stderr.decode(errors="replace"))
    def read(name):
        with open(os.path.join(os.path.dirname(seg), name), "rb") as f:
            return f.read()
    stack = read("seg.nii.gz")
    views = {f"seg_lax{n}.nii.gz": read(f"seg_lax{n}.nii.gz") for n in (1, 2, 3)}
    lv = ["--surface", "LV_EPI"]
    every = [f"@extra:{n}" for n in views]
    cases = [Case("views-intact", stack, "nii.gz", args=lv + every, expect="ok", c2m=1.0,
                  extra=views)]
    one = gzip.decompress(views["seg_lax2.nii.gz"])

    def with_view(name, data, expect="any", more=()):
        extra = dict(views)
        extra["bad_lax.nii"] = data
        cases.append(Case("views-" + name, stack, "nii.gz", extra=extra, expect=expect,
                          args=lv + every[:2] + ["@extra:bad_lax.nii"] + list(more)))

    for k in range(4):
        cut = rng.randrange(len(one))
        with_view(f"trunc{k}@{cut}", one[:cut])
    for k in range(4):
        b = bytearray(one)
        for _ in range(rng.randrange(1, 8)):
            b[rng.randrange(len(b))] = rng.randrange(256)
        with_view(f"corrupt{k}", bytes(b))

    def patched(edits):
        b = bytearray(one)
        for at, fmt, value in edits:
            struct.pack_into(fmt, b, at, *value)
        return bytes(b)

    # Another patient's view (its sform 400 mm away): read, said unused, the stack alone meshed.
    with_view("elsewhere", patched([(292, "<f", (400.0,))]), expect="ok")
    with_view("dims-huge", patched([(42, "<3h", (32767, 32767, 1))]), expect="error")
    with_view("rank-4-frames", patched([(40, "<h", (4,)), (48, "<h", (30,))]), expect="error")
    with_view("second-stack", gzip.decompress(stack), expect="error")
    with_view("frame-of-stack-missing", one, expect="ok", more=["--frame", "0"])
    return cases


def nrrd_maps(out_dir, rng):
    """3D Slicer segmentations (`.seg.nrrd`, session 22): the spasm map as `segment` writes it,
    gzip-encoded and raw, cut and corrupted, and headers that lie or name what is not read."""
    import gzip
    seg = os.path.join(out_dir, "nrrd", "seg.seg.nrrd")
    if not os.path.exists(seg):
        os.makedirs(os.path.dirname(seg), exist_ok=True)
        r = run([BIN, "segment", "--lv-endo", os.path.join(MESHES, "cardiomesh-spasm-LV_endo.obj"),
                 "--lv-epi", os.path.join(MESHES, "cardiomesh-spasm-LV_epi.obj"), "-o", seg,
                 "--quiet"])
        if r.returncode != 0:
            raise RuntimeError("segment failed: " + r.stderr.decode(errors="replace"))
    with open(seg, "rb") as f:
        gz = f.read()
    cut = gz.index(b"\n\n") + 2
    head, body = gz[:cut].decode(), gz[cut:]
    raw = (head.replace("encoding: gzip", "encoding: raw")).encode() + gzip.decompress(body)
    lv = ["--surface", "LV_EPI"]
    cases = corruptions("nrrd-gzip", gz, "nrrd", rng, 4, args=lv)
    cases += corruptions("nrrd-raw", raw, "nrrd", rng, 4, args=lv)

    def edited(name, old, new, data=None, expect="error"):
        h = head.replace(old, new)
        cases.append(Case("nrrd-" + name, h.encode() + (body if data is None else data), "nrrd",
                          args=lv, expect=expect))

    edited("sizes-huge", "sizes: ", "sizes: 99999 99999 ")
    edited("sizes-zero", "sizes: ", "sizes: 0 ")
    edited("dimension-7", "dimension: 3", "dimension: 7")
    edited("type-block", "type: uint8", "type: block")
    edited("type-float", "type: uint8", "type: float")
    edited("encoding-bzip2", "encoding: gzip", "encoding: bzip2")
    edited("encoding-hex", "encoding: gzip", "encoding: hex")
    edited("detached", "encoding: gzip", "encoding: gzip\ndata file: seg.raw.gz", data=b"")
    edited("directions-flat", "space directions: (", "space directions: (0,0,0) (")
    edited("directions-nan", "space directions: (", "space directions: (nan,")
    edited("origin-garbage", "space origin: (", "space origin: (x")
    edited("byte-skip-past", "encoding: gzip", "encoding: gzip\nbyte skip: 99999999")
    edited("byte-skip-minus-one", "encoding: gzip", "encoding: gzip\nbyte skip: -1", expect="ok")
    edited("no-space", "space: left-posterior-superior\n", "", expect="ok")
    edited("not-gzip", "encoding: gzip", "encoding: gzip", data=gzip.decompress(body))
    cases.append(Case("nrrd-header-only", head.encode(), "nrrd", args=lv))
    cases.append(Case("nrrd-no-blank-line", head.rstrip("\n").encode(), "nrrd", args=lv))
    return cases


def awkward(out_dir, p1, surfco, rng, seed):
    """Valid but awkward acquisitions: they must reconstruct (closed, manifold, outward) with a
    sane contour-to-mesh mean, or fail with a typed error that says why."""
    truth = os.path.join(MESHES, "bivme-patient1-ED-LV_ENDO-closed.obj")
    cases = []

    def sim(name, args, c2m=2.5, expect="ok", transform=None):
        path = simulate(out_dir, name, truth, args, seed)
        blocks = read_csv(path)
        if transform:
            blocks = transform(blocks)
        cases.append(Case("sim-" + name, write_csv(blocks), expect=expect, c2m=c2m))
        return blocks

    base = sim("default", [])
    sim("misalign-5-5", ["--misalign", "5,5"], c2m=3.0)
    sim("noise-1", ["--noise", "1"], c2m=2.5)
    sim("noise-2", ["--noise", "2"], c2m=3.5)
    for n in (4, 5, 6):
        sim(f"sax{n}", ["--sax", str(n)])
    sim("no-lax", ["--lax", "0"])
    sim("one-lax", ["--lax", "1"])
    sim("eight-lax", ["--lax", "8"])

    def shuffled(blocks):
        b = list(blocks)
        rng.shuffle(b)
        return b

    def reversed_random_start(blocks):
        out = []
        for cid, s, pts in blocks:
            k = rng.randrange(len(pts))
            pts = pts[k:] + pts[:k]
            if rng.random() < 0.5:
                pts = pts[::-1]
            out.append((cid, s, pts))
        return out

    def spacing(mm):
        return lambda blocks: [(cid, s, resample(pts, mm)) for cid, s, pts in blocks]

    def affine(offset, factor):
        return lambda blocks: [(cid, s, [add(scale(p, factor), offset) for p in pts])
                               for cid, s, pts in blocks]

    def stray(blocks):
        cid, s, pts = blocks[0]
        return blocks + [("stray", s, [add(p, (200.0, 0.0, 0.0)) for p in pts])]

    def twin(blocks):
        return blocks + [(blocks[1][0] + "_copy", blocks[1][1], list(blocks[1][2]))]

    def figure_eight(blocks):
        out = list(blocks)
        i = 2
        cid, s, pts = out[i]
        h = len(pts) // 2
        out[i] = (cid, s, pts[:h] + pts[h:][::-1])
        return out

    def tilted(deg_lo, deg_hi, every=2):
        def t(blocks):
            out = []
            for j, (cid, s, pts) in enumerate(blocks):
                if is_sax(cid) and j % every == 1:
                    pts = tilt(pts, rng.uniform(deg_lo, deg_hi), rng)
                out.append((cid, s, pts))
            return out
        return t

    sim("metres", [], expect="error", transform=affine((0, 0, 0), 0.001))
    sim("micrometres", [], expect="error", transform=affine((0, 0, 0), 1000.0))
    for name, tr, bound in [
        ("shuffled", shuffled, 2.5),
        ("reversed-random-start", reversed_random_start, 2.5),
        ("dense-0.05", spacing(0.05), 2.5),
        ("sparse-8", spacing(8.0), 3.0),
        ("offset-1e5", affine((1e5, -1e5, 1e5), 1.0), 2.5),
        ("centimetres", affine((0, 0, 0), 0.1), 0.25),
        ("stray-200mm", stray, 3.0),
        ("twin-contour", twin, 2.5),
        ("figure-eight", figure_eight, 3.5),
        ("tilt-15-19", tilted(15, 19), 3.5),
    ]:
        sim(name, [], c2m=bound, transform=tr)

    # Uneven gaps 5-20 mm: a dense stack, keep slices with random gaps.
    def uneven(blocks):
        sax = [b for b in blocks if is_sax(b[0])]
        lax = [b for b in blocks if not is_sax(b[0])]
        keep, i = [], 0
        while i < len(sax):
            keep.append(sax[i])
            i += rng.choice([1, 2, 3, 4])
        return keep + lax

    sim("uneven-gaps", ["--sax-spacing", "5"], c2m=3.0, transform=uneven)

    # Real files with the same awkward treatments.
    lv = surface(p1, "LV_ENDO")
    cases.append(Case("p1-lv-endo", write_csv(lv), expect="ok", c2m=2.5))
    cases.append(Case("p1-shuffled", write_csv(shuffled(lv)), expect="ok", c2m=2.5))
    cases.append(Case("p1-reversed-random-start", write_csv(reversed_random_start(lv)), expect="ok", c2m=2.5))
    cases.append(Case("p1-metres", write_csv(affine((0, 0, 0), 0.001)(lv), fmt="{:.8f}"),
                      expect="error"))
    cases.append(Case("p1-offset-1e5", write_csv(affine((1e5, 1e5, 1e5), 1.0)(lv)), expect="ok", c2m=2.5))
    good = read_csv_bytes(surfco)
    cases.append(Case("surfco-sparse-8", write_csv(spacing(8.0)(good)), expect="ok", c2m=3.0))
    cases.append(Case("surfco-shuffled", write_csv(shuffled(good)), expect="ok", c2m=2.5))
    return cases


def other_tools(out_dir, p1, surfco, rng, seed):
    """Session 16: files as other tools write them (encodings, line ends, header spellings,
    index, slice and frame columns, GPFile variants) and awkward geometry the first round did not
    try (dense stacks, 3 and 30 slices, a mouse heart, pieces, open arcs, RV septum only)."""
    text = surfco.decode()
    lines = text.splitlines()
    cases = []

    def rows(head, f):
        return (head + "\n" + "\n".join(f(l) for l in lines[1:] if l) + "\n").encode()

    tabbed = text.replace(",", "\t").replace("\n", "\r\n")
    cases.append(Case("utf16le-bom-tabs", b"\xff\xfe" + tabbed.encode("utf-16-le"), expect="ok"))
    cases.append(Case("utf16be-bom", b"\xfe\xff" + tabbed.encode("utf-16-be"), expect="ok"))
    cases.append(Case("utf16le-no-bom", tabbed.encode("utf-16-le"), expect="ok"))
    cases.append(Case("utf16-unpaired-surrogate",
                      b"\xff\xfe" + "contour,x\n".encode("utf-16-le") + b"\x00\xd8"))
    cases.append(Case("windows-1252-id", rows(lines[0], lambda l: "r\u00e9gion " + l)
                      .decode().encode("cp1252"), expect="ok"))
    cases.append(Case("cr-only-strict", surfco.replace(b"\n", b"\r"), expect="ok"))
    cases.append(Case("mixed-crlf-lf", b"".join(
        l + (b"\r\n" if i % 2 else b"\n") for i, l in enumerate(surfco.split(b"\n"))), expect="ok"))
    cases.append(Case("trailing-separator", rows("contour,x,y,z,", lambda l: l + ","), expect="ok"))
    cases.append(Case("quoted-fields", rows('"contour","x","y","z"', lambda l: ",".join(
        '"%s"' % f for f in l.split(","))), expect="ok"))
    cases.append(Case("decimal-comma-comma-sep", rows(lines[0], lambda l: l.replace(".", ","))))
    for name, head in [("units-paren", "contour,x (mm),y (mm),z (mm)"),
                       ("units-bracket", "Contour,X[mm],Y[mm],Z[mm]"),
                       ("units-suffix", "CONTOUR,X_mm,Y_mm,Z_mm"),
                       ("paraview-points", "contour,Points:0,Points:1,Points:2"),
                       ("slice-column", "slice,x,y,z"),
                       ("reordered-upper", None)]:
        if head is None:
            data = rows("Z,Y,X,Contour", lambda l: ",".join(l.split(",")[::-1]))
        else:
            data = (head + "\n" + "\n".join(lines[1:]) + "\n").encode()
        cases.append(Case(name, data, expect="ok"))
    cases.append(Case("units-pixels", ("contour,x [px],y [px],z [px]\n" + "\n".join(lines[1:]))
                      .encode()))
    cases.append(Case("pandas-index", rows("," + lines[0], lambda l: "0," + l), expect="ok"))
    # Session 19: no header line (name,x,y,z read with a warning); four numbers still need one.
    cases.append(Case("no-header", ("\n".join(lines[1:]) + "\n").encode(), expect="ok"))
    cases.append(Case("no-header-four-numbers", ("\n".join(
        "%d,%s" % (i, ",".join(l.split(",")[1:])) for i, l in enumerate(lines[1:]) if l) + "\n").encode()))
    cases.append(Case("numbers-plus-dot-exp", rows(lines[0], lambda l: ",".join(
        [l.split(",")[0]] + ["%+.6e" % float(v) for v in l.split(",")[1:]])), expect="ok"))
    cases.append(Case("thousands-separator", surfco.replace(b"35.00000", b'"1,035.0"', 1)))
    cases.append(Case("unicode-minus", surfco.replace(b",-", ",\u2212".encode()), expect="ok"))
    # Closed contours as VTK POLYGONS (how DICOM-RT converters store CLOSED_PLANAR), no LINES;
    # and a triangle mesh given as contours.
    rings = [pts for cid, _, pts in read_csv_bytes(surfco) if len(pts) > 50 and
             norm(sub(pts[0], pts[-1])) < 2.0]
    flat = [p for r in rings for p in r]
    head = "# vtk DataFile Version 3.0\nrings\nASCII\nDATASET POLYDATA\nPOINTS %d float\n" % len(flat)
    body = "\n".join("%.5f %.5f %.5f" % p for p in flat)
    cells, k = [], 0
    for r in rings:
        cells.append(" ".join(str(i) for i in [len(r)] + list(range(k, k + len(r)))))
        k += len(r)
    poly = head + body + "\nPOLYGONS %d %d\n" % (len(rings), k + len(rings)) + "\n".join(cells) + "\n"
    cases.append(Case("vtk-polygons-sax-only", poly.encode(), ext="vtk", expect="ok", c2m=3.0))
    tri = head.replace("POINTS %d" % len(flat), "POINTS 4") + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + \
        "POLYGONS 2 8\n3 0 1 2\n3 0 2 3\n"
    cases.append(Case("vtk-triangles-as-contours", tri.encode(), ext="vtk"))
    # Several frames in one CSV: frame 0 is the file, frame 1 the file 10 % larger.
    grow = "\n".join(",".join([l.split(",")[0]] + ["%.5f" % (1.1 * float(v)) for v in
                                                    l.split(",")[1:]]) + ",1"
                     for l in lines[1:] if l)
    two = ("contour,x,y,z,frame\n" + "\n".join(l + ",0" for l in lines[1:] if l) + "\n" +
           grow + "\n").encode()
    cases.append(Case("frame-column-two-frames", two, expect="ok", c2m=0.2))
    cases.append(Case("frame-column-frame-1", two, expect="ok", args=["--frame", "1"], c2m=0.2))
    cases.append(Case("frame-column-absent-frame", two, args=["--frame", "7"]))
    # Slices numbered per surface: ids 1..n again for every surface.
    numbered, seen = [], {}
    for cid, surf, pts in p1:
        seen[surf] = seen.get(surf, 0) + 1
        numbered.append((str(seen[surf]), surf, pts))
    cases.append(Case("ids-per-surface", write_csv(numbered), args=["--surface", "LV_EPI"],
                      expect="ok", c2m=2.5))

    # GPFile variants (named GPFile_000.txt by run_cases: "gpfile" prefix).
    p1dir = os.path.join(CONTOURS, "bivme-example-patient1")
    with open(os.path.join(p1dir, "GPFile_000.txt"), "rb") as f:
        gp = f.read()
    with open(os.path.join(p1dir, "SliceInfoFile.txt"), "rb") as f:
        si = f.read()
    with open(os.path.join(CONTOURS, "bivme-test-patient2", "SliceInfoFile.txt"), "rb") as f:
        si2 = f.read()
    lv = ["--surface", "LV_ENDO"]
    gpl = gp.decode().splitlines()
    again = "\n".join(gpl + ["\t".join(["%.5f" % (float(r.split("\t")[0]) + 3)] +
                                        r.split("\t")[1:6] + ["5"]) for r in gpl[1:]]) + "\n"
    for name, data, extra in [
        ("gpfile-commas", gp.replace(b"\t", b","), si),
        ("gpfile-spaces", gp.replace(b"\t", b" "), si),
        ("gpfile-cr-only", gp.replace(b"\n", b"\r"), si),
        ("gpfile-utf16", b"\xff\xfe" + gp.decode().encode("utf-16-le"), si),
        ("gpfile-two-frames", again.encode(), si),
        ("gpfile-other-sliceinfo", gp, si2),
        ("gpfile-sliceinfo-utf16", gp, b"\xff\xfe" + si.decode().encode("utf-16-le")),
    ]:
        cases.append(Case(name, data, ext="txt", args=lv, expect="ok",
                          extra={"SliceInfoFile.txt": extra}))

    # Geometry (simulated from the biv-me LV, or the real patient).
    truth = os.path.join(MESHES, "bivme-patient1-ED-LV_ENDO-closed.obj")
    cap = os.path.join(MESHES, "cap-atlas-mean-ED-LV_ENDO-open.obj")

    def sim(name, args, c2m=2.5, expect="ok", transform=None, mesh=truth):
        path = simulate(out_dir, name, mesh, args, seed)
        blocks = read_csv(path)
        if transform:
            blocks = transform(blocks)
        cases.append(Case("sim-" + name, write_csv(blocks, fmt="{:.6f}"), expect=expect, c2m=c2m))
        return blocks

    sim("cap-dense-1mm", ["--sax-spacing", "1"], mesh=cap)
    sim("cap-dense-2mm", ["--sax-spacing", "2"], mesh=cap)
    sim("three-slices", ["--sax", "3"])
    sim("three-slices-no-lax", ["--sax", "3", "--lax", "0"])
    sim("thirty-slices", ["--sax", "30"])
    sim("mouse-tenth", [], c2m=0.25,
        transform=lambda b: [(c, s, [scale(p, 0.1) for p in pts]) for c, s, pts in b])

    def arcs(share):
        return lambda b: [(c, s, pts[:int(len(pts) * share)] if is_sax(c) else pts)
                          for c, s, pts in b]

    sim("open-arcs-60pct", [], transform=arcs(0.6))
    sim("open-arcs-30pct", [], transform=arcs(0.3))

    def pieces(k):
        def t(blocks):
            out = []
            for c, s, pts in blocks:
                if not is_sax(c):
                    out.append((c, s, pts))
                    continue
                step = len(pts) // k
                for j in range(k):  # same id, a gap of 6 spacings (a jump) between pieces
                    out.append((c, s, pts[j * step:(j + 1) * step - 6]))
            return out
        return t

    sim("slices-in-four-pieces", [], transform=pieces(4))
    cases.append(Case("rv-septum-only", write_csv([b for b in p1 if "SEPTUM" in b[0]]),
                      expect="any", c2m=3.0))
    many = [(f"c{k}", None, [(20 * math.cos(k + 2.1 * i), 20 * math.sin(k + 2.1 * i), k * 1e-2)
                             for i in range(3)]) for k in range(10_000)]
    cases.append(Case("10k-tiny-contours", write_csv(many, fmt="{:.4f}")))
    ring = [(30 * math.cos(i * 1e-3), 30 * math.sin(i * 1e-3), (i // 6283) * 1.0)
            for i in range(2_000_001)]
    cases.append(Case("2000001-points", write_csv([("c1", None, ring)], fmt="{:.3f}")))
    return cases


# ---------------------------------------------------------------------------------------------
# Running and judging


def judge(case, path, timeout, out_dir):
    mesh = os.path.join(out_dir, "out.obj")
    report = os.path.join(out_dir, "r.json")
    for f in (mesh, report):
        if os.path.exists(f):
            os.remove(f)
    t0 = time.time()
    try:
        # Further inputs written beside the case's file (long-axis views): `@extra:NAME`.
        args = [os.path.join(out_dir, a[7:]) if a.startswith("@extra:") else a for a in case.args]
        r = run([BIN, "reconstruct", path, "-o", mesh, "--report", report, "--quiet"] + args,
                timeout=timeout)
    except subprocess.TimeoutExpired:
        return ["HANG"], f"> {timeout} s", time.time() - t0
    dt = time.time() - t0
    err = r.stderr.decode(errors="replace").strip()
    problems = []
    detail = ""
    if r.returncode == 101 or "panicked" in err:
        problems.append("PANIC")
    elif r.returncode not in (0, 2):
        problems.append("EXIT")
    if r.returncode == 2:
        lines = [ln for ln in err.splitlines() if not ln.startswith("heartmesh: warning")]
        named = [os.path.basename(path)] + list(case.extra)
        if len(lines) != 1 or not any(n in lines[0] for n in named) and "--" not in lines[0]:
            problems.append("VAGUE")
        detail = lines[-1][:200] if lines else "(no message)"
        if case.expect == "ok":
            problems.append("EXPECT")
    if r.returncode == 0:
        try:
            with open(report) as f:
                rep = json.load(f)
            topo = {k: rep.get(k) for k in ("watertight", "manifold", "oriented")}
            if case.open_mesh:
                del topo["watertight"]
            closed = all(topo.values())
            vol = rep.get("volume_ml", 0) if not case.open_mesh else 1.0
            c2m = rep.get("contour_to_mesh", {}).get("mean")
            warns = rep.get("warnings", [])
            detail = f"c2m mean {c2m:.3g} mm, vol {vol:.4g}" if c2m is not None else "no c2m"
            if warns:
                detail += f"; {len(warns)} warning(s): " + " | ".join(warns)[:160]
            if not closed or not (vol and vol > 0):
                problems.append("MESH")
                detail += f"; topology {topo}"
            if c2m is None or not math.isfinite(c2m) or c2m > case.c2m:
                problems.append("C2M")
            crossing = rep.get("quality", {}).get("self_intersections", 0)
            if crossing:
                problems.append("SELFX")
                detail += f"; {crossing} self-intersecting triangle pairs"
        except (OSError, ValueError) as e:
            problems.append("MESH")
            detail = f"no report: {e}"
        if case.expect == "error":
            problems.append("EXPECT")
    return problems, detail, dt


def main():
    argv = sys.argv[1:]
    out_dir = "/tmp/hostile"
    seed, only, timeout, extra = 8, None, 120, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--seed":
            seed = int(argv[i + 1]); i += 2
        elif a == "--only":
            only = argv[i + 1]; i += 2
        elif a == "--timeout":
            timeout = float(argv[i + 1]); i += 2
        elif a == "--args":
            extra = argv[i + 1].split(); i += 2
        elif a.startswith("-"):
            return usage(a, __doc__)
        else:
            out_dir = a; i += 1
    os.makedirs(out_dir, exist_ok=True)
    rng = random.Random(seed)
    p1 = read_csv(os.path.join(CONTOURS, "bivme-example-patient1", "patient1-ED.csv"))
    with open(os.path.join(CONTOURS, "surfco-example.csv"), "rb") as f:
        surfco = f.read()
    cases = malformed(p1, surfco, rng) + other_readers(out_dir, rng) + \
        awkward(out_dir, p1, surfco, rng, seed) + other_tools(out_dir, p1, surfco, rng, seed)
    for c in cases:
        c.args = merge_args(c.args, extra)
    bad = run_cases(cases, out_dir, timeout, only)
    if only is None or "mesh-in" in only:
        bad += mesh_inputs(out_dir, rng, timeout)
    print(f"{bad} case(s) with problems")
    return 1 if bad else 0


def mesh_inputs(out_dir, rng, timeout, per_format=20):
    """Damaged mesh files (session 43: the readers now also look for a `SPACE=` frame in each
    header) given to `info`, `convert` and `compare`: truncated, bytes changed in the header or
    anywhere, frame tags dropped in at random places. One row per file, flagged as `judge` flags
    reconstructions (PANIC, HANG, EXIT, VAGUE; VAGUE also when a control character from the file
    reaches the message). Returns the number of bad files."""
    src = os.path.join(CONTOURS, "bivme-example-patient1", "GPFile_000.txt")
    bases = []
    for ext in ["obj", "ply", "vtk", "vtp", "stl"]:
        path = os.path.join(out_dir, f"mesh-in-base.{ext}")
        run([BIN, "reconstruct", src, "--surface", "LV_ENDO", "-o", path, "--quiet"], timeout)
        with open(path, "rb") as f:
            bases.append((ext, f.read()))
    tags = [b"SPACE=RAS", b"SPACE=", b"SPACE=\xff\xfe", b'Name="SPACE"><', b"\n# SPACE=LPS\n",
            b"comment SPACE=ras\n", b"\x0b\x00\x1b"]
    truth = os.path.join(out_dir, "mesh-in-base.obj")
    bad = 0
    for ext, data in bases:
        for k in range(per_format):
            d = bytearray(data)
            how = rng.randrange(4)
            if how == 0:
                d = d[:rng.randrange(len(d))]
            elif how == 1:
                for _ in range(rng.randrange(1, 20)):
                    d[rng.randrange(min(len(d), 400))] = rng.randrange(256)
            elif how == 2:
                i = rng.randrange(min(len(d), 300))
                d[i:i] = rng.choice(tags)
            else:
                for _ in range(5):
                    d[rng.randrange(len(d))] = rng.randrange(256)
            path = os.path.join(out_dir, f"mesh-in-{ext}-{k}.{ext}")
            with open(path, "wb") as f:
                f.write(d)
            problems, t0 = [], time.time()
            for cmd in (["info", path], ["convert", path, path + ".ply", "--quiet"],
                        ["compare", truth, path]):
                try:
                    r = run([BIN] + cmd, timeout)
                except subprocess.TimeoutExpired:
                    problems.append("HANG")
                    continue
                err = r.stderr.decode(errors="replace")
                if r.returncode == 101 or "panicked" in err:
                    problems.append("PANIC")
                elif r.returncode not in (0, 2):
                    problems.append("EXIT")
                elif r.returncode == 2 and (err.count("\n") != 1 or not err.endswith("\n")
                                            or any(ord(c) < 32 for c in err[:-1])):
                    problems.append("VAGUE")
            bad += bool(problems)
            flag = ",".join(sorted(set(problems))) if problems else "ok"
            name = f"mesh-in-{ext}-{k}-{['cut', 'header', 'tag', 'bytes'][how]}"
            print(f"{flag:12} {name:34} {time.time() - t0:6.1f}s", flush=True)
    return bad


def merge_args(args, extra):
    """`args` plus each option of `extra` ("--flag [values]") that `args` does not already set: a
    case's own choice wins, and an option's value never gets separated from its flag."""
    groups = []
    for a in extra:
        if a.startswith("--") or not groups:
            groups.append([a])
        else:
            groups[-1].append(a)
    return list(args) + [a for g in groups if g[0] not in args for a in g]


def usage(option, doc):
    """Exit status for an option no parser took: 0 after printing `doc` for -h/--help, else 2
    (an unknown option must not become the output directory)."""
    if option in ("-h", "--help"):
        print(doc)
        return 0
    print(f"unknown option {option}\n{doc}", file=sys.stderr)
    return 2


def run_cases(cases, out_dir, timeout, only=None, check=None):
    """Write, run and judge every case; one printed row each. `check(case, case_dir)` may return
    more (problems, detail) from the case's report and mesh. Returns the number of bad cases."""
    bad = 0
    for case in cases:
        if only and only not in case.name:
            continue
        cdir = os.path.join(out_dir, "cases", case.name.replace("@", "_"))
        os.makedirs(cdir, exist_ok=True)
        base = "GPFile_000.txt" if case.name.startswith(("gpfile", "sliceinfo")) else \
            "input." + case.ext
        path = os.path.join(cdir, base)
        with open(path, "wb") as f:
            f.write(case.data)
        for n, d in case.extra.items():
            with open(os.path.join(cdir, n), "wb") as f:
                f.write(d)
        problems, detail, dt = judge(case, path, timeout, cdir)
        if check and not any(p in problems for p in ("PANIC", "HANG", "EXIT")):
            more, more_detail = check(case, cdir)
            problems += more
            detail += more_detail
        bad += bool(problems)
        flag = ",".join(problems) if problems else "ok"
        print(f"{flag:12} {case.name:34} {dt:6.1f}s  {detail}", flush=True)
    return bad


if __name__ == "__main__":
    sys.exit(main())
