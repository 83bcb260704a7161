#!/usr/bin/env python3
"""Writes a cvi42 workspace and the DICOM image headers it was "drawn" on from biv-me's patient 1
(GPFile_000.txt = frame 0, GPFile_009.txt = frame 9, SliceInfoFile.txt = the image planes), so
that the cvi42 reader can be checked against contours whose millimetre positions are known.

    python3 scripts/cvi42_fixture.py ../shared/data/contours/bivme-example-patient1 OUT_DIR

OUT_DIR/Contours.cvi42wsx holds every curve in pixel coordinates (SubpixelResolution 8) keyed by
the SOP Instance UID of its image, nested as UK Biobank's workspaces are (StudyMapStates / List:item
/ ImageStates / UID / Contours / TYPE / Points / List:item / Point:x, Point:y); OUT_DIR/dicom/ holds one header-only MR image per slice and time
frame (10 frames per slice, trigger time 40 ms apart, short-axis slices in one series, each
long-axis view in its own); OUT_DIR/zipped/ holds the same as two ZIP archives, the workspace in
one and the images in the other, as UK Biobank hands them out. Curves of the RV endocardium (free wall + septum in the GPFile) are
joined into one curve, as cvi42 draws them (a ring in the short-axis images, the gaps bridged); the
RV insertion landmarks become cvi42's SAX reference points (superior = the more anterior one,
inferior) and the mitral hinges and apex of a long-axis view its LV extent points; a type the reader
must skip (a papillary muscle) is added. The output is committed (tests read it); rerun only to change it.
"""
import os
import struct
import sys
import zipfile


SUB = 8
FRAMES = 10
MR_IMAGE = "1.2.840.10008.5.1.4.1.1.4"
EXPLICIT_LE = "1.2.840.10008.1.2.1"

TYPES = {
    "LV_ENDOCARDIAL": "endocardialContour",
    "LV_EPICARDIAL": "epicardialContour",
    "RV_EPICARDIAL": "rvepicardialContour",
}


def read_slices(path):
    slices = {}
    for line in open(path):
        f = line.split()
        if not f:
            continue
        i = f.index("sliceID:")
        sid = int(f[i + 1])
        p = f.index("ImagePositionPatient")
        o = f.index("ImageOrientationPatient")
        s = f.index("PixelSpacing")
        slices[sid] = dict(
            uid=f[0].removesuffix(".dcm").replace("-", "."),
            position=[float(v) for v in f[p + 1 : p + 4]],
            row=[float(v) for v in f[o + 1 : o + 4]],
            col=[float(v) for v in f[o + 4 : o + 7]],
            spacing=[float(v) for v in f[s + 1 : s + 3]],
        )
    return slices


def read_gp(path):
    curves = {}
    for line in open(path).read().splitlines()[1:]:
        f = line.split("\t")
        if len(f) < 5:
            continue
        key = (int(f[4]), f[3])
        curves.setdefault(key, []).append([float(v) for v in f[:3]])
    return curves


