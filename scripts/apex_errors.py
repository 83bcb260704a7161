#!/usr/bin/env python3
"""Signed apex error per arm of a paired study, LV and RV apart (docs/VALIDATION.md, sessions 14
and 17: the apex floor on short-axis-only stacks).

Usage: scripts/apex_errors.py OUT_DIR ARM...   (arms as scripts/paired.sh tags them: a b ...)

The error is the mesh's reach past the lowest slice minus the truth's (mm; + past the truth's
apex, - short of it). RVs are the population members whose base name holds "rv" and, in the
reference runs (misalignment-ARM-ref0/ref2), subjects 6 and 7 (scripts/paired.sh lists the biv-me
RV and the spasm RV cavity last; the CSVs name the cavity after its septum, cardiomesh-spasm-LV_epi).
Prints, per group, the median, the |error| median and p90, the counts more than 2 mm short and
past, the worst of each, the folded edges and self-intersecting pairs in total, and the mean signed
clipped volume error."""
import csv
import glob
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from paired import quant as quantile  # noqa: E402  (one interpolated quantile for both summaries)

REF_RV_SUBJECTS = (6, 7)


def rows(out, arm):
    for path in sorted(glob.glob(os.path.join(out, f"*-{arm}-*.csv"))):
        if path.endswith("-shapes.csv"):
            continue
        ref = os.path.basename(path).startswith("misalignment-")
        with open(path) as f:
            table = list(csv.DictReader(f))
        # Reference runs: trial = subject x seeds + seed index, the seeds counted per level.
        seeds = max(1, len({r["seed"] for r in table}))
        for r in table:
            if r.get("error"):
                continue
            rv = "rv" in os.path.basename(r["shape"]).lower() or (
                ref and int(r["trial"]) // seeds in REF_RV_SUBJECTS
            )
            yield rv, float(r["past_apex_mm"]) - float(r["truth_past_apex_mm"]), r


def summary(es):
    a = [abs(x) for x in es]
    return (f"n {len(es):3d}  median {statistics.median(es):+.2f}  |.| median "
            f"{statistics.median(a):.2f} p90 {quantile(a, .9):.2f}  >2 short "
            f"{sum(x < -2 for x in es):3d}  >2 past {sum(x > 2 for x in es):3d}  worst short "
            f"{min(es):+.2f}  worst past {max(es):+.2f}")


def main(out, arms):
    for arm in arms:
        data = list(rows(out, arm))
        if not data:
            print(f"== {arm}: no runs in {out}")
            continue
        print(f"== {arm}")
        groups = (
            ("all", lambda rv, r: True),
            ("LV", lambda rv, r: not rv),
            ("RV", lambda rv, r: rv),
            ("LV aligned", lambda rv, r: not rv and float(r["shift_mm"]) == 0),
            ("LV misaligned", lambda rv, r: not rv and float(r["shift_mm"]) > 0),
            ("RV aligned", lambda rv, r: rv and float(r["shift_mm"]) == 0),
            ("RV misaligned", lambda rv, r: rv and float(r["shift_mm"]) > 0),
        )
        for name, keep in groups:
            es = [e for rv, e, r in data if keep(rv, r)]
            if es:
                print(f"  {name:14s} {summary(es)}")
        for col in ("folded_edges", "self_intersections"):
            print(f"  {col} total {sum(float(r[col]) for _, _, r in data if col in r):.0f}")
        vol = statistics.mean(float(r["volume_diff_percent"]) for _, _, r in data)
        print(f"  signed clipped volume error, mean {vol:+.3f} %")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
