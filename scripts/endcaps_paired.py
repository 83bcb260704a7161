#!/usr/bin/env python3
"""Summarise paired `--end-caps off` / `auto` experiment runs (scripts/endcaps_paired.sh).

Pairs every KIND-off-TAG.csv with KIND-auto-TAG.csv row by row (same shape, same slicing,
same misalignment) and prints, per metric and misalignment level, the median paired difference
(auto - off), its IQR, a bootstrap 95 % interval of the median (fixed seed: reproducible), and the
share of pairs where auto is worse / better by more than 0.05 mm (1 % for volume, 1 for folds).
The truth-to-mesh maximum is also split by where it lies (worst_height: fraction of the length
from the apex; >= 0.9 = within 10 % of the length from the base)."""
import csv
import glob
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


def main(out):
    pairs, errors = [], 0
    for off_path in sorted(glob.glob(os.path.join(out, "*-off-*.csv"))):
        if off_path.endswith("-shapes.csv"):
            continue
        seed = os.path.basename(off_path).replace("-off-", "-")[:-4]
        auto_path = off_path.replace("-off-", "-auto-")
        if not os.path.exists(auto_path):
            continue
        off, auto = load(off_path), load(auto_path)
        for t, a in off.items():
            b = auto.get(t)
            if a is None or b is None:
                errors += 1
                continue
            pairs.append((seed, a, b))
    rng = random.Random(1)
    print(f"{len(pairs)} pairs ({errors} with a failed run), runs "
          f"{sorted({p[0] for p in pairs})}")
    for level, name in ((0.0, "aligned"), (2.0, "2 mm / 2 deg")):
        every = [(a, b) for _, a, b in pairs if a["shift_mm"] == level]
        # Pairs where auto put no lid (the simulated LAX curves close both ends) are identical;
        # they would make every median 0, so the statistics are over the changed pairs only.
        sel = [(a, b) for a, b in every if any(abs(a[c] - b[c]) > 1e-9 for c, _, _ in METRICS)]
        if not sel:
            continue
        print(f"\n{name}: {len(every)} pairs, {len(sel)} changed by auto (statistics over these)")
        print("| metric | off median | auto median | median diff (auto-off) | IQR of diff "
              "| 95% CI of median diff | auto worse by > thr | auto better by > thr |")
        print("|---|---|---|---|---|---|---|---|")
        for col, label, thr in METRICS:
            d = [b[col] - a[col] for a, b in sel]
            lo, hi = boot_median(d, rng)
            worse = sum(x > thr for x in d) / len(d)
            better = sum(x < -thr for x in d) / len(d)
            print(f"| {label} (thr {thr:g}) | {statistics.median(a[col] for a, _ in sel):.3f} "
                  f"| {statistics.median(b[col] for _, b in sel):.3f} "
                  f"| {statistics.median(d):+.4f} | {quant(d, .25):+.4f} .. {quant(d, .75):+.4f} "
                  f"| {lo:+.4f} .. {hi:+.4f} | {100 * worse:.0f}% | {100 * better:.0f}% |")
        fo = sum(a["folded_edges"] for a, _ in sel)
        fa = sum(b["folded_edges"] for _, b in sel)
        print(f"folded edges total: off {fo:.0f}, auto {fa:.0f}")
        # Where the truth->mesh maximum lies.
        nb_off = sum(a["worst_height"] >= BASE_BAND for a, _ in sel)
        nb_auto = sum(b["worst_height"] >= BASE_BAND for _, b in sel)
        print(f"t2m max within 10 % of the base: off {nb_off}/{len(sel)}, auto {nb_auto}/{len(sel)}")
        for tag, i in (("off", 0), ("auto", 1)):
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
    main(sys.argv[1] if len(sys.argv) > 1 else "/tmp/endcaps-paired")