def joined(fw, septum, closed):
    """The free wall and septum as one continuous curve, as cvi42 draws it (a ring in short-axis
    images): GPFiles store some curves in pieces (jumps of 35-45 mm), so the pieces are chained
    end to nearest end, each gap bridged at the curves' spacing."""
    steps = [dist(a, b) for c in (fw, septum) for a, b in zip(c, c[1:])]
    step = sorted(steps)[len(steps) // 2]
    runs = [r for c in (fw, septum) for r in pieces(c, 5 * step)]
    runs.sort(key=len, reverse=True)
    out = runs.pop(0)
    while runs:
        end = out[-1]
        k, flip = min(
            ((k, f) for k in range(len(runs)) for f in (False, True)),
            key=lambda kf: dist(end, runs[kf[0]][-1 if kf[1] else 0]),
        )
        run = runs.pop(k)
        run = run[::-1] if flip else run
        out = out + bridge(end, run[0], step) + run
    return out + bridge(out[-1], out[0], step) if closed else out


def pieces(curve, jump):
    """The runs of a curve between jumps longer than `jump`."""
    out = [[curve[0]]]
    for a, b in zip(curve, curve[1:]):
        if dist(a, b) > jump:
            out.append([])
        out[-1].append(b)
    return out


def bridge(a, b, step):
    """Points strictly between a and b, about `step` apart."""
    n = int(dist(a, b) / step)
    return [[x + (y - x) * k / n for x, y in zip(a, b)] for k in range(1, n)]


def dist(a, b):
    return sum((x - y) ** 2 for x, y in zip(a, b)) ** 0.5


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cvi42_curves(gp):
    out = {}
    for (sid, kind), pts in gp.items():
        view, _, rest = kind.partition("_")
        prefix = {"SAX": "sa", "LAX": "la"}.get(view)
        if prefix is None:
            continue
        if rest in TYPES:
            out[(sid, prefix + TYPES[rest])] = pts
    for sid in {s for s, _ in gp}:
        for view, prefix in (("SAX", "sa"), ("LAX", "la")):
            fw = gp.get((sid, f"{view}_RV_FREEWALL"))
            septum = gp.get((sid, f"{view}_RV_SEPTUM"))
            if fw is not None and septum is not None:
                out[(sid, prefix + "rvendocardialContour")] = joined(fw, septum, view == "SAX")
    return out


def cvi42_points(gp):
    """cvi42's point types from the GPFile's landmarks, by slice: of a slice's two RV insertions
    the more anterior (lower y, LPS) is the superior reference point, the other the inferior one;
    a long-axis view's mitral hinges and apex are its LV extent points."""
    out = {}
    for (sid, kind), pts in gp.items():
        if kind == "RV_INSERT" and len(pts) == 2:
            a, i = sorted(pts, key=lambda p: p[1])
            out.setdefault(sid, []).extend([("sacardialRefPoint", [a]), ("sacardialInferiorRefPoint", [i])])
    for sid in sorted({s for s, k in gp if k in ("MITRAL_VALVE", "APEX_POINT")}):
        extent = gp.get((sid, "MITRAL_VALVE"), []) + gp.get((sid, "APEX_POINT"), [])
        out.setdefault(sid, []).append(("laxLvExtentPoints", extent))
    return out


def pixels(points, s):
    out = []
    for p in points:
        d = [a - b for a, b in zip(p, s["position"])]
        x = dot(d, s["row"]) / s["spacing"][1]
        y = dot(d, s["col"]) / s["spacing"][0]
        out.append((round(x * SUB), round(y * SUB)))
    return out


def uid_of(s, frame):
    return s["uid"] if frame == 0 else f"{s['uid']}.{frame}"


def workspace(images):
    h = "http://www.circlecvi.com/cvi42/Workspace/Hash/"
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<Hash:root xmlns:Hash="{h}" xmlns:Workspace="http://www.circlecvi.com/cvi42/Workspace/"'
        ' xmlns:List="http://www.circlecvi.com/cvi42/Workspace/List/"'
        ' xmlns:Point="http://www.circlecvi.com/cvi42/Workspace/Point/"'
        ' Hash:count="1">',
        ' <Hash:item Hash:key="StudyMapStates" Hash:count="1">',
        "  <List:item>",
        f'   <Hash:item Hash:key="ImageStates" Hash:count="{len(images)}">',
    ]
    for uid, curves in images:
        out.append(f'  <Hash:item Hash:key="{uid}" Hash:count="1">')
        out.append(f'   <Hash:item Hash:key="Contours" Hash:count="{len(curves)}">')
        for kind, px in curves:
            out.append(f'    <Hash:item Hash:key="{kind}" Hash:count="3">')
            out.append(f'     <Hash:item Hash:key="SubpixelResolution">{SUB}</Hash:item>')
            out.append(f'     <Hash:item Hash:key="Label">{kind}</Hash:item>')
            out.append(f'     <Hash:item Hash:key="Points" Hash:count="{len(px)}">')
            for x, y in px:
                out.append(
                    f'      <List:item Point:count="2"><Point:x>{x}</Point:x>'
                    f"<Point:y>{y}</Point:y></List:item>"
                )
            out.append("     </Hash:item>")
            out.append("    </Hash:item>")
        out.append("   </Hash:item>")
        out.append("  </Hash:item>")
    out += ["   </Hash:item>", "  </List:item>", " </Hash:item>", "</Hash:root>", ""]
    return "\n".join(out)


def element(group, elem, vr, value):
    if isinstance(value, str):
        value = value.encode()
        if len(value) % 2:
            value += b"\0" if vr == b"UI" else b" "
    head = struct.pack("<HH", group, elem) + vr
    if vr in (b"OB", b"OW", b"SQ", b"UN", b"UT"):
        return head + b"\0\0" + struct.pack("<I", len(value)) + value
    return head + struct.pack("<H", len(value)) + value


