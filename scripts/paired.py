#!/usr/bin/env python3
"""Summarise paired experiment runs of two flag sets A and B (scripts/paired.sh).

Usage: scripts/paired.py OUT_DIR [NAME_A NAME_B]   (default names: a b)

Pairs every KIND-A-TAG.csv with KIND-B-TAG.csv row by row (same shape, same slicing, same
misalignment) and prints, per metric and misalignment level, the median paired difference (B - A),
its IQR, a bootstrap 95 % interval of the median (fixed seed: reproducible), and the share of pairs
where B is worse / better by more than 0.05 mm (1 % for volume, 1 for folds). Besides the clipped
measures (both surfaces cut at the most basal SAX plane, as the paper does) it compares what the
clip hides: the unclipped volume and the overrun past the data at each end (the mesh's reach past
the highest / lowest contour point minus the truth's).
The truth-to-mesh maximum is also split by where it lies (worst_height: fraction of the length
from the apex; >= 0.9 = within 10 % of the length from the base)."""
import csv
import glob
import math
import os
import random
import re
import statistics
import sys

BASE_BAND = 0.9  # worst_height at or above: within 10 % of the length from the base
METRICS = [  # (column, label, threshold for "worse by more than")
    ("mesh_to_truth_mean", "m2t mean (mm)", 0.05),
    ("mesh_to_truth_max", "m2t max (mm)", 0.05),
    ("truth_to_mesh_mean", "t2m mean (mm)", 0.05),
    ("truth_to_mesh_max", "t2m max (mm)", 0.05),
    ("hausdorff", "Hausdorff (mm)", 0.05),
    ("abs_vol_pct", "|volume error| vs clipped truth (%)", 1.0),
    ("volume_diff_percent", "signed volume error (%)", 1.0),
    ("contour_to_mesh_mean", "contour->mesh mean (mm)", 0.05),
    ("folded_edges", "folded edges", 1.0),
    # Present in CSVs written since session 11 (NaN-free rows only):
    ("base_overrun_abs", "|overrun past the data| at the base (mm)", 0.5),
    ("apex_overrun_abs", "|overrun past the data| at the apex (mm)", 0.5),
    ("volume_mesh_unclipped_ml", "unclipped mesh volume (ml)", 1.0),
]


