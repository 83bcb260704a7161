#!/usr/bin/env python3
"""Writes biv-me's patient 1 as a case of the Sunnybrook Cardiac Data is laid out, so that the
Sunnybrook reader can be checked against contours whose millimetre positions are known:

    python3 scripts/sunnybrook_fixture.py ../shared/data/contours/bivme-example-patient1 OUT_DIR

OUT_DIR/contours-manual/IRCCI-expert/IM-0001-NNNN-{i,o,p1}contour-manual.txt: the short-axis LV
endocardium (frames 0 and 9) and epicardium (frame 0 only, as the data's experts drew it) of
GPFile_000.txt / GPFile_009.txt, one file per image and type, `x y` in pixels with two decimals
(column, row, 0 at the first pixel's centre), and one papillary muscle the reader must skip.
NNNN is the image's number in the cine short-axis series: slice k (1 = the first SAX slice of the
SliceInfoFile), frame f (0-19) is image 20 (k - 1) + f + 1. OUT_DIR/CINESAX_300/IM-0003-NNNN.dcm
holds one header-only MR image per slice and frame (series 300, Instance Number NNNN, trigger time
40 ms apart): the contours' `0001` is not the images' series, as in the data. OUT_DIR/CINE2CH_400/
IM-0004-NNNN.dcm is a long-axis cine series numbered 1-20 like the first short-axis slice: the
reader must pick the short-axis series by the numbers it holds. The output is committed (tests read
it); rerun only to change it.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cvi42_fixture import dicom, dot, read_gp, read_slices  # noqa: E402

FRAMES = 20
TYPES = {"SAX_LV_ENDOCARDIAL": "icontour", "SAX_LV_EPICARDIAL": "ocontour"}


def pixels(points, s):
    out = []
    for p in points:
        d = [a - b for a, b in zip(p, s["position"])]
        out.append((dot(d, s["row"]) / s["spacing"][1], dot(d, s["col"]) / s["spacing"][0]))
    return out


def write_contour(path, px):
    with open(path, "w") as f:
        for x, y in px:
            f.write(f"{x:.2f} {y:.2f}\n")


def main(src, out):
    slices = read_slices(os.path.join(src, "SliceInfoFile.txt"))
    gps = {0: read_gp(os.path.join(src, "GPFile_000.txt")), 9: read_gp(os.path.join(src, "GPFile_009.txt"))}
    sax = sorted({sid for gp in gps.values() for sid, kind in gp if kind.startswith("SAX_")})
    lax = sorted({sid for gp in gps.values() for sid, kind in gp if kind.startswith("LAX_")})
    contours = os.path.join(out, "contours-manual", "IRCCI-expert")
    images = os.path.join(out, "CINESAX_300")
    os.makedirs(contours, exist_ok=True)
    os.makedirs(images, exist_ok=True)
    number = lambda k, frame: (k - 1) * FRAMES + frame + 1  # noqa: E731
    for k, sid in enumerate(sax, start=1):
        for frame, gp in gps.items():
            for kind, name in TYPES.items():
                pts = gp.get((sid, kind))
                if pts is None or (name == "ocontour" and frame != 0):
                    continue
                n = number(k, frame)
                write_contour(os.path.join(contours, f"IM-0001-{n:04d}-{name}-manual.txt"), pixels(pts, slices[sid]))
            if frame == 0 and k == 2:
                endo = gp[(sid, "SAX_LV_ENDOCARDIAL")][::6]
                n = number(k, frame)
                write_contour(os.path.join(contours, f"IM-0001-{n:04d}-p1contour-manual.txt"), pixels(endo, slices[sid]))
        for frame in range(FRAMES):
            n = number(k, frame)
            uid = f"{slices[sid]['uid']}.{frame + 1}"
            with open(os.path.join(images, f"IM-0003-{n:04d}.dcm"), "wb") as f:
                f.write(dicom(uid, slices[sid], 300, "CINESAX", n, 40.0 * frame))
    two = os.path.join(out, "CINE2CH_400")
    os.makedirs(two, exist_ok=True)
    for frame in range(FRAMES):
        s = slices[lax[0]]
        with open(os.path.join(two, f"IM-0004-{frame + 1:04d}.dcm"), "wb") as f:
            f.write(dicom(f"{s['uid']}.{frame + 1}", s, 400, "CINE2CH", frame + 1, 40.0 * frame))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
