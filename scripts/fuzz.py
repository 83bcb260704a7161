#!/usr/bin/env python3
"""Fuzzing the release CLI (session 18): random inputs built from the real contour files, each run
through `heartmesh reconstruct`, one row per input that goes wrong.

  bytes  mutations of real files in every input format (SurFCo CSV and .mat, a biv-me GPFile, and
         the SurFCo contours converted to VTK, VTP, session JSON, RTSTRUCT and XYZ): bytes flipped,
         the file cut, a chunk repeated or deleted, numbers replaced (nan, inf, 1e308, ...), lines
         swapped, NUL runs, long digit runs. Run with --iterations 30 (the readers and the first
         steps are what is under test).
  edits  valid contour CSVs (SurFCo; biv-me patients 1 and 2, ED and ES, each surface) with 1-4
         random edits: contours dropped, moved up to 20 mm, scaled 0.2-2.5 times, rotated out of
         their plane, duplicated, reversed, cut open, subsampled, swapped or merged under one name,
         or damaged values: 1-3 rows thrown 10-150 mm out inside a curve (spike) or at its first
         or last rows (endrow). Run at the defaults.

Flags: EXIT (status other than 0 or 2), PANIC, HANG (60 s / 120 s), VAGUE (exit 2 but not one
stderr line); for `edits` also MESH (exit 0 but not closed, manifold and outward), SELFX (the mesh
passes through itself: expected on strongly contradictory edits, warned to the user) and C2M
(contour-to-mesh mean above 3 mm). Inputs that go wrong are kept in OUT_DIR; the others are
deleted. Standard library only, seeded.

  cvi42  mutations of the cvi42 fixture (heartmesh-core/tests/data/cvi42-patient1): its workspace
         with the images intact, or some or all of its DICOM images with the workspace intact,
         each study run as `reconstruct WORKSPACE IMAGES/ --surface LV_ENDO`.

Usage: scripts/fuzz.py bytes|edits|cvi42 [OUT_DIR] [--seed S] [--count N]
"""

import csv
import json
import math
import os
import random
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile as H  # noqa: E402  (the CLI path and the data folder)

CONTOURS = H.CONTOURS
EDIT_SOURCES = [  # (file under CONTOURS, surface or None)
    ("surfco-example.csv", None),
    ("bivme-example-patient1/patient1-ED.csv", "LV_ENDO"),
    ("bivme-example-patient1/patient1-ED.csv", "RV_ENDO"),
    ("bivme-example-patient1/patient1-ES.csv", "LV_EPI"),
    ("bivme-test-patient2/patient2-ED.csv", "RV_ENDO"),
    ("bivme-test-patient2/patient2-ES.csv", "LV_ENDO"),
]


