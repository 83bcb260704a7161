#!/usr/bin/env python3
"""Accuracy of `heartmesh volumes` (session 23): end-diastolic and end-systolic volumes and the
ejection fraction against known truth, over many contractions and breath-hold misalignments.

Each reference cavity is the end-diastolic truth; its end-systolic partner is the same mesh
contracted about its centroid, along the principal axis by a factor drawn in [0.85, 0.97] and
across it by one in [0.70, 0.88] (a ventricle narrows more than it shortens), so the truth
ejection fraction spans about 35-60 %. Both phases are sliced by `heartmesh simulate` (an RV on
its LV's axis, contracted alike, one long-axis view), aligned or with every plane shifted up to
2 mm and tilted up to 2 degrees, and measured by `heartmesh volumes`. Standard library only.

Usage:  scripts/function_accuracy.py [OUT_DIR] [--pairs N] [--seed S]
Prints per shape and level the median / p95 / max absolute error of EDV and ESV (%) and of the EF
(percentage points): of the meshes against the truth, both clipped at the basal plane (the
method's accuracy where there are data), and of the volumes `heartmesh volumes` reports against
the whole truth cavity (closed, or an open truth closed flat at its rim) where the long-axis
curves reach all of it.
"""

import json
import math
import os
import random
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile as H  # noqa: E402  (the CLI path and the data directory)
from heldout import read_obj  # noqa: E402

# (name, ED truth, LV whose axis plans the planes or None, whether the long-axis curves reach the
# whole cavity: the LVs' run to the valve rim; the RV's one view misses its outflow tract)
SHAPES = [
    ("bivme-lv", "bivme-patient1-ED-LV_ENDO-closed.obj", None, True),
    ("cap-lv", "cap-atlas-mean-ED-LV_ENDO-open.obj", None, True),
    ("spasm-lv", "cardiomesh-spasm-LV_endo.obj", None, True),
    ("bivme-rv", "bivme-patient1-ED-RV_ENDO-closed.obj", "bivme-patient1-ED-LV_ENDO-closed.obj",
     False),
]
LEVELS = [("aligned", []), ("2mm-2deg", ["--misalign", "2,2"])]


def principal_axis(verts):
    """Unit direction of largest spread (power iteration on the 3x3 covariance)."""
    n = len(verts)
    c = [sum(v[i] for v in verts) / n for i in range(3)]
    cov = [[sum((v[i] - c[i]) * (v[j] - c[j]) for v in verts) / n for j in range(3)]
           for i in range(3)]
    d = [1.0, 0.7, 0.3]
    for _ in range(200):
        d = [sum(cov[i][j] * d[j] for j in range(3)) for i in range(3)]
        s = math.sqrt(sum(x * x for x in d))
        d = [x / s for x in d]
    return c, d


def contracted(verts, centre, axis, along, across):
    out = []
    for v in verts:
        q = [v[i] - centre[i] for i in range(3)]
        a = sum(q[i] * axis[i] for i in range(3))
        out.append(tuple(centre[i] + axis[i] * a * along + (q[i] - axis[i] * a) * across
                         for i in range(3)))
    return out


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        for v in verts:
            f.write("v %.6f %.6f %.6f\n" % v)
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


def rim_centre(verts, faces):
    """Centroid of the boundary edges' vertices (None for a closed mesh)."""
    count = {}
    for f in faces:
        for i in range(3):
            e = tuple(sorted((f[i], f[(i + 1) % 3])))
            count[e] = count.get(e, 0) + 1
    rim = {v for e, n in count.items() if n == 1 for v in e}
    if not rim:
        return None
    return [sum(verts[v][i] for v in rim) / len(rim) for i in range(3)]


def volume_ml(verts, faces, origin=None):
    """Enclosed volume; an open mesh is closed by the cone from `origin` (its rim's centre) to
    its rim, a flat lid where the rim is planar; whatever way the triangles face (CardioMesh's face
    inwards)."""
    o = origin or (0.0, 0.0, 0.0)
    s = 0.0
    for a, b, c in faces:
        p, q, r = [[verts[i][k] - o[k] for k in range(3)] for i in (a, b, c)]
        s += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
              + p[2] * (q[0] * r[1] - q[1] * r[0]))
    return abs(s) / 6000.0


def cli(args):
    r = subprocess.run([H.BIN] + args, capture_output=True, timeout=600)
    if r.returncode != 0:
        raise RuntimeError(" ".join(args[:2]) + ": " + r.stderr.decode(errors="replace"))
    return r.stdout.decode()


def clipped(truth, mesh, contours):
    """(truth, mesh) volumes below the most basal SAX plane of `contours`."""
    out = json.loads(cli(["compare", truth, mesh, "--clip-contours", contours, "--json"]))
    return out["volume_truth_ml"], out["volume_mesh_ml"]


def percentile(xs, q):
    s = sorted(xs)
    return s[min(len(s) - 1, max(0, int(math.ceil(q * len(s))) - 1))]


