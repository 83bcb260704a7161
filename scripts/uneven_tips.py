#!/usr/bin/env python3
"""Summarise the uneven-tip family (session 16; `cargo run --release --example uneven_tips --
family N SEED > X.csv`, one CSV per variant): per pattern group, the median (and max) of each
measure per variant, and the paired median difference B - A with a bootstrap 95 % interval.

Usage: scripts/uneven_tips.py A.csv B.csv [C.csv ...]   (names are the files' stems)
Columns: lid_minus_cut_orig = the lid's plane over a cut tip's original place minus its height
(negative: the lid dips under where the truth goes on); lid_minus_kept_max = the most the plane
lies over a tip kept whole; tip_out_* = signed distance of the original tips to the mesh (+:
outside, the mesh stops short); band_t2m_* = truth -> mesh distance over the truth above the
basal SAX plane (the part the paper's clip hides); vol_unclipped_pct = mesh volume against the
truth closed by a fan over its rim.
"""
import csv
import os
import random
import statistics
import sys

COLS = [  # (column, label)
    ("lid_minus_cut_orig", "lid - truth at the cut tip (mm)"),
    ("lid_minus_kept_max", "lid above a kept tip, max (mm)"),
    ("tip_out_cut_orig", "cut tip outside the mesh (mm)"),
    ("tip_out_all_max", "any tip outside the mesh, max (mm)"),
    ("band_t2m_mean", "truth above the basal plane -> mesh, mean"),
    ("band_t2m_max", "truth above the basal plane -> mesh, max"),
    ("m2t_mean", "clipped m2t mean"),
    ("t2m_max", "clipped t2m max"),
    ("hausdorff", "clipped Hausdorff"),
    ("vol_pct", "clipped volume error (%)"),
    ("vol_unclipped_pct", "volume vs truth closed at its rim (%)"),
    ("past_base", "past_data base (mm)"),
    ("folds", "folded edges"),
]


def load(path):
    with open(path) as f:
        return [r for r in csv.DictReader(f)]


def group(r):
    p = r["pattern"]
    return p.rsplit("-", 1)[0]


def num(x, col=""):
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    # The truth closed by a fan over its rim fails on a few truths (spasm LV endo: several rims),
    # giving volume errors of hundreds of per cent: left out.
    if col == "vol_unclipped_pct" and abs(v) > 100:
        return None
    return None if v != v else v


def ci(diffs, rng):
    meds = sorted(statistics.median(rng.choices(diffs, k=len(diffs))) for _ in range(2000))
    return meds[50], meds[1949]


def main():
    files = sys.argv[1:]
    names = [os.path.splitext(os.path.basename(f))[0] for f in files]
    data = [load(f) for f in files]
    groups = sorted({group(r) for r in data[0]})
    for g in groups + ["all"]:
        idx = [i for i, r in enumerate(data[0]) if g == "all" or group(r) == g]
        print(f"\n## {g} ({len(idx)} cases)")
        print("| measure | " + " | ".join(f"{n} median / max" for n in names)
              + " | " + " | ".join(f"{n} - {names[0]} median [95% CI]" for n in names[1:]) + " |")
        print("|---" * (1 + len(names) + len(names) - 1) + "|")
        for col, label in COLS:
            cells = []
            vals = []
            for d in data:
                v = [num(d[i][col], col) for i in idx]
                vals.append(v)
                w = [x for x in v if x is not None]
                cells.append(f"{statistics.median(w):+.2f} / {max(w):+.2f}" if w else "-")
            for v in vals[1:]:
                diffs = [b - a for a, b in zip(vals[0], v) if a is not None and b is not None]
                if diffs:
                    lo, hi = ci(diffs, random.Random(7))
                    cells.append(f"{statistics.median(diffs):+.3f} [{lo:+.3f}, {hi:+.3f}]")
                else:
                    cells.append("-")
            print(f"| {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