def cli(args, timeout):
    """(status or None on a hang, stderr text)."""
    try:
        r = subprocess.run([H.BIN] + args, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, ""
    return r.returncode, r.stderr.decode("utf8", "replace")


def verdict(status, err):
    """The flag of a run's status and stderr, or None."""
    if status is None:
        return "HANG"
    if status not in (0, 2):
        return f"EXIT{status}"
    if "panicked" in err:
        return "PANIC"
    if status == 2 and len([line for line in err.splitlines() if line.strip()]) != 1:
        return "VAGUE"
    return None


# ---------------------------------------------------------------------------------------------
# bytes


def byte_seeds(out):
    """The real files, the SurFCo contours in every other format, a DICOM SEG and a Slicer markups
    file (JSON and legacy .fcsv), under OUT/seeds."""
    d = os.path.join(out, "seeds")
    os.makedirs(d, exist_ok=True)
    surfco = os.path.join(CONTOURS, "surfco-example.csv")
    for src in ["surfco-example.csv", "surfco-example.mat", "bivme-example-patient1/GPFile_000.txt"]:
        with open(os.path.join(CONTOURS, src), "rb") as f, open(
            os.path.join(d, os.path.basename(src)), "wb"
        ) as g:
            g.write(f.read())
    for ext in ["vtk", "vtp", "json", "dcm"]:
        cli(["convert", surfco, os.path.join(d, f"s.{ext}"), "--quiet"], 60)
    # A DICOM SEG (the core's fixture: the app's example label map, scripts/seg_fixture.py).
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    seg = os.path.join(repo, "wasm-core/crates/heartmesh-core/tests/data/spasm-seg.dcm")
    with open(seg, "rb") as f, open(os.path.join(d, "spasm-seg.dcm"), "wb") as g:
        g.write(f.read())
    # A 3D Slicer markups file (the core's fixture, scripts/markups_fixture.py): one closed curve.
    mrk = os.path.join(repo, "wasm-core/crates/heartmesh-core/tests/data/slicer-markups-patient1",
                       "s03_SAX_LV_ENDOCARDIAL.mrk.json")
    with open(mrk, "rb") as f, open(os.path.join(d, "s03.mrk.json"), "wb") as g:
        g.write(f.read())
    # The same curve as Slicer 4's point list file (.fcsv, Slicer 5's rows with two extra fields).
    with open(mrk) as f:
        markup = json.load(f)["markups"][0]
    with open(os.path.join(d, "s03.fcsv"), "w") as g:
        g.write("# Markups fiducial file version = 5.6\n# CoordinateSystem = LPS\n"
                "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n")
        for k, p in enumerate(markup["controlPoints"]):
            x, y, z = p["position"]
            g.write(f'{k + 1},{x},{y},{z},0,0,0,1,1,1,0,{p["label"]},"a, note",,2,0\n')
    blocks = H.read_csv(surfco)
    with open(os.path.join(d, "s.xyz.txt"), "w") as g:
        g.write("\n\n".join("\n".join(f"{x} {y} {z}" for x, y, z in pts) for _, _, pts in blocks))
        g.write("\n")
    return d, sorted(os.listdir(d))


def mutate(data, rng):
    data = bytearray(data)
    kind = rng.choice(["flip", "cut", "repeat", "garbage", "numbers", "delete", "swap", "nul", "digits"])
    n = len(data)
    if kind == "flip":
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(n)] = rng.randrange(256)
    elif kind == "cut":
        data = data[: rng.randrange(n)]
    elif kind == "repeat":
        i = rng.randrange(n)
        j = min(n, i + rng.randint(1, 5000))
        data = data[:j] + data[i:j] * rng.randint(1, 5) + data[j:]
    elif kind == "garbage":
        i = rng.randrange(n)
        data = data[:i] + bytes(rng.randrange(256) for _ in range(rng.randint(1, 200))) + data[i:]
    elif kind == "numbers":
        text = data.decode("latin1")
        found = list(re.finditer(r"-?\d+\.\d+", text))
        new = rng.choice(["nan", "inf", "-1e308", "1e308", "0", "", "--", "1e-320", "9" * 20])
        for m in sorted(rng.sample(found, min(len(found), rng.randint(1, 30))), key=lambda m: -m.start()):
            text = text[: m.start()] + new + text[m.end():]
        data = bytearray(text.encode("latin1"))
    elif kind == "delete":
        i = rng.randrange(n)
        data = data[:i] + data[i + rng.randint(1, 3000):]
    elif kind == "swap":
        lines = bytes(data).split(b"\n")
        for _ in range(rng.randint(1, 50)):
            a, b = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[a], lines[b] = lines[b], lines[a]
        data = bytearray(b"\n".join(lines))
    elif kind == "nul":
        i = rng.randrange(n)
        k = len(data[i: i + rng.randint(1, 500)])
        data[i: i + k] = b"\0" * k
    else:
        i = rng.randrange(n)
        data = data[:i] + b"9" * rng.randint(50, 400) + data[i:]
    return bytes(data), kind


def run_bytes(out, rng, count):
    seed_dir, seeds = byte_seeds(out)
    bad = 0
    for t in range(count):
        src = rng.choice(seeds)
        with open(os.path.join(seed_dir, src), "rb") as f:
            data, kind = mutate(f.read(), rng)
        path = os.path.join(out, f"{t:04d}-{kind}-{src}")
        with open(path, "wb") as f:
            f.write(data)
        args = ["reconstruct", path, "-o", path + ".obj", "--iterations", "30"]
        status, err = cli(args, 60)
        flag = verdict(status, err)
        bad += report(flag, path, err)
    return bad


# ---------------------------------------------------------------------------------------------
# cvi42


