#!/usr/bin/env python3
"""Writes biv-me's patient 1 (ED) as a 3D Slicer user would leave it: one markups file per curve,
as Slicer saves each markup node, so that the Slicer markups reader can be checked on real curves
whose dense originals are known:

    python3 scripts/markups_fixture.py ../shared/data/contours/bivme-example-patient1/patient1-ED.csv OUT_DIR

OUT_DIR/<contour>.mrk.json (schema markups-schema-v1.0.3, LPS, mm): each curve of the CSV (every
surface) with a control point every 8 mm of arc along it, as one clicks them in Slicer: a
`ClosedCurve` where the CSV's curve closes (its ends within two spacings), else a `Curve`; where the
CSV's curve jumps (a step over 5x its median spacing: the gaps real files leave) the stretches are
separate markups of the same name, and a curve whose file order starts mid-curve (the jump inside,
its ends together) is one curve from jump to jump. Slicer's display and bookkeeping fields are
written as Slicer writes them (the reader must pass over them). One file holds the RV insertion
points (the ends of slice 4's septum) as a point list (`Fiducial`). The output is committed (tests read it); rerun only to change it.
"""
import csv
import json
import math
import os
import sys

SCHEMA = ("https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/"
          "Resources/Schema/markups-schema-v1.0.3.json#")
STEP = 8.0
JUMP = 5.0


def read_csv(path):
    curves, order = {}, []
    for r in csv.DictReader(open(path)):
        k = r["contour"]
        if k not in curves:
            curves[k] = []
            order.append(k)
        curves[k].append([float(r["x"]), float(r["y"]), float(r["z"])])
    return curves, order


def stretches(p):
    """(control points, closed) per stretch of one curve."""
    gaps = sorted(math.dist(a, b) for a, b in zip(p, p[1:]))
    median = gaps[len(gaps) // 2]
    jump = JUMP * median
    ends = math.dist(p[0], p[-1])
    runs, since = [[p[0]]], 0.0
    for a, b in zip(p, p[1:]):
        d = math.dist(a, b)
        if d > jump:
            if runs[-1][-1] != a:
                runs[-1].append(a)
            runs.append([b])
            since = 0.0
            continue
        since += d
        if since >= STEP:
            runs[-1].append(b)
            since = 0.0
    if runs[-1][-1] != p[-1]:
        runs[-1].append(p[-1])
    closed = len(runs) == 1 and ends <= 2 * median and len(p) >= 3
    if len(runs) > 1 and ends <= jump:
        runs[-1].extend(runs.pop(0))
    if closed and len(runs[0]) > 3 and math.dist(runs[0][-1], p[0]) < STEP / 2:
        runs[0].pop()
    return [(r, closed) for r in runs]


def display():
    return {"visibility": True, "opacity": 1.0, "color": [0.4, 1.0, 1.0],
            "selectedColor": [1.0, 0.5000076295109483, 0.5000076295109483],
            "propertiesLabelVisibility": True, "pointLabelsVisibility": False, "textScale": 3.0,
            "glyphType": "Sphere3D", "glyphScale": 1.0, "glyphSize": 5.0, "useGlyphScale": True,
            "sliceProjection": False, "lineThickness": 0.2, "snapMode": "toVisibleSurface"}


def markup(kind, name, points):
    return {
        "type": kind, "coordinateSystem": "LPS", "coordinateUnits": "mm", "locked": False,
        "fixedNumberOfControlPoints": False, "labelFormat": "%N-%d",
        "lastUsedControlPointNumber": len(points), "name": name,
        "controlPoints": [
            {"id": str(i + 1), "label": f"{name}-{i + 1}", "description": "",
             "associatedNodeID": "", "position": [round(v, 4) for v in q],
             "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0],
             "selected": True, "locked": False, "visibility": True, "positionStatus": "defined"}
            for i, q in enumerate(points)],
        "measurements": [], "display": display(),
    }


def main(src, out):
    os.makedirs(out, exist_ok=True)
    curves, order = read_csv(src)
    for name in order:
        ms = [markup("ClosedCurve" if closed else "Curve", name, run)
              for run, closed in stretches(curves[name])]
        with open(os.path.join(out, f"{name}.mrk.json"), "w") as f:
            json.dump({"@schema": SCHEMA, "markups": ms}, f, indent=1)
            f.write("\n")
    # The RV insertion points, as a point list (the ends of a septum curve: where the RV meets the LV).
    sept = curves["s04_SAX_RV_SEPTUM"]
    points = markup("Fiducial", "RV insertions", [sept[0], sept[-1]])
    for cp in points["controlPoints"]:
        cp["label"] = "RV_INSERT"
    with open(os.path.join(out, "RV insertions.mrk.json"), "w") as f:
        json.dump({"@schema": SCHEMA, "markups": [points]}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
