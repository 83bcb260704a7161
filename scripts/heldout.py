#!/usr/bin/env python3
"""Held-out acquisitions: slices our planner (`sim::planes`) never makes (session 13, EVAL13).

Every study of ours slices a truth with the same planner: short-axis (SAX) planes exactly
perpendicular to the anatomical axis every 10 mm, long-axis (LAX) planes exactly through the apex.
This script slices the truth meshes itself (standard library only) the way real acquisitions
differ: stacks tilted off the axis, other spacings and counts, a slice missing, stacks short of
the apex or past the base, a second loop beside the basal ring, a speck (a 3-point loop past the
base or between slices, session 14), LAX planes off the apex, one or
two LAX views, LAX from another breath-hold, LAX drawn only in part or closed across the valve
(as a traced mask gives the cavity; also with each view from its own breath-hold), point spacing 0.2-6 mm,
curves traced from a pixel mask (1.4 and 2 mm pixels, as segmentation networks give them),
winding, order, duplicates, far coordinates and hand-drawing noise. Each case runs through the
release CLI at defaults (`reconstruct --report`, then `compare` against the truth clipped at the
acquisition's own basal SAX plane and at the planner's), and the table gives mean (both ways,
mm), Hausdorff (mm), volume error (%), topology, folded edges and time. Outliers against the same
truth's planner case are flagged:

  FAIL    the CLI refused or crashed            MESH   not watertight / manifold
  FOLD    folded edges                          MEAN   mean > 2x the planner case + 0.3 mm
  MAX     Hausdorff > 2x the planner case + 2 mm
  SLOW    time > 5x the planner case

Usage:  scripts/heldout.py [OUT_DIR] [--seed S] [--seeds N] [--only SUBSTRING] [--truth NAME]
        [--args "EXTRA CLI FLAGS"]
The acquisition geometry (axis, basal plane, apex, LAX reference) comes from `heartmesh simulate`
at defaults, so "the true axis" is the planner's; everything else is sliced here.
"""

import json
import math
import os
import random
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile as H  # noqa: E402  (CSV reader/writer, vector helpers, the CLI path)

MESHES = H.MESHES

# (name, truth OBJ, OBJ whose long axis plans the planes or None, surface label)
TRUTHS = [
    ("cap-endo", "cap-atlas-mean-ED-LV_ENDO-open.obj", None, "LV_ENDO"),
    ("cap-epi", "cap-atlas-mean-ED-LV_EPI-open.obj", None, "LV_EPI"),
    ("spasm-endo", "cardiomesh-spasm-LV_endo.obj", None, "LV_ENDO"),
    ("spasm-epi", "cardiomesh-spasm-LV_epi.obj", None, "LV_EPI"),
    ("bivme-lv", "bivme-patient1-ED-LV_ENDO-closed.obj", None, "LV_ENDO"),
    ("bivme-rv", "bivme-patient1-ED-RV_ENDO-closed.obj", "bivme-patient1-ED-LV_ENDO-closed.obj",
     "RV_ENDO"),
    ("param", None, None, "LV_ENDO"),  # written by `parametric_obj`
]


# ---------------------------------------------------------------------------------------------
# Meshes


