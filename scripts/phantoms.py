#!/usr/bin/env python3
"""Analytic phantoms with exact coincidences, end to end (session 9, brief PHANT9).

Hand-built shapes are what users feed a new tool first: perfect ellipsoids, spheres, cylinders,
cones, integer coordinates, exactly symmetric layouts, long-axis curves that end exactly in a
short-axis plane or at the apex tip. This script builds them (seeded, standard library only), runs
each through the release CLI with scripts/hostile.py's runner and, besides hostile.py's flags
(PANIC, HANG, EXIT, VAGUE, MESH, C2M, SELFX, EXPECT), flags

  FOLD     the report counts folded edges
  VOL      the mesh volume is off the analytic volume between the lowest and highest data by more
           than the extrapolation past the data explains (see `check`)

and prints, per case, how far the mesh runs past the data along the axis (top / apex, mm).
Usage:  scripts/phantoms.py [OUT_DIR] [--seed S] [--only SUBSTRING] [--timeout SECONDS]
        [--random N] [--args "EXTRA CLI FLAGS"]
"""

import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile as H  # noqa: E402  (the shared runner, judge and CSV writer)

TAU = 2 * math.pi


# ---------------------------------------------------------------------------------------------
# Shapes: a radius profile r(z) about the local z axis, apex at the bottom


class Shape:
    """A solid of revolution (or, for the RV crescent, of circular-segment sections) between
    z_apex and z_max; `profile` is its meridian (u, z) from the top down to the axis, exact at
    both ends, so long-axis curves end exactly where the brief asks."""

    def __init__(self, name, r_of_z, z_apex, z_max, profile, area=None):
        self.name = name
        self.r = r_of_z
        self.z_apex = z_apex
        self.z_max = z_max
        self.profile = profile  # f(z_from, n) -> [(u, z)] from z_from down to the apex (u = 0)
        self.area = area or (lambda z: math.pi * self.r(z) ** 2)

    def volume(self, z0, z1, steps=2000):
        """Simpson's rule of the section area (mm^3)."""
        if z1 <= z0:
            return 0.0
        h = (z1 - z0) / steps
        s = self.area(z0) + self.area(z1)
        for i in range(1, steps):
            s += (4 if i % 2 else 2) * self.area(z0 + i * h)
        return s * h / 3


def ellipsoid(a, c, z_max=0.0):
    """Semi-axes a (radial) and c (axial), centred at z = 0; cut at z_max (0: the equator)."""
    def r(z):
        return a * math.sqrt(max(0.0, 1 - (z / c) ** 2))

    def profile(z_from, n):
        t0 = math.acos(max(-1.0, min(1.0, -z_from / c)))  # angle from the apex
        pts = [(a * math.sin(t0 * (1 - i / (n - 1))), -c * math.cos(t0 * (1 - i / (n - 1))))
               for i in range(n)]
        pts[0] = (r(z_from), z_from)
        pts[-1] = (0.0, -c)
        return pts
    return Shape(f"ellipsoid-a{a:g}-c{c:g}", r, -c, z_max, profile)


def polyline_shape(name, corners, z_apex):
    """A shape whose meridian is a polyline from the top corner down to (0, z_apex)."""
    def r(z):
        for (u0, z0), (u1, z1) in zip(corners, corners[1:]):
            if z1 <= z <= z0 and z0 > z1:
                return u0 + (u1 - u0) * (z0 - z) / (z0 - z1)
        return corners[-2][0] if z <= corners[-2][1] else corners[0][0]

    def profile(z_from, n):
        pts = [(r(z_from), z_from)] + [c for c in corners if c[1] < z_from]
        if pts[-1] != corners[-1]:
            pts.append(corners[-1])
        return densify(pts, n)
    return Shape(name, r, z_apex, corners[0][1], profile)


