#!/usr/bin/env python3
"""Writes biv-me's patient 1 as a Segment (Medviso) study file, so that the Segment reader can be
checked against contours whose millimetre positions are known:

    python3 scripts/segment_fixture.py ../shared/data/contours/bivme-example-patient1 OUT_DIR

OUT_DIR/patient1.mat is a level-5 MAT-file as Segment's File > Save all saves it by default
(`save(..., 'preview', 'info', 'im', 'setstruct', '-v7')`: each variable zlib-compressed), its
`setstruct` a 1x5 struct array of image stacks:
- stack 1, the short-axis cine: the five SAX slices of the SliceInfoFile are one stack (they share
  an orientation and lie 17.7 mm apart along the normal: SliceThickness 8 + SliceGap 9.7), 20
  frames, end-diastole frame 1 (GPFile_000.txt), end-systole frame 10 (GPFile_009.txt), with an
  `IM` of 192 x 192 x 20 x 5 singles the reader must skip unread;
- stacks 2-5, the four long-axis views (one slice each), ImageViewPlane 2CH/3CH/4CH/RVOT;
- EndoX/EndoY, EpiX/EpiY and RVEndoX/RVEndoY as Segment keeps them: 80 x TSize x ZSize doubles,
  NaN where nothing is drawn, each curve resampled to 79 points along its closed outline with its
  first point repeated as the 80th; x is the row (along ImageOrientation(4:6)) and y the column
  (along ImageOrientation(1:3)), both from 1. The SAX epicardium is the GPFile's LV epicardium
  closed over the septum by its RV septum curve, the RV endocardium its free wall and septum joined;
  long-axis curves are closed across their valve, as Segment's are;
- `Point`: each SAX slice's two RV insertions at end-diastole labelled `RV insertion`, one of them
  at T = NaN (placed in all frames);
- a sixth stack without contours (a scout) and a rotated stack with one curve the reader must skip.

OUT_DIR/expected-ED.csv and expected-ES.csv hold the same curves in patient millimetres (79
points each, no repeat), placed with Segment's conversion (calcfunctions xyz2rlapfh) written
independently here. The output is committed (tests read it); rerun only to change it.
"""
import math
import os
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cvi42_fixture import dist, dot, joined, read_gp, read_slices  # noqa: E402

FRAMES = 20
ED, ES = 0, 9
POINTS = 80
STEP = 17.7  # mm between the SAX slices (8 + 9.7)
VIEWS = {7: "2CH", 8: "3CH", 9: "4CH", 11: "RVOT"}

# MAT-file element and class codes (MathWorks, "MAT-File Format", level 5).
MI_INT8, MI_UINT8, MI_UINT16, MI_INT32, MI_UINT32 = 1, 2, 4, 5, 6
MI_SINGLE, MI_DOUBLE, MI_MATRIX, MI_COMPRESSED = 7, 9, 14, 15
MX_CELL, MX_STRUCT, MX_CHAR, MX_DOUBLE, MX_SINGLE, MX_UINT8 = 1, 2, 4, 6, 7, 9


def element(ty, data):
    if 0 < len(data) <= 4 and ty != MI_MATRIX:
        return struct.pack("<HH", ty, len(data)) + data + b"\0" * (4 - len(data))
    pad = (-len(data)) % 8
    return struct.pack("<II", ty, len(data)) + data + b"\0" * pad


def matrix(name, cls, dims, content, logical=False):
    flags = struct.pack("<II", cls | ((0x02 if logical else 0) << 8), 0)
    body = element(MI_UINT32, flags)
    body += element(MI_INT32, struct.pack(f"<{len(dims)}i", *dims))
    body += element(MI_INT8, name.encode())
    body += content
    return struct.pack("<II", MI_MATRIX, len(body)) + body


def doubles(values, dims, name=""):
    values = list(values)
    # MATLAB stores doubles that are small non-negative integers as uint8: so do we, sometimes.
    if values and all(v == v and v == int(v) and 0 <= v < 256 for v in values):
        return matrix(name, MX_DOUBLE, dims, element(MI_UINT8, bytes(int(v) for v in values)))
    return matrix(name, MX_DOUBLE, dims, element(MI_DOUBLE, struct.pack(f"<{len(values)}d", *values)))


def empty(name=""):
    return matrix(name, MX_DOUBLE, [0, 0], element(MI_DOUBLE, b""))


def text(s, name=""):
    units = s.encode("utf-16-le")
    return matrix(name, MX_CHAR, [1, len(s)], element(MI_UINT16, units))


def logical(v, name=""):
    return matrix(name, MX_UINT8, [1, 1], element(MI_UINT8, bytes([1 if v else 0])), logical=True)


def cell(items, dims, name=""):
    return matrix(name, MX_CELL, dims, b"".join(items))


def struct_array(fields, elements, name=""):
    """A 1xK struct array: `elements` is a list of {field: encoded value (no name)}."""
    width = 32
    names = b"".join(f.encode().ljust(width, b"\0") for f in fields)
    content = element(MI_INT32, struct.pack("<i", width)) + element(MI_INT8, names)
    for e in elements:
        content += b"".join(e[f] for f in fields)
    return matrix(name, MX_STRUCT, [1, len(elements)], content)