CVI42 = os.path.join(H.ROOT, "wasm-core/crates/heartmesh-core/tests/data/cvi42-patient1")


def run_cvi42(out, rng, count):
    """The fixture's workspace mutated with its images intact, or one, two or all images mutated
    with the workspace intact; each study through `reconstruct WORKSPACE IMAGES_DIR`."""
    import shutil

    with open(os.path.join(CVI42, "Contours.cvi42wsx"), "rb") as f:
        wsx = f.read()
    names = sorted(os.listdir(os.path.join(CVI42, "dicom")))
    bad = 0
    for t in range(count):
        case = os.path.join(out, f"{t:04d}")
        images = os.path.join(case, "dicom")
        shutil.copytree(os.path.join(CVI42, "dicom"), images)
        target = "workspace" if rng.random() < 0.5 else "images"
        kinds = []
        data = wsx
        if target == "workspace":
            data, kind = mutate(wsx, rng)
            kinds.append(kind)
        else:
            chosen = names if rng.random() < 0.1 else rng.sample(names, rng.randint(1, 2))
            for n in chosen:
                with open(os.path.join(images, n), "rb") as f:
                    img, kind = mutate(f.read(), rng)
                with open(os.path.join(images, n), "wb") as f:
                    f.write(img)
                kinds.append(kind)
        path = os.path.join(case, f"{target}-{kinds[0]}.cvi42wsx")
        with open(path, "wb") as f:
            f.write(data)
        args = ["reconstruct", path, images, "-o", path + ".obj", "--iterations", "30", "--surface", "LV_ENDO"]
        status, err = cli(args, 60)
        flagged = report(verdict(status, err), path, err)
        bad += flagged
        if not flagged:
            shutil.rmtree(case)
    return bad


# ---------------------------------------------------------------------------------------------
# edits


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    contours = {}
    for r in rows:
        contours.setdefault(r["contour"], []).append(r)
    return list(rows[0].keys()), contours