def capsule(radius, height):
    """A cylinder on a hemisphere (the U-shape)."""
    def r(z):
        return radius if z >= 0 else math.sqrt(max(0.0, radius ** 2 - z ** 2))

    def profile(z_from, n):
        k = max(3, n // 2)
        side = [(radius, z_from), (radius, 0.0)] if z_from > 0 else []
        t0 = math.asin(max(-1.0, min(1.0, -z_from / radius))) if z_from < 0 else 0.0
        cap = [(radius * math.cos(t0 + (math.pi / 2 - t0) * i / (k - 1)),
                -radius * math.sin(t0 + (math.pi / 2 - t0) * i / (k - 1))) for i in range(k)]
        cap[-1] = (0.0, -radius)
        return densify(side, n - k) + cap if side else cap
    return Shape(f"capsule-r{radius:g}-h{height:g}", r, -radius, height, profile)


def densify(pts, n):
    """About n points along the polyline, keeping its corners exactly."""
    lengths = [H.norm((b[0] - a[0], b[1] - a[1], 0.0)) for a, b in zip(pts, pts[1:])]
    total = sum(lengths) or 1.0
    out = [pts[0]]
    for (a, b), length in zip(zip(pts, pts[1:]), lengths):
        k = max(1, round(n * length / total))
        out += [(a[0] + (b[0] - a[0]) * i / k, a[1] + (b[1] - a[1]) * i / k)
                for i in range(1, k + 1)]
    return out


def crescent(radius, offset, depth):
    """An RV-like section: the part of a circle beyond a straight septum at `offset` from its
    centre, tapering linearly to nothing `depth` mm below z = 0."""
    def rad(z):
        return radius * max(0.0, min(1.0, 1 + z / depth))

    def area(z):
        r = rad(z)
        d = offset * r / radius
        return r * r * math.acos(d / r) - d * math.sqrt(r * r - d * d) if r > 0 else 0.0
    s = Shape(f"crescent-r{radius:g}-d{offset:g}", rad, -depth, 0.0, None, area)
    return s


# ---------------------------------------------------------------------------------------------
# Contours from a shape, in the local frame, then placed


def sax_ring(shape, z, n, start, clockwise):
    r = shape.r(z)
    pts = [(r * math.cos(start + TAU * i / n), r * math.sin(start + TAU * i / n), z)
           for i in range(n)]
    return pts[::-1] if clockwise else pts


def crescent_ring(shape, z, n, start):
    """Arc of the circle beyond the septum x = d, then the straight septum back (closed)."""
    r = shape.r(z)
    d = offset_of(shape) * r / shape.r(0.0)
    half = math.acos(d / r)
    arc = [(r * math.cos(-half + 2 * half * i / (n - 1)), r * math.sin(-half + 2 * half * i / (n - 1)), z)
           for i in range(n)]
    k = max(2, int(n * (2 * r * math.sin(half)) / (2 * half * r)))
    septum = [(d, r * math.sin(half) * (1 - 2 * i / k), z) for i in range(1, k)]
    ring = arc + septum
    shift = int(start / TAU * len(ring)) % len(ring)
    return ring[shift:] + ring[:shift]


def offset_of(shape):
    return float(shape.name.split("-d")[1])


def lax_curve(shape, phi, z_from, n, mode):
    """A long-axis curve in the plane at angle phi through the axis.
    mode 'both': down one side through the apex and up the other (open U);
    'apex': one side, ending exactly at the apex tip; 'short': one side, 4 mm below z_from to
    5 mm above the apex (reaching neither end)."""
    side = shape.profile(z_from, n)
    if mode == "short":
        side = [p for p in side if shape.z_apex + 5 <= p[1] <= z_from - 4]
    c, s = math.cos(phi), math.sin(phi)
    one = [(u * c, u * s, z) for u, z in side]
    if mode not in ("both", "closed"):
        return one
    other = [(-u * c, -u * s, z) for u, z in side]
    u_shape = one + other[::-1][1:]
    if mode == "both":
        return u_shape
    # 'closed': the U closed by the straight segment across the top, which lies exactly in the
    # top short-axis plane (as SurFCo's closed long-axis contours do at the base).
    a, b = u_shape[-1], u_shape[0]
    k = max(2, round(n * H.norm(H.sub(a, b)) / (2 * shape.z_max - 2 * shape.z_apex + 1e-9)))
    return u_shape + [H.add(a, H.scale(H.sub(b, a), i / k)) for i in range(1, k)]


def frame(axis_name, rng):
    """Orthonormal (e1, e2, axis) for the long axis along x, y, z or an oblique direction."""
    if axis_name == "x":
        return (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)
    if axis_name == "y":
        return (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)
    if axis_name == "-z":
        return (1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)
    if axis_name == "z":
        return (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    axis = H.scale((1.0, -2.0, 3.0) if axis_name == "oblique" else
                   (rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)), 1.0)
    axis = H.scale(axis, 1 / H.norm(axis))
    e1 = H.cross(axis, (0.0, 0.0, 1.0) if abs(axis[2]) < 0.9 else (1.0, 0.0, 0.0))
    e1 = H.scale(e1, 1 / H.norm(e1))
    return e1, H.cross(axis, e1), axis


def place(p, fr, offset):
    e1, e2, ax = fr
    return H.add(H.add(H.add(H.scale(e1, p[0]), H.scale(e2, p[1])), H.scale(ax, p[2])), offset)


# ---------------------------------------------------------------------------------------------
# One phantom case


def phantom(name, shape, sax_z, ring_points=60, lax=(), lax_mode="both", lax_top=None,
            lax_points=60, start=0.0, start_mode="same", clockwise=False, axis="z",
            offset=(0.0, 0.0, 0.0), integer=False, extra_rings=(), args=(), c2m=0.5, rng=None,
            surface_name="LV_ENDO", expect="ok", twin_lax=False, close_dup=False, ring_shape=None):
    rng = rng or random.Random(0)
    fr = frame(axis, rng)
    if ring_shape is not None:  # a polygonal section: its area scales with r(z)^2
        unit = abs(sum(p[0] * q[1] - q[0] * p[1]
                       for p, q in zip(ring_shape, ring_shape[1:] + ring_shape[:1]))) / 2
        shape = Shape(shape.name, shape.r, shape.z_apex, shape.z_max, shape.profile,
                      lambda z: unit * shape.r(z) ** 2)
    blocks = []
    for k, z in enumerate(sax_z):
        s = start if start_mode == "same" else rng.uniform(0, TAU)
        if shape.name.startswith("crescent"):
            ring = crescent_ring(shape, z, ring_points, s)
        elif ring_shape is not None:
            ring = [(x * shape.r(z), y * shape.r(z), z) for x, y in ring_shape]
        else:
            ring = sax_ring(shape, z, ring_points, s, clockwise if clockwise != "alt" else k % 2)
        if close_dup:
            ring = ring + ring[:1]  # the first point repeated at the end
        blocks.append((f"SAX_{k}", surface_name, ring))
    for k, ring in enumerate(extra_rings):
        blocks.append((f"SAX_x{k}", surface_name, ring))
    top = max(sax_z) if lax_top is None else lax_top
    for j, phi in enumerate(lax):
        blocks.append((f"LAX_{j}", surface_name, lax_curve(shape, phi, top, lax_points, lax_mode)))
        if twin_lax:
            blocks.append((f"LAX_{j}b", surface_name, lax_curve(shape, phi, top, lax_points, lax_mode)))
    placed = [(cid, s, [place(p, fr, offset) for p in pts]) for cid, s, pts in blocks]
    fmt = "{:.0f}" if integer else "{:.17g}"
    data = H.write_csv(placed, fmt=fmt)
    local = [p for _, _, pts in blocks for p in pts]
    z_lo = min(p[2] for p in local)
    z_hi = max(p[2] for p in local)
    case = H.Case("ph-" + name, data, args=args, expect=expect, c2m=c2m,
                  open_mesh="none" in args)
    case.phantom = {"shape": shape, "frame": fr, "offset": offset, "z_lo": z_lo, "z_hi": z_hi}
    return case


def named_cases():
    """The brief's families, each with the exact coincidence it names."""
    cases = []
    e = ellipsoid(25.0, 60.0)
    sax8 = [-48.0, -40.0, -32.0, -24.0, -16.0, -8.0, 0.0]
    add = cases.append
    # Ellipsoid LV: LAX ending exactly at the top plane, at the apex tip, beyond, short of both.
    add(phantom("ell-lax-top", e, sax8, lax=(0.3, 1.9)))
    add(phantom("ell-lax-apex-only", e, sax8, lax=(0.3, 1.9), lax_mode="apex"))
    add(phantom("ell-lax-beyond", ellipsoid(25.0, 60.0, 20.0), sax8, lax=(0.3, 1.9), lax_top=20.0))
    add(phantom("ell-lax-short", e, sax8, lax=(0.3, 1.9), lax_mode="short"))
    add(phantom("ell-no-lax", e, sax8))
    add(phantom("ell-no-lax-lids-none", e, sax8, args=["--lids", "none"]))
    add(phantom("ell-lax-top-lids-none", e, sax8, lax=(0.3, 1.9), args=["--lids", "none"]))
    add(phantom("ell-one-lax", e, sax8, lax=(0.0,)))
    add(phantom("ell-four-lax", e, sax8, lax=(0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4)))
    # LAX planes through ring vertices exactly, coincident LAX, exactly 90 degrees apart.
    add(phantom("ell-lax-through-vertices", e, sax8, ring_points=60, lax=(0.0, TAU * 15 / 60)))
    add(phantom("ell-lax-coincident", e, sax8, lax=(0.7,), twin_lax=True))
    add(phantom("ell-lax-same-plane-opposite", e, sax8, lax=(0.7, 0.7 + math.pi)))
    add(phantom("ell-lax-90", e, sax8, lax=(0.0, math.pi / 2)))
    # A SAX plane through the apex tip (a ring of radius 0), through the equator, beyond it.
    add(phantom("ell-sax-at-apex-ring0", e, [-60.0] + sax8, lax=(0.3, 1.9), expect="any"))
    add(phantom("ell-sax-at-apex-point", e, sax8, lax=(0.3, 1.9), expect="any",
                extra_rings=[[(0.0, 0.0, -60.0)]]))
    sph = ellipsoid(30.0, 30.0, 20.0)
    add(phantom("sphere-past-equator", sph, [-20.0, -10.0, 0.0, 10.0, 20.0], lax=(0.0, math.pi / 2),
                lax_top=20.0))
    add(phantom("sphere-sax-only", sph, [-20.0, -10.0, 0.0, 10.0, 20.0]))
    add(phantom("oblate", ellipsoid(40.0, 20.0), [-16.0, -12.0, -8.0, -4.0, 0.0], lax=(0.0, 1.0)))
    add(phantom("prolate-thin", ellipsoid(8.0, 70.0), [-60.0 + 10 * i for i in range(7)],
                lax=(0.0, 1.0)))
    # Cylinders (identical rings, straight LAX), flat bottom, cones, truncated cones, a U.
    cyl = polyline_shape("cylinder", [(20.0, 40.0), (20.0, 0.0), (0.0, 0.0)], 0.0)
    add(phantom("cylinder-sax-only", cyl, [0.0, 10.0, 20.0, 30.0, 40.0]))
    add(phantom("cylinder-lax-u", cyl, [0.0, 10.0, 20.0, 30.0, 40.0], lax=(0.0, math.pi / 2)))
    add(phantom("cylinder-lax-u-above-bottom", cyl, [10.0, 20.0, 30.0, 40.0], lax=(0.0, 1.0)))
    cone = polyline_shape("cone", [(25.0, 50.0), (0.0, 0.0)], 0.0)
    add(phantom("cone", cone, [10.0, 20.0, 30.0, 40.0, 50.0], lax=(0.0, math.pi / 2)))
    add(phantom("cone-sax-only", cone, [10.0, 20.0, 30.0, 40.0, 50.0]))
    trunc = polyline_shape("truncated-cone", [(30.0, 40.0), (12.0, 0.0), (0.0, 0.0)], 0.0)
    add(phantom("truncated-cone", trunc, [0.0, 10.0, 20.0, 30.0, 40.0], lax=(0.0, 1.0)))
    u = capsule(20.0, 30.0)
    add(phantom("capsule-u", u, [-10.0, 0.0, 10.0, 20.0, 30.0], lax=(0.0, math.pi / 2)))
    # Ordering and symmetry: clockwise rings, alternating, same start angle, random starts.
    add(phantom("ell-clockwise", e, sax8, lax=(0.3, 1.9), clockwise=True))
    add(phantom("ell-alternating-winding", e, sax8, lax=(0.3, 1.9), clockwise="alt"))
    add(phantom("ell-random-starts", e, sax8, lax=(0.3, 1.9), start_mode="random"))
    add(phantom("ell-8-points", e, sax8, ring_points=8, lax=(0.3, 1.9), lax_points=12, c2m=0.8))
    add(phantom("ell-200-points", e, sax8, ring_points=200, lax=(0.3, 1.9), lax_points=200))
    # RV-like crescents (arc + straight septum), with an open long-axis curve over the free wall.
    cr = crescent(35.0, 12.0, 60.0)
    add(phantom("rv-crescent", cr, [-40.0, -30.0, -20.0, -10.0, 0.0], surface_name="RV_ENDO",
                c2m=0.8))
    # Axes and offsets with exact geometry; integer coordinates.
    for ax in ("x", "y", "-z", "oblique"):
        add(phantom(f"ell-axis-{ax}", e, sax8, lax=(0.3, 1.9), axis=ax))
    add(phantom("ell-offset-1e3", e, sax8, lax=(0.3, 1.9), offset=(1e3, -1e3, 1e3)))
    add(phantom("ell-offset-1e5", e, sax8, lax=(0.3, 1.9), offset=(1e5, 1e5, -1e5)))
    add(phantom("ell-offset-1e5-oblique", e, sax8, lax=(0.3, 1.9), axis="oblique",
                offset=(-1e5, 3e4, 1e5)))
    add(phantom("ell-integer", ellipsoid(40.0, 80.0), [-70.0 + 10 * i for i in range(8)],
                lax=(0.0, math.pi / 2), integer=True, c2m=0.8))
    add(phantom("ell-tiny-5mm", ellipsoid(5.0, 12.0), [-10.0, -8.0, -6.0, -4.0, -2.0, 0.0],
                lax=(0.0, 1.0), c2m=0.2))
    add(phantom("ell-large-80mm", ellipsoid(80.0, 150.0),
                [-140.0 + 10 * i for i in range(15)], lax=(0.0, 1.0, 2.0, 2.6)))
    # Listing conventions and more exact coincidences.
    add(phantom("ell-rings-repeat-first-point", e, sax8, lax=(0.3, 1.9), close_dup=True))
    add(phantom("ell-lax-closed-across-top", e, sax8, lax=(0.3, 1.9), lax_mode="closed"))
    add(phantom("ell-integer-small", ellipsoid(8.0, 20.0), [-16.0, -12.0, -8.0, -4.0, 0.0],
                lax=(0.0, math.pi / 2), integer=True, c2m=0.8, expect="any"))
    add(phantom("ell-duplicate-slice", e, sax8 + [-24.0], lax=(0.3, 1.9), ring_points=60))
    add(phantom("ell-lax-ends-mid-slice", e, sax8, lax=(0.3, 1.9), lax_top=-24.0))
    full = ellipsoid(30.0, 30.0, 30.0)
    add(phantom("sphere-both-poles-rings", full, [-30.0, -20.0, -10.0, 0.0, 10.0, 20.0, 30.0],
                expect="any"))
    add(phantom("sphere-both-poles-lax", full, [-20.0, -10.0, 0.0, 10.0, 20.0],
                lax=(0.0, math.pi / 2), lax_top=30.0))
    box = polyline_shape("cuboid", [(20.0, 40.0), (20.0, 0.0), (0.0, 0.0)], 0.0)
    square = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
    add(phantom("cuboid-4-point-rings", box, [0.0, 10.0, 20.0, 30.0, 40.0], ring_shape=square, c2m=1.5))
    tri = [(math.cos(a), math.sin(a)) for a in (0.0, TAU / 3, 2 * TAU / 3)]
    add(phantom("prism-3-point-rings", box, [0.0, 10.0, 20.0, 30.0, 40.0], ring_shape=tri, c2m=1.5))
    add(phantom("ell-two-sax", e, [-24.0, 0.0], lax=(0.3, 1.9), expect="any"))
    add(phantom("ell-two-sax-no-lax", e, [-24.0, 0.0], expect="any"))
    return cases


def random_cases(count, rng):
    """Seeded variations over the same families: sizes 5-80 mm, 3-15 slices, 0-4 LAX, 8-200
    points per ring, LAX end modes, windings, axes and offsets."""
    cases = []
    for k in range(count):
        radius = rng.uniform(5.0, 80.0)
        family = rng.choice(["ellipsoid", "sphere", "cylinder", "cone", "capsule"])
        nsax = rng.randint(3, 15)
        if family in ("ellipsoid", "sphere"):
            c = radius if family == "sphere" else radius * rng.uniform(0.5, 3.0)
            shape = ellipsoid(radius, c)
            lo, hi = -c * rng.uniform(0.6, 0.95), 0.0
        elif family == "cylinder":
            h = radius * rng.uniform(1.0, 3.0)
            shape = polyline_shape("cylinder", [(radius, h), (radius, 0.0), (0.0, 0.0)], 0.0)
            lo, hi = 0.0, h
        elif family == "cone":
            h = radius * rng.uniform(1.0, 3.0)
            shape = polyline_shape("cone", [(radius, h), (0.0, 0.0)], 0.0)
            lo, hi = h * 0.15, h
        else:
            h = radius * rng.uniform(0.5, 2.0)
            shape = capsule(radius, h)
            lo, hi = -radius * 0.6, h
        step = (hi - lo) / (nsax - 1)
        sax_z = [lo + i * step for i in range(nsax)]
        nlax = rng.randint(0, 4)
        lax = [rng.choice([rng.uniform(0, math.pi), math.pi * rng.randint(0, 7) / 8])
               for _ in range(nlax)]
        cases.append(phantom(
            f"rnd{k:03d}-{family}-r{radius:.0f}-s{nsax}-l{nlax}", shape, sax_z,
            ring_points=rng.randint(8, 200), lax=lax,
            lax_mode=rng.choice(["both", "both", "apex", "short"]),
            lax_points=rng.randint(8, 200), start_mode=rng.choice(["same", "random"]),
            clockwise=rng.choice([False, True, "alt"]),
            axis=rng.choice(["z", "x", "y", "-z", "oblique", "random"]),
            offset=rng.choice([(0.0, 0.0, 0.0), (1e3, -2e3, 5e2), (1e5, 1e5, -1e5)]),
            c2m=max(0.5, 0.02 * radius), rng=rng))
    return cases


# ---------------------------------------------------------------------------------------------
# Judging the phantom-specific numbers


def read_obj_vertices(path):
    out = []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                out.append(tuple(float(v) for v in line.split()[1:4]))
    return out


def check(case, cdir):
    """Folds, how far the mesh runs past the data along the axis, and the volume against the
    analytic volume between the lowest and highest data (the part past the data is extrapolated:
    allowed up to the shape's own section there times the overrun, plus 8%)."""
    info = getattr(case, "phantom", None)
    report = os.path.join(cdir, "r.json")
    mesh = os.path.join(cdir, "out.obj")
    if info is None or not os.path.exists(report) or not os.path.exists(mesh):
        return [], ""
    with open(report) as f:
        rep = json.load(f)
    problems = []
    folds = rep.get("quality", {}).get("folded_edges", 0)
    if folds:
        problems.append("FOLD")
    axis, offset, shape = info["frame"][2], info["offset"], info["shape"]
    heights = [H.dot(H.sub(v, offset), axis) for v in read_obj_vertices(mesh)]
    if not heights:
        return problems, ""
    over_top = max(heights) - info["z_hi"]
    below = info["z_lo"] - min(heights)
    detail = f"; past data top {over_top:+.1f} apex {below:+.1f} mm"
    if case.open_mesh:
        return problems, detail
    truth = shape.volume(info["z_lo"], info["z_hi"]) / 1000
    vol = rep.get("volume_ml", 0.0)
    extrapolated = (shape.area(info["z_hi"]) * max(0.0, over_top) +
                    shape.area(info["z_lo"]) * max(0.0, below)) / 1000
    detail += f"; analytic {truth:.4g} ml (+{extrapolated:.3g} past data)"
    if not (truth * 0.92 - 0.05 <= vol <= (truth + extrapolated) * 1.08 + 0.05):
        problems.append("VOL")
    if folds:
        detail += f"; {folds} folded edges"
    return problems, detail


def main():
    argv = sys.argv[1:]
    out_dir, seed, only, timeout, count, extra = "/tmp/phantoms", 9, None, 60, 40, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--seed", "--only", "--timeout", "--random", "--args"):
            v = argv[i + 1]
            i += 2
            if a == "--seed":
                seed = int(v)
            elif a == "--only":
                only = v
            elif a == "--timeout":
                timeout = float(v)
            elif a == "--random":
                count = int(v)
            else:
                extra = v.split()
        elif a.startswith("-"):
            return H.usage(a, __doc__)
        else:
            out_dir = a
            i += 1
    os.makedirs(out_dir, exist_ok=True)
    rng = random.Random(seed)
    cases = named_cases() + random_cases(count, rng)
    for c in cases:
        c.args = H.merge_args(c.args, extra)
        c.open_mesh = "none" in c.args
    bad = H.run_cases(cases, out_dir, timeout, only, check)
    print(f"{bad} case(s) with problems")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