def load(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            if r.get("error"):
                rows[r["trial"]] = None
                continue
            d = {k: float(v) for k, v in r.items() if k not in ("shape", "error") and v != ""}
            d["shape"] = r["shape"]
            d["abs_vol_pct"] = abs(d["volume_diff_percent"])
            if "past_base_mm" in d and "truth_past_base_mm" in d:
                d["base_overrun_abs"] = abs(d["past_base_mm"] - d["truth_past_base_mm"])
                d["apex_overrun_abs"] = abs(d["past_apex_mm"] - d["truth_past_apex_mm"])
            rows[r["trial"]] = d
    return rows


def base_of(shape):
    """Population shapes are pNN-BASE; reference runs use the file's name."""
    return re.sub(r"^p\d+-", "", os.path.basename(shape))


def quant(xs, q):
    xs = sorted(xs)
    i = q * (len(xs) - 1)
    lo = int(i)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (i - lo)


def boot_median(xs, rng, n=2000):
    meds = sorted(statistics.median(rng.choices(xs, k=len(xs))) for _ in range(n))
    return meds[int(0.025 * n)], meds[int(0.975 * n) - 1]


def main(out, name_a, name_b):
    pairs, errors = [], 0
    for path_a in sorted(glob.glob(os.path.join(out, f"*-{name_a}-*.csv"))):
        if path_a.endswith("-shapes.csv"):
            continue
        seed = os.path.basename(path_a).replace(f"-{name_a}-", "-")[:-4]
        path_b = path_a.replace(f"-{name_a}-", f"-{name_b}-")
        if not os.path.exists(path_b):
            continue
        rows_a, rows_b = load(path_a), load(path_b)
        for t, a in rows_a.items():
            b = rows_b.get(t)
            if a is None or b is None:
                errors += 1
                continue
            pairs.append((seed, a, b))
    rng = random.Random(1)
    print(f"{len(pairs)} pairs ({errors} with a failed run), runs "
          f"{sorted({p[0] for p in pairs})}")
    for level, name in ((0.0, "aligned"), (2.0, "2 mm / 2 deg")):
        every = [(a, b) for _, a, b in pairs if a["shift_mm"] == level]
        # Pairs B did not change (e.g. no lid placed where the simulated LAX curves close both
        # ends) would make every median 0, so the statistics are over the changed pairs only.
        sel = [(a, b) for a, b in every
               if any(abs(a[c] - b[c]) > 1e-9 for c, _, _ in METRICS if c in a and c in b)]
        if not sel:
            continue
        print(f"\n{name}: {len(every)} pairs, {len(sel)} changed by {name_b} (statistics over these)")
        print(f"| metric | {name_a} median | {name_b} median | median diff ({name_b}-{name_a}) "
              f"| IQR of diff | 95% CI of median diff | {name_b} worse by > thr "
              f"| {name_b} better by > thr |")
        print("|---|---|---|---|---|---|---|---|")
        for col, label, thr in METRICS:
            have = [(a, b) for a, b in sel if col in a and col in b
                    and not (math.isnan(a[col]) or math.isnan(b[col]))]
            if not have:
                continue
            d = [b[col] - a[col] for a, b in have]
            lo, hi = boot_median(d, rng)
            worse = sum(x > thr for x in d) / len(d)
            better = sum(x < -thr for x in d) / len(d)
            print(f"| {label} (thr {thr:g}) | {statistics.median(a[col] for a, _ in have):.3f} "
                  f"| {statistics.median(b[col] for _, b in have):.3f} "
                  f"| {statistics.median(d):+.4f} | {quant(d, .25):+.4f} .. {quant(d, .75):+.4f} "
                  f"| {lo:+.4f} .. {hi:+.4f} | {100 * worse:.0f}% | {100 * better:.0f}% |")
        fo = sum(a["folded_edges"] for a, _ in sel)
        fa = sum(b["folded_edges"] for _, b in sel)
        print(f"folded edges total: {name_a} {fo:.0f}, {name_b} {fa:.0f}")
        # Present in CSVs written since session 13.
        if all("self_intersections" in a and "self_intersections" in b for a, b in sel):
            xo = sum(a["self_intersections"] for a, _ in sel)
            xa = sum(b["self_intersections"] for _, b in sel)
            print(f"self-intersecting triangle pairs total: {name_a} {xo:.0f}, {name_b} {xa:.0f}")
        # Where the truth->mesh maximum lies.
        nb_a = sum(a["worst_height"] >= BASE_BAND for a, _ in sel)
        nb_b = sum(b["worst_height"] >= BASE_BAND for _, b in sel)
        print(f"t2m max within 10 % of the base: {name_a} {nb_a}/{len(sel)}, "
              f"{name_b} {nb_b}/{len(sel)}")
        for tag, i in ((name_a, 0), (name_b, 1)):
            hist = [0] * 10
            for p in sel:
                hist[min(9, max(0, int(p[i]["worst_height"] * 10)))] += 1
            print(f"  t2m max height deciles (apex .. base), {tag}: {hist}")
        # The measured part ends at the basal SAX plane, below the truth's top (height 1), so the
        # cap-to-wall corner shows in the 0.8-0.9 decile: split at both 0.9 and 0.8.
        for band in (BASE_BAND, BASE_BAND - 0.1):
            for tag, sub in (
                (f"either max at height >= {band:.1f}",
                 [(a, b) for a, b in sel if max(a["worst_height"], b["worst_height"]) >= band]),
                ("both maxima below", [(a, b) for a, b in sel
                                       if max(a["worst_height"], b["worst_height"]) < band]),
            ):
                if len(sub) < 2:
                    continue
                d = [b["truth_to_mesh_max"] - a["truth_to_mesh_max"] for a, b in sub]
                lo, hi = boot_median(d, rng)
                print(f"  t2m max, {tag}: n {len(sub)}, median diff {statistics.median(d):+.4f}, "
                      f"IQR {quant(d, .25):+.4f} .. {quant(d, .75):+.4f}, CI {lo:+.4f} .. {hi:+.4f}, "
                      f"worse > 0.05: {100 * sum(x > 0.05 for x in d) / len(d):.0f}%, "
                      f"better > 0.05: {100 * sum(x < -0.05 for x in d) / len(d):.0f}%")
        # Per base shape: median paired difference of the means and maxima.
        print("  per base shape (median diff m2t mean / t2m max / |vol|%, n):")
        bases = sorted({base_of(a["shape"]) for a, _ in sel})
        for base in bases:
            sub = [(a, b) for a, b in sel if base_of(a["shape"]) == base]
            m = statistics.median(b["mesh_to_truth_mean"] - a["mesh_to_truth_mean"] for a, b in sub)
            x = statistics.median(b["truth_to_mesh_max"] - a["truth_to_mesh_max"] for a, b in sub)
            v = statistics.median(b["abs_vol_pct"] - a["abs_vol_pct"] for a, b in sub)
            print(f"    {base}: {m:+.4f} / {x:+.4f} / {v:+.2f}, n {len(sub)}")


if __name__ == "__main__":
    argv = sys.argv[1:]
    main(argv[0] if argv else "/tmp/paired", *(argv[1:3] if len(argv) >= 3 else ("a", "b")))