def mat_file(variables):
    head = b"MATLAB 5.0 MAT-file, Platform: PCWIN64, Created on: Sat Dec  5 12:00:00 2026"
    out = head.ljust(116, b" ") + b"\0" * 8 + struct.pack("<H", 0x0100) + b"IM"
    for v in variables:
        z = zlib.compress(v)
        out += struct.pack("<II", MI_COMPRESSED, len(z)) + z
    return out


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def resampled(curve, n):
    """n points along the closed outline of `curve`, from its first point, equally spaced."""
    ring = curve + [curve[0]]
    lengths = [dist(a, b) for a, b in zip(ring, ring[1:])]
    total = sum(lengths)
    out, k, walked = [], 0, 0.0
    for i in range(n):
        target = total * i / n
        while walked + lengths[k] < target:
            walked += lengths[k]
            k += 1
        t = (target - walked) / lengths[k] if lengths[k] else 0.0
        out.append([a + (b - a) * t for a, b in zip(ring[k], ring[k + 1])])
    return out


class Stack:
    def __init__(self, position, row, col, spacing, slices, view):
        self.position, self.row, self.col = position, row, col
        self.normal = cross(row, col)
        self.spacing, self.slices, self.view = spacing, slices, view
        self.curves = {}  # kind -> {(frame, slice): [[x, y], ...]}

    def origin(self, z):
        return [p - n * z * STEP for p, n in zip(self.position, self.normal)]

    def pixels(self, points, z):
        o = self.origin(z)
        out = []
        for p in points:
            d = [a - b for a, b in zip(p, o)]
            out.append([dot(d, self.col) / self.spacing[0] + 1, dot(d, self.row) / self.spacing[1] + 1])
        return out

    def mm(self, xy, z):
        """Segment's xyz2rlapfh: ImagePosition + (x-1) ResX IO(4:6) + (y-1) ResY IO(1:3) - (z-1) step zdir."""
        x, y = xy
        return [
            p + (x - 1) * self.spacing[0] * c + (y - 1) * self.spacing[1] * r - z * STEP * n
            for p, r, c, n in zip(self.position, self.row, self.col, self.normal)
        ]

    def draw(self, kind, frame, z, curve):
        px = self.pixels(resampled(curve, POINTS - 1), z)
        self.curves.setdefault(kind, {})[(frame, z)] = px + [px[0]]

    def arrays(self):
        out = {}
        for kind in ("Endo", "Epi", "RVEndo", "RVEpi"):
            drawn = self.curves.get(kind)
            if not drawn:
                out[kind + "X"] = out[kind + "Y"] = empty()
                continue
            dims = [POINTS, FRAMES, self.slices] if self.slices > 1 else [POINTS, FRAMES]
            for axis in (0, 1):
                values = []
                for z in range(self.slices):
                    for t in range(FRAMES):
                        pts = drawn.get((t, z))
                        values += [p[axis] for p in pts] if pts else [math.nan] * POINTS
                out[kind + "XY"[axis]] = doubles(values, dims)
        return out