def points(rows):
    return [[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows]


def put(rows, pts):
    for r, p in zip(rows, pts):
        r["x"], r["y"], r["z"] = (repr(v) for v in p)


def centroid(pts):
    return [sum(p[i] for p in pts) / len(pts) for i in range(3)]


def edit(contours, surface, rng):
    ids = [k for k, v in contours.items() if surface is None or v[0].get("surface") == surface]
    kind = rng.choice(["drop", "move", "scale", "twin", "reverse", "cut", "subsample", "swap", "tilt", "merge",
                       "spike", "endrow"])
    if len(ids) < 2:
        return kind
    c = rng.choice(ids)
    other = rng.choice([k for k in ids if k != c])
    pts = points(contours[c])
    o = centroid(pts)
    if kind == "drop" and len(ids) > 3:
        for k in rng.sample(ids, min(len(ids) - 2, rng.randint(1, 4))):
            del contours[k]
    elif kind == "move":
        d = [rng.gauss(0, 1) for _ in range(3)]
        s = rng.uniform(0, 20) / math.sqrt(sum(v * v for v in d))
        put(contours[c], [[p[i] + d[i] * s for i in range(3)] for p in pts])
    elif kind == "scale":
        s = rng.uniform(0.2, 2.5)
        put(contours[c], [[o[i] + (p[i] - o[i]) * s for i in range(3)] for p in pts])
    elif kind == "twin":
        d = [rng.uniform(-2, 2) for _ in range(3)]
        twin = [dict(r, contour=c + "_twin") for r in contours[c]]
        put(twin, [[p[i] + d[i] for i in range(3)] for p in pts])
        contours[c + "_twin"] = twin
    elif kind == "reverse":
        contours[c] = contours[c][::-1]
    elif kind == "cut" and len(contours[c]) > 10:
        rows = contours[c]
        a = rng.randrange(len(rows))
        contours[c] = rows[:a] + rows[min(len(rows), a + rng.randint(2, len(rows) // 2)):]
    elif kind == "subsample":
        contours[c] = contours[c][:: rng.randint(2, 20)]
    elif kind == "swap":
        for r in contours[c]:
            r["contour"] = other
        for r in contours[other]:
            r["contour"] = c
        contours[c], contours[other] = contours[other], contours[c]
    elif kind == "tilt":
        t = math.radians(rng.uniform(-40, 40))
        i, j = rng.choice([(1, 2), (0, 2), (0, 1)])
        tilted = []
        for p in pts:
            q = list(p)
            x, y = p[i] - o[i], p[j] - o[j]
            q[i], q[j] = o[i] + x * math.cos(t) - y * math.sin(t), o[j] + x * math.sin(t) + y * math.cos(t)
            tilted.append(q)
        put(contours[c], tilted)
    elif kind == "spike" and len(pts) > 10:
        # A damaged value: one to three rows thrown 10-150 mm out, the next row back on the curve.
        a, n = rng.randrange(1, len(pts) - 4), rng.randint(1, 3)
        d = [rng.gauss(0, 1) for _ in range(3)]
        s = rng.uniform(10, 150) / math.sqrt(sum(v * v for v in d))
        put(contours[c], [[p[i] + d[i] * s for i in range(3)] if a <= k < a + n else p for k, p in enumerate(pts)])
    elif kind == "endrow" and len(pts) > 10:
        # A damaged value at a curve's first or last rows (1-3), 10-150 mm out: an open curve
        # cannot come back to itself there.
        n = rng.randint(1, 3)
        ends = range(n) if rng.random() < 0.5 else range(len(pts) - n, len(pts))
        d = [rng.gauss(0, 1) for _ in range(3)]
        s = rng.uniform(10, 150) / math.sqrt(sum(v * v for v in d))
        put(contours[c], [[p[i] + d[i] * s for i in range(3)] if k in ends else p for k, p in enumerate(pts)])
    elif kind == "merge":
        for r in contours[other]:
            r["contour"] = c
        contours[c] = contours[c] + contours.pop(other)
    return kind


def run_edits(out, rng, count):
    bad = 0
    for t in range(count):
        src, surface = rng.choice(EDIT_SOURCES)
        cols, contours = load(os.path.join(CONTOURS, src))
        kinds = [edit(contours, surface, rng) for _ in range(rng.randint(1, 4))]
        name = f"{t:04d}-{'+'.join(kinds)}-{os.path.basename(src)[:-4]}-{surface}.csv"
        path = os.path.join(out, name)
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=cols)
            w.writeheader()
            for rows in contours.values():
                w.writerows(rows)
        args = ["reconstruct", path, "-o", path + ".obj", "--report", path + ".json", "--quiet"]
        status, err = cli(args + (["--surface", surface] if surface else []), 120)
        flag = verdict(status, err)
        if flag is None and status == 0:
            with open(path + ".json") as f:
                rep = json.load(f)
            crossings = rep["quality"]["self_intersections"]
            if not (rep["watertight"] and rep["manifold"] and rep["oriented"]):
                flag = "MESH"
            elif crossings > 0:
                flag = f"SELFX{crossings}"
            elif rep["contour_to_mesh"]["mean"] > 3.0:
                flag = f"C2M{rep['contour_to_mesh']['mean']:.1f}"
        bad += report(flag, path, err)
    return bad


def report(flag, path, err):
    """Prints a flagged run and keeps its files; deletes a clean run's. 1 if flagged."""
    if flag:
        print(f"{flag:8} {os.path.basename(path)}  {err.strip()[:240]}".replace("\n", " | "), flush=True)
        return 1
    for ext in ("", ".obj", ".json"):
        if os.path.exists(path + ext):
            os.remove(path + ext)
    return 0


def main():
    args = sys.argv[1:]
    if not args or args[0] not in ("bytes", "edits", "cvi42"):
        sys.exit(__doc__)
    mode, rest = args[0], args[1:]
    opts = {"--seed": "1", "--count": "300"}
    positional = []
    while rest:
        a = rest.pop(0)
        if a in opts and rest:
            opts[a] = rest.pop(0)
        else:
            positional.append(a)
    out = positional[0] if positional else f"/tmp/heartmesh-fuzz-{mode}"
    os.makedirs(out, exist_ok=True)
    rng = random.Random(int(opts["--seed"]))
    count = int(opts["--count"])
    run = {"bytes": run_bytes, "edits": run_edits, "cvi42": run_cvi42}[mode]
    bad = run(out, rng, count)
    print(f"{bad} of {count} flagged")


if __name__ == "__main__":
    main()