def ds(v):
    return "\\".join(f"{x:.6f}".rstrip("0").rstrip(".") for x in v)


def dicom(uid, s, series, description, instance, trigger):
    meta = b"".join(
        [
            element(0x0002, 0x0001, b"OB", b"\0\1"),
            element(0x0002, 0x0002, b"UI", MR_IMAGE),
            element(0x0002, 0x0003, b"UI", uid),
            element(0x0002, 0x0010, b"UI", EXPLICIT_LE),
        ]
    )
    meta = element(0x0002, 0x0000, b"UL", struct.pack("<I", len(meta))) + meta
    body = b"".join(
        [
            element(0x0008, 0x0016, b"UI", MR_IMAGE),
            element(0x0008, 0x0018, b"UI", uid),
            element(0x0008, 0x0060, b"CS", "MR"),
            element(0x0008, 0x103E, b"LO", description),
            element(0x0018, 0x1060, b"DS", ds([trigger])),
            element(0x0020, 0x0011, b"IS", str(series)),
            element(0x0020, 0x0013, b"IS", str(instance)),
            element(0x0020, 0x0032, b"DS", ds(s["position"])),
            element(0x0020, 0x0037, b"DS", ds(list(s["row"]) + list(s["col"]))),
            element(0x0028, 0x0010, b"US", struct.pack("<H", 2)),
            element(0x0028, 0x0011, b"US", struct.pack("<H", 2)),
            element(0x0028, 0x0030, b"DS", ds(s["spacing"])),
            element(0x0028, 0x0100, b"US", struct.pack("<H", 16)),
            element(0x7FE0, 0x0010, b"OW", bytes(8)),
        ]
    )
    return b"\0" * 128 + b"DICM" + meta + body


def main(src, out):
    slices = read_slices(os.path.join(src, "SliceInfoFile.txt"))
    gps = {0: read_gp(os.path.join(src, "GPFile_000.txt")), 9: read_gp(os.path.join(src, "GPFile_009.txt"))}
    frames = {f: cvi42_curves(gp) for f, gp in gps.items()}
    marks = {f: cvi42_points(gp) for f, gp in gps.items()}
    lax = {sid for f in frames.values() for sid, kind in f if kind.startswith("la")}
    images = []
    for frame, curves in frames.items():
        for sid in sorted(slices):
            mine = [(k, pixels(p, slices[sid])) for (s, k), p in sorted(curves.items()) if s == sid]
            mine += [(k, pixels(p, slices[sid])) for k, p in marks[frame].get(sid, [])]
            if frame == 0 and sid == 3:
                mine.append(("saPapMuscContour", pixels(curves[(3, "saendocardialContour")][::6], slices[sid])))
            if mine:
                images.append((uid_of(slices[sid], frame), mine))
    os.makedirs(os.path.join(out, "dicom"), exist_ok=True)
    with open(os.path.join(out, "Contours.cvi42wsx"), "w") as f:
        f.write(workspace(images))
    for sid, s in sorted(slices.items()):
        series, description = (20 + sid, f"cine LAX {sid}") if sid in lax else (10, "cine SAX")
        for frame in range(FRAMES):
            # Instance numbers run through the series: slice after slice for the stack.
            instance = (sid * FRAMES if series == 10 else 0) + frame + 1
            name = os.path.join(out, "dicom", f"IM_{sid:02d}_{frame:02d}.dcm")
            with open(name, "wb") as f:
                f.write(dicom(uid_of(s, frame), s, series, description, instance, 40.0 * frame))
    # As UK Biobank hands them out: the workspace in one archive, the images in another.
    zips = os.path.join(out, "zipped")
    os.makedirs(zips, exist_ok=True)
    with zipfile.ZipFile(os.path.join(zips, "1000001_cvi42.zip"), "w", zipfile.ZIP_DEFLATED) as z:
        z.write(os.path.join(out, "Contours.cvi42wsx"), "1000001_cvi42.cvi42wsx")
    with zipfile.ZipFile(os.path.join(zips, "1000001_images.zip"), "w", zipfile.ZIP_DEFLATED) as z:
        for name in sorted(os.listdir(os.path.join(out, "dicom"))):
            z.write(os.path.join(out, "dicom", name), "dicom/" + name)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