def read_obj(path):
    """Vertices welded (coincident copies merged, as `simulate` does) and fan-split faces."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(tuple(float(v) for v in line.split()[1:4]))
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) for t in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    index, welded, remap = {}, [], []
    for v in verts:
        key = tuple(round(x, 6) for x in v)
        if key not in index:
            index[key] = len(welded)
            welded.append(v)
        remap.append(index[key])
    faces = [tuple(remap[i] for i in f) for f in faces]
    faces = [f for f in faces if len(set(f)) == 3]
    return welded, faces


def parametric_obj(path, seed):
    """A truncated LV-like cavity (not one of our phantoms): an ellipsoid 24 x 20 mm across, 70 mm
    long, with a 3-lobed and a 2-lobed wobble of its sections, a curved axis and an open base,
    placed on an oblique axis."""
    rng = random.Random(seed)
    a2, a3 = rng.uniform(0.05, 0.12), rng.uniform(0.02, 0.06)
    p2, p3 = rng.uniform(0, 6), rng.uniform(0, 6)
    rings, per = 40, 64
    verts = [(0.0, 0.0, -70.0)]
    for i in range(1, rings + 1):
        t = i / rings * (math.pi / 2 + 0.25)  # to a little past the equator: the base widens
        z = -70.0 * math.cos(t)
        bend = 4.0 * (1 + z / 70.0) ** 2
        for j in range(per):
            th = 2 * math.pi * j / per
            w = 1 + a2 * math.cos(2 * th + p2) + a3 * math.cos(3 * th + p3)
            verts.append((24.0 * math.sin(t) * w * math.cos(th) + bend,
                          20.0 * math.sin(t) * w * math.sin(th), z))
    faces = [(0, 1 + (j + 1) % per, 1 + j) for j in range(per)]
    for i in range(rings - 1):
        for j in range(per):
            a, b = 1 + i * per + j, 1 + i * per + (j + 1) % per
            c, d = a + per, b + per
            faces += [(a, b, d), (a, d, c)]
    e1, e2, ax = (0.8, 0.6, 0.0), (-0.36, 0.48, 0.8), (0.48, -0.64, 0.6)
    with open(path, "w") as f:
        for x, y, z in verts:
            p = H.add(H.add(H.scale(e1, x), H.scale(e2, y)), H.scale(ax, z))
            f.write("v {:.6f} {:.6f} {:.6f}\n".format(p[0] + 20, p[1] - 40, p[2] + 100))
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


def slice_mesh(mesh, origin, normal, join_gap=3.0):
    """The plane's section of the mesh: [(points, closed)], pieces chained through shared edges;
    open pieces whose ends are within `join_gap` mm are joined (composite truths)."""
    verts, faces = mesh
    d = [H.dot(H.sub(v, origin), normal) for v in verts]
    d = [x if x != 0.0 else 1e-12 for x in d]  # a vertex on the plane counts as above it
    point = {}
    nxt = {}
    for f in faces:
        cut = []
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            if (d[a] > 0) != (d[b] > 0):
                key = (min(a, b), max(a, b))
                if key not in point:
                    t = d[a] / (d[a] - d[b])
                    point[key] = H.add(verts[a], H.scale(H.sub(verts[b], verts[a]), t))
                cut.append(key)
        if len(cut) == 2:
            nxt.setdefault(cut[0], []).append(cut[1])
            nxt.setdefault(cut[1], []).append(cut[0])
    seen = set()
    pieces = []
    # open chains start at an edge with one neighbour (mesh boundary); then the loops
    starts = [k for k, v in nxt.items() if len(v) == 1] + list(nxt)
    for s in starts:
        if s in seen:
            continue
        chain, prev, cur = [s], None, s
        seen.add(s)
        closed = False
        while True:
            cand = [k for k in nxt[cur] if k != prev and k not in seen]
            if not cand:
                closed = len(chain) > 2 and s in nxt[cur] and prev is not None
                break
            prev, cur = cur, cand[0]
            seen.add(cur)
            chain.append(cur)
        pieces.append(([point[k] for k in chain], closed))
    # join open pieces end to end
    opened = [p for p, c in pieces if not c]
    closed = [(p, True) for p, c in pieces if c]
    joined = True
    while joined and len(opened) > 1:
        joined = False
        for i in range(len(opened)):
            for j in range(i + 1, len(opened)):
                a, b = opened[i], opened[j]
                for aa, bb in ((a, b), (a, b[::-1]), (a[::-1], b), (a[::-1], b[::-1])):
                    if H.norm(H.sub(aa[-1], bb[0])) <= join_gap:
                        opened[i] = aa + bb
                        del opened[j]
                        joined = True
                        break
                if joined:
                    break
            if joined:
                break
    out = closed
    for p in opened:
        out.append((p, len(p) > 2 and H.norm(H.sub(p[0], p[-1])) <= join_gap))
    return out


def length(pts, closed):
    s = sum(H.norm(H.sub(b, a)) for a, b in zip(pts, pts[1:]))
    return s + (H.norm(H.sub(pts[0], pts[-1])) if closed else 0.0)


def resample(pts, spacing, closed):
    """Points every `spacing` mm along the polyline (the ends of an open one kept)."""
    ring = pts + [pts[0]] if closed else list(pts)
    total = length(pts, closed)
    n = max(3 if closed else 2, round(total / spacing))
    step = total / n
    out, acc, i = [ring[0]], 0.0, 0
    target = step
    while i < len(ring) - 1 and len(out) < (n if closed else n + 1):
        seg = H.norm(H.sub(ring[i + 1], ring[i]))
        if acc + seg >= target - 1e-12 and seg > 0:
            t = (target - acc) / seg
            out.append(H.add(ring[i], H.scale(H.sub(ring[i + 1], ring[i]), t)))
            target += step
        else:
            acc += seg
            i += 1
    if not closed and H.norm(H.sub(out[-1], ring[-1])) > 1e-9:
        out.append(ring[-1])
    return out


# ---------------------------------------------------------------------------------------------
# The planner's geometry, read off `heartmesh simulate` at defaults


def solve3(m, v):
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    out = []
    for c in range(3):
        mm = [list(r) for r in m]
        for r in range(3):
            mm[r][c] = v[r]
        out.append((mm[0][0] * (mm[1][1] * mm[2][2] - mm[1][2] * mm[2][1]) -
                    mm[0][1] * (mm[1][0] * mm[2][2] - mm[1][2] * mm[2][0]) +
                    mm[0][2] * (mm[1][0] * mm[2][1] - mm[1][1] * mm[2][0])) / det)
    return tuple(out)


def unit(v):
    return H.scale(v, 1 / H.norm(v))


class Frame:
    """Axis direction `d` (apex to base), a point `c` on the axis at the basal SAX height, the
    SAX heights along `d` from `c` (apex first, so the top is 0), the apex height, and the LAX
    reference `e0` (the planner's 0-degree LAX plane contains d and e0)."""

    def __init__(self, ref_csv):
        blocks = H.read_csv(ref_csv)
        sax = [b for b in blocks if b[0].startswith("sax")]
        lax = [b for b in blocks if b[0].startswith("lax")]
        d = H.normal_of(sax[len(sax) // 2][2])
        if H.dot(H.sub(H.centroid(sax[-1][2]), H.centroid(sax[0][2])), d) < 0:
            d = H.scale(d, -1)
        self.d = d
        hs = [H.dot(H.centroid(b[2]), d) for b in sax]
        top = hs[-1]
        # a point on the axis: in every LAX plane, at the basal height
        rows = [H.cross(d, unit(H.cross(H.normal_of(b[2]), d))) for b in lax]
        rows = [unit(r) for r in rows]
        m = [[0.0] * 3 for _ in range(3)]
        v = [0.0, 0.0, 0.0]
        for n, b in zip(rows, lax):
            off = H.dot(n, H.centroid(b[2]))
            for i in range(3):
                for j in range(3):
                    m[i][j] += n[i] * n[j]
                v[i] = v[i] + n[i] * off
        for i in range(3):
            for j in range(3):
                m[i][j] += d[i] * d[j]
            v[i] += d[i] * top
        self.c = solve3(m, v)
        self.sax = [h - top for h in hs]
        self.apex = min(H.dot(H.sub(p, self.c), d) for b in lax for p in b[2])
        self.e0 = unit(H.cross(rows[0], d)) if lax else unit(H.cross(d, (1.0, 0.0, 0.0)))
        self.e1 = H.cross(d, self.e0)


def perpendicular(v, rng):
    """A random unit vector perpendicular to v."""
    while True:
        w = H.cross(v, (rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        if H.norm(w) > 1e-3:
            return unit(w)


# ---------------------------------------------------------------------------------------------
# An acquisition: SAX planes (origin, normal) and LAX planes, then the curves


class Acq:
    def __init__(self, fr):
        self.fr = fr
        self.sax_normal = fr.d
        self.sax_h = list(fr.sax)  # heights from the basal plane along sax_normal
        self.lax_deg = [0.0, 90.0, 45.0]
        self.lax_off = [0.0, 0.0, 0.0]  # mm along each LAX plane's normal
        self.lax_shift = [None, None, None]  # breath-hold displacement of the heart per LAX
        self.lax_trim = None  # (lo, hi) mm of arc removed from each end of the LAX curves
        self.lax_half = False  # only one side of the U
        self.lax_closed = False  # the U closed by its chord (the valve line), as masks trace it
        self.all_loops = False  # every closed loop of a SAX section (else the longest)
        self.spacing = 1.0
        self.noise = 0.0
        self.pixel = 0.0  # > 0: curves traced from a mask on an image grid of this spacing (mm)
        self.post = []  # functions on the block list


def sax_range(fr, spacing, start=0.0, low=None):
    """Heights from `start` (0: the planner's basal plane) down to 3 mm above the apex."""
    low = fr.apex + 3.0 if low is None else low
    hs, h = [], start
    while h >= low - 1e-9:
        hs.append(h)
        h -= spacing
    return hs[::-1]


def build(mesh, acq, rng, surface):
    fr = acq.fr
    blocks, warnings = [], []
    for k, h in enumerate(acq.sax_h):
        origin = H.add(fr.c, H.scale(acq.sax_normal, h))
        pieces = [p for p in slice_mesh(mesh, origin, acq.sax_normal) if p[1] and len(p[0]) > 2]
        pieces.sort(key=lambda p: -length(*p))
        if not pieces:
            warnings.append(f"sax{k + 1:02}: no closed loop")
            continue
        keep = pieces if acq.all_loops else pieces[:1]
        for j, (pts, closed) in enumerate(keep):
            cid = f"sax{k + 1:02}" + (chr(ord("a") + j) if len(keep) > 1 else "")
            blocks.append([cid, surface, pts, closed, acq.sax_normal])
    for j, deg in enumerate(acq.lax_deg):
        t = math.radians(deg)
        in_plane = H.add(H.scale(fr.e0, math.cos(t)), H.scale(fr.e1, math.sin(t)))
        n = unit(H.cross(fr.d, in_plane))
        origin = H.add(fr.c, H.scale(n, acq.lax_off[j]))
        shift = acq.lax_shift[j] or (0.0, 0.0, 0.0)
        pieces = slice_mesh(mesh, H.sub(origin, shift), n)
        if not pieces:
            warnings.append(f"lax{j + 1:02}: plane misses")
            continue
        pts, closed = max(pieces, key=lambda p: length(*p))
        pts = [H.add(p, shift) for p in pts]
        if acq.lax_half and not closed:
            low = min(range(len(pts)), key=lambda i: H.dot(pts[i], fr.d))
            pts = pts[:low + 1] if rng.random() < 0.5 else pts[low:]
        if acq.lax_trim and not closed:
            pts = trim(pts, rng.uniform(*acq.lax_trim), rng.uniform(*acq.lax_trim))
        if len(pts) < 3:
            continue
        if acq.lax_closed and not closed:
            a, b = pts[-1], pts[0]
            k = max(1, int(H.norm(H.sub(b, a)) / 0.5))
            pts = pts + [H.add(a, H.scale(H.sub(b, a), i / k)) for i in range(1, k)]
            closed = True
        blocks.append([f"lax{j + 1:02}", surface, pts, closed, n])
    if acq.pixel > 0:
        blocks = [b for b in (pixelated(b, acq.pixel, rng) for b in blocks) if b]
    for b in blocks:
        b[2] = resample(b[2], acq.spacing, b[3]) if acq.spacing > 0 else b[2]
        if acq.noise > 0:
            u = perpendicular(b[4], rng)
            v = H.cross(b[4], u)
            b[2] = [H.add(p, H.add(H.scale(u, rng.gauss(0, acq.noise)),
                                   H.scale(v, rng.gauss(0, acq.noise)))) for p in b[2]]
    out = [(b[0], b[1], b[2]) for b in blocks]
    for f in acq.post:
        out = f(out, rng)
    return out, warnings


def pixelated(block, size, rng):
    """The curve as a segmentation network's mask gives it: the region it bounds (an open
    long-axis curve closed by its chord, the valve plane) filled on an image grid of `size` mm
    at a random in-plane angle and offset, and its outline traced between inside and outside
    pixel centres (marching squares on a binary mask: a staircase, no inward bias), ordered; an
    open curve loses the chord's part again. None when the region covers no pixel centre."""
    cid, surface, pts, closed, n = block
    u = perpendicular(n, rng)
    v = H.cross(n, u)
    o = H.add(pts[0], H.add(H.scale(u, rng.uniform(0, size)), H.scale(v, rng.uniform(0, size))))
    h = H.dot(H.sub(pts[0], o), n)
    xy = [(H.dot(H.sub(p, o), u) / size, H.dot(H.sub(p, o), v) / size) for p in pts]
    poly = xy + ([] if closed else [xy[0]])
    inside = set()
    for j in range(math.floor(min(q[1] for q in poly)), math.ceil(max(q[1] for q in poly)) + 1):
        xs = []
        for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
            if (y0 > j) != (y1 > j):
                xs.append(x0 + (j - y0) * (x1 - x0) / (y1 - y0))
        xs.sort()
        for a, b in zip(xs[::2], xs[1::2]):
            inside.update((i, j) for i in range(math.ceil(a), math.floor(b) + 1))
    # directed pixel edges with the region on their left, chained corner to corner
    nxt = {}
    for i, j in inside:
        for (di, dj), a, b in (((0, -1), (i - .5, j - .5), (i + .5, j - .5)),
                               ((1, 0), (i + .5, j - .5), (i + .5, j + .5)),
                               ((0, 1), (i + .5, j + .5), (i - .5, j + .5)),
                               ((-1, 0), (i - .5, j + .5), (i - .5, j - .5))):
            if (i + di, j + dj) not in inside:
                nxt.setdefault(a, []).append(b)
    loops = []
    while nxt:
        start = min(nxt)
        loop, c = [], start
        while c in nxt:
            d = nxt[c].pop()
            if not nxt[c]:
                del nxt[c]
            loop.append(((c[0] + d[0]) / 2, (c[1] + d[1]) / 2))
            c = d
        loops.append(loop)
    if not loops:
        return None

    def area(lp):
        return abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(lp, lp[1:] + lp[:1])))
    out = max(loops, key=area)
    if not closed:
        a, b = xy[-1], xy[0]
        ab = (b[0] - a[0], b[1] - a[1])
        ll = ab[0] ** 2 + ab[1] ** 2 or 1.0

        def near_chord(q):
            t = max(0.0, min(1.0, ((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1]) / ll))
            return math.hypot(q[0] - a[0] - t * ab[0], q[1] - a[1] - t * ab[1]) < 1.0
        keep = [not near_chord(q) for q in out]
        if all(keep) or not any(keep):
            return None
        k = keep.index(False)
        out, keep = out[k:] + out[:k], keep[k:] + keep[:k]  # start inside the chord's run
        runs, cur = [], []
        for q, kq in zip(out, keep):
            if kq:
                cur.append(q)
            elif cur:
                runs.append(cur)
                cur = []
        runs.append(cur)
        out = max(runs, key=len)
    if len(out) < 3:
        return None
    to3 = [H.add(o, H.add(H.scale(n, h), H.add(H.scale(u, x * size), H.scale(v, y * size))))
           for x, y in out]
    return [cid, surface, to3, closed, n]


def trim(pts, a, b):
    """Drop `a` mm of arc from the start and `b` mm from the end."""
    def cut(p, amount):
        acc = 0.0
        for i in range(1, len(p)):
            acc += H.norm(H.sub(p[i], p[i - 1]))
            if acc >= amount:
                return p[i:]
        return []
    return cut(cut(pts, a)[::-1], b)[::-1]


# ---------------------------------------------------------------------------------------------
# Families


def families():
    """name -> function(acq, rng) that changes the planner's acquisition."""
    F = {}

    def planner(a, r):
        pass
    F["planner"] = planner

    for deg in (5, 10, 15):
        def tilt(a, r, deg=deg):
            axis = perpendicular(a.fr.d, r)
            a.sax_normal = unit(H.rotate(a.fr.d, axis, math.radians(deg)))
            # planned on a scout: the stack still runs from the base to near the apex
            a.sax_h = sax_range(a.fr, 10.0, low=a.fr.apex * math.cos(math.radians(deg)) + 3.0)
        F[f"tilt{deg}"] = tilt

    for s in (6, 8, 12, 15):
        F[f"spacing{s}"] = lambda a, r, s=s: setattr(a, "sax_h", sax_range(a.fr, s))

    for n in (6, 14):
        def count(a, r, n=n):
            lo, hi = a.fr.apex + 3.0, 0.0
            a.sax_h = [lo + (hi - lo) * k / (n - 1) for k in range(n)]
        F[f"count{n}"] = count

    def gap(a, r):
        del a.sax_h[len(a.sax_h) // 2]
    F["gap-mid"] = gap

    def no_apex(a, r):
        a.sax_h = [h for h in a.sax_h if h >= a.fr.apex + r.uniform(18.0, 26.0)]
    F["short-of-apex"] = no_apex

    def no_apex_sax_only(a, r):
        no_apex(a, r)
        a.lax_deg = []
    F["short-of-apex-sax-only"] = no_apex_sax_only

    def no_base(a, r):
        a.sax_h = [h for h in a.sax_h if h <= -r.uniform(12.0, 20.0)]
    F["short-of-base"] = no_base

    def over_base(a, r):
        a.sax_h = a.sax_h + [r.uniform(3.0, 6.0), r.uniform(8.0, 12.0)]
        a.all_loops = True
    F["past-base-all-loops"] = over_base

    def second_loop(a, r):
        """A basal slice that also cuts another structure (an outflow tract, an RV body and its
        outflow): a 5-8 mm loop 5-15 mm beside the basal ring, in its plane, same label."""
        def f(bl, r):
            sax = [b for b in bl if b[0].startswith("sax")]
            if not sax:
                return bl
            cid, surf, pts = sax[-1]
            c = H.centroid(pts)
            u = perpendicular(a.sax_normal, r)
            v = H.cross(a.sax_normal, u)
            reach = max(H.dot(H.sub(p, c), u) for p in pts)
            rad = r.uniform(5.0, 8.0)
            centre = H.add(c, H.scale(u, reach + r.uniform(5.0, 15.0) + rad))
            n = max(12, round(2 * math.pi * rad / a.spacing))
            ring = [H.add(centre, H.add(H.scale(u, rad * math.cos(2 * math.pi * i / n)),
                                        H.scale(v, rad * math.sin(2 * math.pi * i / n))))
                    for i in range(n)]
            return bl + [(cid + "b", surf, ring)]
        a.post.append(f)
    F["second-loop-base"] = second_loop

    def speck(where):
        """A speck (session 14): a 3-point loop 0.5-1.5 mm in radius (2.6-7.8 mm around) in a
        short-axis plane of its own, same label: a stray click inside the basal ring's outline
        4-8 mm past it ("click-past-base"), a graze of the wall 3-6 mm past the basal ring
        ("graze-past-base"), or a stray click inside the cavity halfway between two slices
        ("click-mid")."""
        def fam(a, r):
            a.post.append(lambda bl, r: add_speck(a, bl, r))

        def add_speck(a, bl, r):
            sax = [b for b in bl if b[0].startswith("sax")]
            if len(sax) < 4:
                return bl
            n = a.sax_normal
            if where == "click-mid":
                k = r.randrange(1, len(sax) - 2)
                ring = sax[k][2]
                c = H.scale(H.add(H.centroid(ring), H.centroid(sax[k + 1][2])), 0.5)
            else:
                ring = sax[-1][2]
                c = H.centroid(ring)
            u = perpendicular(n, r)
            v = H.cross(n, u)
            reach = max(H.dot(H.sub(p, c), u) for p in ring)
            if where == "graze-past-base":
                off, lift = reach, r.uniform(3.0, 6.0)
            elif where == "click-past-base":
                off, lift = r.uniform(0.0, 0.8) * reach, r.uniform(4.0, 8.0)
            else:
                off, lift = r.uniform(0.0, 0.8) * reach, 0.0
            centre = H.add(c, H.add(H.scale(u, off), H.scale(n, lift)))
            rad, phase = r.uniform(0.5, 1.5), r.uniform(0.0, 2 * math.pi)
            pts = [H.add(centre, H.add(H.scale(u, rad * math.cos(phase + 2 * math.pi * i / 3)),
                                       H.scale(v, rad * math.sin(phase + 2 * math.pi * i / 3))))
                   for i in range(3)]
            return bl + [("speck", sax[-1][1], pts)]
        return fam

    for where in ("click-past-base", "graze-past-base", "click-mid"):
        F["speck-" + where] = speck(where)

    def far_pair(a, r):
        """Two adjacent short-axis rings copied 150-300 mm away in a random direction, same label
        (session 15): curves of another series pasted into the file side by side, which hid each
        other from session 14's one-at-a-time stray rule. Left out, the mesh is the one without
        them; kept, the tube threads them with the real rings."""
        def add_pair(bl, r):
            sax = [b for b in bl if b[0].startswith("sax")]
            if len(sax) < 3:
                return bl
            k = r.randrange(0, len(sax) - 1)
            d = unit((r.gauss(0, 1), r.gauss(0, 1), r.gauss(0, 1)))
            shift = H.scale(d, r.uniform(150.0, 300.0))
            return bl + [(f"far{j}", sax[k + j][1], [H.add(p, shift) for p in sax[k + j][2]])
                         for j in range(2)]
        a.post.append(add_pair)
    F["far-pair"] = far_pair

    def click_lax(a, r):
        """A click in a long-axis view (session 15): a 3-point loop 0.5-1.5 mm in radius in the
        plane of one long-axis curve, at the middle of the cavity (the short-axis points' centroid
        projected into that plane), same label. Kept, it pulls a spike of the wall into the
        cavity; left out (`lax_speck`), the mesh is the one without it."""
        def add_click(bl, r):
            lax = [b for b in bl if b[0].startswith("lax")]
            sax = [p for b in bl if b[0].startswith("sax") for p in b[2]]
            if not lax or not sax:
                return bl
            _, surf, pts = r.choice(lax)
            n = H.normal_of(pts)
            c = H.centroid(sax)
            c = H.sub(c, H.scale(n, H.dot(H.sub(c, pts[0]), n)))
            u = perpendicular(n, r)
            v = H.cross(n, u)
            rad, phase = r.uniform(0.5, 1.5), r.uniform(0.0, 2 * math.pi)
            ring = [H.add(c, H.add(H.scale(u, rad * math.cos(phase + 2 * math.pi * i / 3)),
                                   H.scale(v, rad * math.sin(phase + 2 * math.pi * i / 3))))
                    for i in range(3)]
            return bl + [("click", surf, ring)]
        a.post.append(add_click)
    F["click-lax"] = click_lax

    for off in (3, 6):
        def lax_off(a, r, off=off):
            a.lax_off = [off * r.choice((-1, 1)) for _ in a.lax_deg]
        F[f"lax-off{off}"] = lax_off

    F["lax-4ch-only"] = lambda a, r: setattr(a, "lax_deg", [0.0])
    F["lax-2ch-4ch"] = lambda a, r: setattr(a, "lax_deg", [0.0, 90.0])

    def lax_shift(a, r):
        a.lax_shift = [H.scale(unit((r.gauss(0, 1), r.gauss(0, 1), r.gauss(0, 1))),
                               r.uniform(3.0, 5.0)) for _ in a.lax_deg]
    F["lax-breath-hold"] = lax_shift

    F["lax-partial"] = lambda a, r: setattr(a, "lax_trim", (10.0, 30.0))
    F["lax-one-side"] = lambda a, r: setattr(a, "lax_half", True)
    F["lax-closed-valve"] = lambda a, r: setattr(a, "lax_closed", True)

    def closed_breath_hold(a, r):
        lax_shift(a, r)
        a.lax_closed = True
    F["lax-closed-breath-hold"] = closed_breath_hold

    for sp in (0.2, 3.0, 6.0):
        F[f"points{sp:g}mm"] = lambda a, r, sp=sp: setattr(a, "spacing", sp)

    def clockwise(a, r):
        a.post.append(lambda bl, r: [(c, s, p[::-1]) for c, s, p in bl])
    F["reversed"] = clockwise

    def alternate(a, r):
        a.post.append(lambda bl, r: [(c, s, p[::-1] if i % 2 else p)
                                     for i, (c, s, p) in enumerate(bl)])
    F["alternating-winding"] = alternate

    def shuffled(a, r):
        def f(bl, r):
            bl = list(bl)
            r.shuffle(bl)
            return bl
        a.post.append(f)
    F["random-order"] = shuffled

    def duplicate(a, r):
        def f(bl, r):
            k = r.randrange(len(bl))
            return bl + [(bl[k][0] + "copy", bl[k][1], list(bl[k][2]))]
        a.post.append(f)
    F["duplicate-contour"] = duplicate

    for far in (1e3, 1e4):
        def offset(a, r, far=far):
            v = H.scale(unit((1.0, -0.7, 0.4)), far)
            a.post.append(lambda bl, r: [(c, s, [H.add(p, v) for p in pts]) for c, s, pts in bl])
            a.offset = v
        F[f"offset{far:.0e}"] = offset

    for px in (1.4, 2.0):
        def pixels(a, r, px=px):
            a.pixel = px
            a.spacing = 0.0  # one point per pixel edge, as traced
        F[f"pixels{px:g}"] = pixels

    for sd in (0.3, 0.6, 1.0):
        F[f"noise{sd:g}"] = lambda a, r, sd=sd: setattr(a, "noise", sd)

    def realistic(a, r):
        F["tilt10"](a, r)
        a.sax_h = sax_range(a.fr, 8.0, low=a.fr.apex + 4.0)
        F["lax-off3"](a, r)
        lax_shift(a, r)
        a.noise = 0.5
    F["combined"] = realistic
    return F


# ---------------------------------------------------------------------------------------------
# Running and judging


def run(cmd, timeout=300):
    return subprocess.run(cmd, capture_output=True, timeout=timeout)


def compare(truth, mesh, clip_csv):
    r = run([H.BIN, "compare", truth, mesh, "--clip-contours", clip_csv, "--json"])
    if r.returncode != 0:
        return None
    return json.loads(r.stdout)


def shifted_obj(src, dst, v):
    """`src` moved by v (the far-coordinates family compares in its own frame)."""
    with open(src) as f, open(dst, "w") as g:
        for line in f:
            if line.startswith("v "):
                p = [float(t) for t in line.split()[1:4]]
                g.write("v {:.6f} {:.6f} {:.6f}\n".format(p[0] + v[0], p[1] + v[1], p[2] + v[2]))
            else:
                g.write(line)


def one_case(out, tname, truth, ref_csv, mesh, fr, fam, fn, seed, surface, extra):
    rng = random.Random(f"{tname}/{fam}/{seed}")
    acq = Acq(fr)
    fn(acq, rng)
    blocks, warnings = build(mesh, acq, rng, surface)
    cdir = os.path.join(out, "cases", f"{tname}-{fam}-s{seed}")
    os.makedirs(cdir, exist_ok=True)
    csv = os.path.join(cdir, "in.csv")
    with open(csv, "wb") as f:
        f.write(H.write_csv(blocks, fmt="{:.6f}"))
    obj, rep_path = os.path.join(cdir, "out.obj"), os.path.join(cdir, "r.json")
    for p in (obj, rep_path):
        if os.path.exists(p):
            os.remove(p)
    t0 = time.time()
    r = run([H.BIN, "reconstruct", csv, "-o", obj, "--report", rep_path, "--quiet"] + extra)
    dt = time.time() - t0
    row = {"truth": tname, "family": fam, "seed": seed, "contours": len(blocks), "time": dt,
           "warnings": warnings}
    if r.returncode != 0:
        row["fail"] = f"exit {r.returncode}: " + r.stderr.decode(errors="replace").strip()[:200]
        return row
    with open(rep_path) as f:
        rep = json.load(f)
    row.update(watertight=rep["watertight"], manifold=rep["manifold"],
               folds=rep["quality"]["folded_edges"], c2m=rep["contour_to_mesh"]["mean"],
               c2m_max=rep["contour_to_mesh"]["max"], past=rep.get("past_data"),
               seconds=rep.get("seconds"), cli_warnings=rep.get("warnings", []))
    t = truth
    ref = ref_csv
    if getattr(acq, "offset", None) is not None:
        t = os.path.join(cdir, "truth.obj")
        shifted_obj(truth, t, acq.offset)
        ref = os.path.join(cdir, "ref.csv")
        blocks_ref = [(c, s, [H.add(p, acq.offset) for p in pts])
                      for c, s, pts in H.read_csv(ref_csv)]
        with open(ref, "wb") as f:
            f.write(H.write_csv(blocks_ref, fmt="{:.6f}"))
    for key, clip in (("own", csv), ("ref", ref)):
        c = compare(t, obj, clip)
        if c is None:
            row["fail"] = f"compare ({key}) failed"
            return row
        row[key] = {"mean": (c["mesh_to_truth"]["mean"] + c["truth_to_mesh"]["mean"]) / 2,
                    "haus": c["hausdorff"],
                    "vol": 100 * (c["volume_mesh_ml"] / c["volume_truth_ml"] - 1)}
    return row


def flags(row, base):
    out = []
    if "fail" in row:
        return ["FAIL"]
    if not (row["watertight"] and row["manifold"]):
        out.append("MESH")
    if row["folds"]:
        out.append("FOLD")
    if base and "own" in base:
        if row["own"]["mean"] > 2 * base["own"]["mean"] + 0.3:
            out.append("MEAN")
        if row["own"]["haus"] > 2 * base["own"]["haus"] + 2.0:
            out.append("MAX")
        if row["time"] > 5 * base["time"]:
            out.append("SLOW")
    return out


def median(xs):
    xs = sorted(xs)
    n = len(xs)
    return (xs[n // 2] + xs[(n - 1) // 2]) / 2 if n else float("nan")


def main():
    argv = sys.argv[1:]
    out, seed, nseeds, only, only_truth, extra = "/tmp/heldout", 13, 2, None, None, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--seed", "--seeds", "--only", "--truth", "--args"):
            v = argv[i + 1]
            i += 2
            if a == "--seed":
                seed = int(v)
            elif a == "--seeds":
                nseeds = int(v)
            elif a == "--only":
                only = v
            elif a == "--truth":
                only_truth = v
            else:
                extra = v.split()
        elif a.startswith("-"):
            return H.usage(a, __doc__)
        else:
            out = a
            i += 1
    os.makedirs(out, exist_ok=True)
    fams = families()
    rows = []
    print(f"{'flags':10} {'truth':10} {'family':24} seed  own mean  haus   vol%  | ref mean  haus"
          f"   vol% | c2m   folds  time  warnings")
    for tname, tfile, axis_from, surface in TRUTHS:
        if only_truth and only_truth != tname:
            continue
        if tfile is None:
            truth = os.path.join(out, f"truth-{tname}.obj")
            parametric_obj(truth, seed)
        else:
            truth = os.path.join(MESHES, tfile)
        ref_csv = os.path.join(out, f"ref-{tname}.csv")
        cmd = [H.BIN, "simulate", truth, "-o", ref_csv, "--quiet"]
        if axis_from:
            cmd += ["--axis-from", os.path.join(MESHES, axis_from)]
        r = run(cmd)
        if r.returncode != 0:
            print(f"simulate {tname} failed: {r.stderr.decode(errors='replace')}")
            continue
        fr = Frame(ref_csv)
        mesh = read_obj(truth)
        base = None
        for fam, fn in fams.items():
            if only and fam != "planner" and only not in fam:
                continue
            for s in range(seed, seed + (1 if fam == "planner" else nseeds)):
                row = one_case(out, tname, truth, ref_csv, mesh, fr, fam, fn, s, surface, extra)
                if fam == "planner":
                    base = row
                row["flags"] = flags(row, base)
                rows.append(row)
                show(row)
    with open(os.path.join(out, "heldout.json"), "w") as f:
        json.dump(rows, f, indent=1)
    summary(rows)
    bad = sum(1 for r in rows if r["flags"])
    print(f"{bad} case(s) flagged of {len(rows)}")
    return 0


def show(row):
    fl = ",".join(row["flags"]) or "ok"
    head = f"{fl:10} {row['truth']:10} {row['family']:24} {row['seed']:4}"
    if "fail" in row:
        print(f"{head}  {row['fail']}", flush=True)
        return
    o, f = row["own"], row["ref"]
    print(f"{head}  {o['mean']:6.3f} {o['haus']:6.2f} {o['vol']:+6.1f} | {f['mean']:6.3f} "
          f"{f['haus']:6.2f} {f['vol']:+6.1f} | {row['c2m']:5.3f} {row['folds']:4d} "
          f"{row['time']:5.2f}s  {len(row['cli_warnings'])}w", flush=True)


def summary(rows):
    """Per family over all truths and seeds: medians and worst cases (own clip)."""
    print("\nfamily                    n  fail  mean(med/max)   haus(med/max)  |vol%|(med/max)"
          "  folds  time(med)")
    fams = []
    for r in rows:
        if r["family"] not in fams:
            fams.append(r["family"])
    for fam in fams:
        rs = [r for r in rows if r["family"] == fam]
        ok = [r for r in rs if "fail" not in r]
        m = [r["own"]["mean"] for r in ok]
        h = [r["own"]["haus"] for r in ok]
        v = [abs(r["own"]["vol"]) for r in ok]
        print(f"{fam:24} {len(rs):3} {len(rs) - len(ok):4}  {median(m):6.3f} {max(m or [0]):6.3f}"
              f"   {median(h):6.2f} {max(h or [0]):6.2f}   {median(v):6.1f} {max(v or [0]):6.1f}"
              f"  {sum(r['folds'] for r in ok):5}  {median([r['time'] for r in ok]):5.2f}")


if __name__ == "__main__":
    sys.exit(main())