def main(src, out):
    slices = read_slices(os.path.join(src, "SliceInfoFile.txt"))
    gps = {ED: read_gp(os.path.join(src, "GPFile_000.txt")), ES: read_gp(os.path.join(src, "GPFile_009.txt"))}
    sax = sorted({sid for gp in gps.values() for sid, kind in gp if kind.startswith("SAX_")})
    first = slices[sax[0]]
    stacks = [Stack(first["position"], first["row"], first["col"], first["spacing"], len(sax), "Short-axis")]
    for k, sid in enumerate(sax):
        o = stacks[0].origin(k)
        assert dist(o, slices[sid]["position"]) < 0.05, (sid, o, slices[sid]["position"])
    lax = sorted({sid for gp in gps.values() for sid, kind in gp if kind.startswith("LAX_")})
    for sid in lax:
        s = slices[sid]
        stacks.append(Stack(s["position"], s["row"], s["col"], s["spacing"], 1, VIEWS[sid]))
    expected = {ED: [], ES: []}
    points = []  # (x, y, z, t, label) of stack 1
    for frame, gp in gps.items():
        for sid in sax + lax:
            stack = stacks[0] if sid in sax else stacks[1 + lax.index(sid)]
            z = sax.index(sid) if sid in sax else 0
            view = "SAX" if sid in sax else "LAX"
            curves = {"Endo": gp.get((sid, f"{view}_LV_ENDOCARDIAL"))}
            fw, septum = gp.get((sid, f"{view}_RV_FREEWALL")), gp.get((sid, f"{view}_RV_SEPTUM"))
            if fw and septum:
                curves["RVEndo"] = joined(fw, septum, True)
            epi = gp.get((sid, f"{view}_LV_EPICARDIAL"))
            if view == "SAX" and epi and septum:
                curves["Epi"] = joined(epi, septum, True)
            for kind, curve in curves.items():
                if not curve:
                    continue
                stack.draw(kind, frame, z, curve)
                surface = {"Endo": "LV_ENDO", "Epi": "LV_EPI", "RVEndo": "RV_ENDO"}[kind]
                for xy in stack.curves[kind][(frame, z)][:-1]:
                    expected[frame].append((f"{stack.view}_{z + 1}_{kind}", stack.mm(xy, z), surface))
            inserts = gp.get((sid, "RV_INSERT"))
            if frame == ED and sid in sax and inserts:
                for i, p in enumerate(inserts):
                    x, y = stacks[0].pixels([p], z)[0]
                    points.append((x, y, z + 1, math.nan if (z == 0 and i == 0) else ED + 1, "RV insertion"))
    for frame, rows in expected.items():
        with open(os.path.join(out, f"expected-{'ED' if frame == ED else 'ES'}.csv"), "w") as f:
            f.write("contour,x,y,z,surface\n")
            for cid, p, surface in rows:
                f.write(f"{cid},{p[0]:.9f},{p[1]:.9f},{p[2]:.9f},{surface}\n")
    # A scout without contours and a rotated (radial) stack with one curve: both skipped.
    scout = Stack(first["position"], [1, 0, 0], [0, 1, 0], [1.5, 1.5], 1, "Coronal")
    radial = Stack(first["position"], first["row"], first["col"], first["spacing"], 1, "2CH")
    radial.curves["Endo"] = {(0, 0): [[40 + 10 * math.cos(a / 12), 40 + 10 * math.sin(a / 12)] for a in range(POINTS)]}
    fields = [
        "IM", "ImagePosition", "ImageOrientation", "ResolutionX", "ResolutionY", "SliceThickness",
        "SliceGap", "TSize", "ZSize", "XSize", "YSize", "TIncr", "EDT", "EST", "ImageViewPlane",
        "ImageType", "SeriesDescription", "Rotated", "EndoX", "EndoY", "EpiX", "EpiY", "RVEndoX",
        "RVEndoY", "RVEpiX", "RVEpiY", "EndoPinX", "Point", "ProgramVersion",
    ]
    elements = []
    for k, s in enumerate(stacks + [scout, radial]):
        xs = ys = 192
        if k == 0:
            n = xs * ys * FRAMES * s.slices
            im = matrix("", MX_SINGLE, [xs, ys, FRAMES, s.slices], element(MI_SINGLE, struct.pack(f"<{n}f", *([0.25] * n))))
        else:
            im = matrix("", MX_SINGLE, [xs, ys, FRAMES], element(MI_SINGLE, b"\0" * (4 * xs * ys * FRAMES)))
        if k == 0:
            cols = list(zip(*points))
            point = struct_array(
                ["X", "Y", "Z", "T", "Label"],
                [{
                    "X": doubles(cols[0], [1, len(points)]),
                    "Y": doubles(cols[1], [1, len(points)]),
                    "Z": doubles(cols[2], [1, len(points)]),
                    "T": doubles(cols[3], [1, len(points)]),
                    "Label": cell([text(lab) for lab in cols[4]], [1, len(points)]),
                }],
            )
        else:
            point = struct_array(["X", "Y", "Z", "T", "Label"], [{f: empty() for f in "XYZT"} | {"Label": cell([], [0, 0])}])
        e = {
            "IM": im,
            "ImagePosition": doubles(s.position, [1, 3]),
            "ImageOrientation": doubles(s.row + s.col, [1, 6]),
            "ResolutionX": doubles([s.spacing[0]], [1, 1]),
            "ResolutionY": doubles([s.spacing[1]], [1, 1]),
            "SliceThickness": doubles([8.0], [1, 1]),
            "SliceGap": doubles([STEP - 8.0], [1, 1]),
            "TSize": doubles([FRAMES], [1, 1]),
            "ZSize": doubles([s.slices], [1, 1]),
            "XSize": doubles([xs], [1, 1]),
            "YSize": doubles([ys], [1, 1]),
            "TIncr": doubles([0.045], [1, 1]),
            "EDT": doubles([ED + 1], [1, 1]),
            "EST": doubles([ES + 1], [1, 1]),
            "ImageViewPlane": text(s.view),
            "ImageType": text("Cine"),
            "SeriesDescription": text(f"cine {s.view}"),
            "Rotated": logical(s is radial),
            "EndoPinX": cell([], [0, 0]),
            "Point": point,
            "ProgramVersion": text("4.0 R12067"),
        }
        for f, v in s.arrays().items():
            e[f] = v
        elements.append(e)
    info = struct_array(["Name", "ID", "NFrames"], [{"Name": text("Patient 1"), "ID": text("P1"), "NFrames": doubles([0], [1, 1])}], "info")
    variables = [
        matrix("preview", MX_UINT8, [4, 4], element(MI_UINT8, bytes(range(16)))),
        info,
        empty("im"),
        struct_array(fields, elements, "setstruct"),
    ]
    with open(os.path.join(out, "patient1.mat"), "wb") as f:
        f.write(mat_file(variables))


if __name__ == "__main__":
    os.makedirs(sys.argv[2], exist_ok=True)
    main(sys.argv[1], sys.argv[2])