def main():
    argv = sys.argv[1:]
    out_dir = argv[0] if argv and not argv[0].startswith("--") else "/tmp/function-accuracy"
    pairs = int(argv[argv.index("--pairs") + 1]) if "--pairs" in argv else 10
    seed = int(argv[argv.index("--seed") + 1]) if "--seed" in argv else 1
    os.makedirs(out_dir, exist_ok=True)
    rng = random.Random(seed)
    rows = []
    for name, truth_file, axis_file, whole in SHAPES:
        verts, faces = read_obj(os.path.join(H.MESHES, truth_file))
        axis_verts = read_obj(os.path.join(H.MESHES, axis_file))[0] if axis_file else verts
        centre_lv, axis = principal_axis(axis_verts)
        ed_path = os.path.join(out_dir, name + "-ED.obj")
        write_obj(ed_path, verts, faces)
        for k in range(pairs):
            along, across = rng.uniform(0.85, 0.97), rng.uniform(0.70, 0.88)
            n = len(verts)
            centre = [sum(v[i] for v in verts) / n for i in range(3)]
            es_verts = contracted(verts, centre, axis, along, across)
            es_path = os.path.join(out_dir, "%s-ES%d.obj" % (name, k))
            write_obj(es_path, es_verts, faces)
            plan = {}
            if axis_file:
                lv_verts, lv_faces = read_obj(os.path.join(H.MESHES, axis_file))
                lv_es = os.path.join(out_dir, "%s-axis-ES%d.obj" % (name, k))
                write_obj(lv_es, contracted(lv_verts, centre_lv, axis, along, across), lv_faces)
                plan = {"ED": os.path.join(H.MESHES, axis_file), "ES": lv_es}
            for level, extra in LEVELS:
                phases = {}
                for phase, truth in (("ED", ed_path), ("ES", es_path)):
                    csv = os.path.join(out_dir, "%s-%d-%s-%s.csv" % (name, k, level, phase))
                    args = ["simulate", truth, "-o", csv, "--seed", str(seed * 1000 + k),
                            "--quiet"] + extra
                    if plan:
                        args += ["--lax", "1", "--axis-from", plan[phase]]
                    cli(args)
                    phases[phase] = (truth, csv)
                meshes = os.path.join(out_dir, "meshes")
                report = os.path.join(out_dir, "v.json")
                cli(["volumes", phases["ED"][1], phases["ES"][1], "--quiet", "--json", report,
                     "--meshes", meshes])
                doc = json.load(open(report))
                got = {v["phase"].rsplit("-", 1)[1]: v["volume_ml"] for v in doc["volumes"]}
                cut = {}
                for phase, (t, csv) in phases.items():
                    stem = os.path.splitext(os.path.basename(csv))[0]
                    cut[phase] = clipped(t, os.path.join(meshes, stem + "-surface.obj"), csv)
                ef = lambda ed, es: 100.0 * (ed - es) / ed  # noqa: E731
                (t_ed, m_ed), (t_es, m_es) = cut["ED"], cut["ES"]
                row = {
                    "shape": name, "level": level, "pair": k,
                    "ef_truth": ef(t_ed, t_es),
                    "edv_err": 100.0 * (m_ed - t_ed) / t_ed,
                    "esv_err": 100.0 * (m_es - t_es) / t_es,
                    "ef_err": ef(m_ed, m_es) - ef(t_ed, t_es),
                }
                if whole:
                    rim = rim_centre(verts, faces)
                    w_ed = volume_ml(verts, faces, rim)
                    w_es = volume_ml(es_verts, faces, rim_centre(es_verts, faces))
                    row["edv_err_whole"] = 100.0 * (got["ED"] - w_ed) / w_ed
                    row["esv_err_whole"] = 100.0 * (got["ES"] - w_es) / w_es
                    row["ef_err_whole"] = ef(got["ED"], got["ES"]) - ef(w_ed, w_es)
                    row["ef_truth_whole"] = ef(w_ed, w_es)
                rows.append(row)
                print("%-9s %-9s %2d  EF truth %5.1f  clipped: EDV %+6.2f %%  ESV %+6.2f %%  EF "
                      "%+5.2f pt%s" % (name, level, k, row["ef_truth"], row["edv_err"],
                                       row["esv_err"], row["ef_err"],
                                       "  whole: EDV %+6.2f %%  EF %+5.2f pt"
                                       % (row["edv_err_whole"], row["ef_err_whole"])
                                       if whole else ""), flush=True)
    with open(os.path.join(out_dir, "function-accuracy.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print("\nerrors of `volumes` against the truth below the basal plane, both clipped there "
          "(|EDV|, |ESV| in %, |EF| in points, median / p95 / max),\nand of what `volumes` "
          "reports against the whole truth cavity (LVs: closed, or closed flat at the rim)")
    print("shape     level      n   |EDV| clipped      |ESV| clipped      |EF| clipped"
          "         |EDV| whole        |EF| whole")
    for name, _, _, whole in SHAPES:
        for level, _ in LEVELS:
            sel = [r for r in rows if r["shape"] == name and r["level"] == level]
            if not sel:
                continue

            def trio(key):
                xs = [abs(r[key]) for r in sel]
                return "%5.2f %5.2f %5.2f" % (percentile(xs, 0.5), percentile(xs, 0.95), max(xs))
            extra = ""
            if whole:
                extra = "  %s  %s" % (trio("edv_err_whole"), trio("ef_err_whole"))
            print("%-9s %-9s %3d  %s  %s  %s%s"
                  % (name, level, len(sel), trio("edv_err"), trio("esv_err"), trio("ef_err"),
                     extra))


if __name__ == "__main__":
    main()
