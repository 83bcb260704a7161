#!/usr/bin/env python3
"""Random parameter settings on real contours (session 48): every slider and option a user can set,
one to four at a time anywhere in its allowed range, run through `heartmesh reconstruct --report`
on SurFCo, biv-me patient 1 ED (LV and RV endocardium) and patient 2 ES (LV epicardium), one row
per run.

The readers and the defaults are covered elsewhere (hostile.py, fuzz.py, heldout.py); this is for
what a user reaches by moving the sliders: a run must end in a mesh or a clear refusal (exit 2),
whatever the settings. Found with it: smoothing settings that shrink the surface away at a remesh
(1000 sweeps of twicing: the run ended inside out; Taubin 0.6 x 2000 at -76 460 ml), fixed by
skipping such remeshes (`pipeline::remesh_guard`).

Flags per run: EXIT (status other than 0 or 2: a failure), TIMEOUT (over --timeout seconds: slow
settings, e.g. a remesh every 2 iterations for 800, which the CLI's note warns about), VOL (volume
not positive), SELFX (crossing triangle pairs), C2M (contour-to-mesh mean over 2 mm: expected for
a few iterations or a tiny lambda), SKIP (remeshes skipped), OPEN (not watertight). Only EXIT is a
defect by itself; the rest says what the settings did, to read against them.

Usage: scripts/param_sweep.py OUT_DIR [--seed S] [--count N] [--timeout SECONDS]
Standard library only, seeded; the CLI is $HEARTMESH or wasm-core/target/release/heartmesh.
"""

import json
import os
import random
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("HEARTMESH", os.path.join(ROOT, "wasm-core/target/release/heartmesh"))
DATA = os.environ.get("HEARTMESH_DATA", "/work/shared/data")
INPUTS = [
    ("surfco-example.csv", None),
    ("bivme-example-patient1/patient1-ED.csv", "LV_ENDO"),
    ("bivme-example-patient1/patient1-ED.csv", "RV_ENDO"),
    ("bivme-test-patient2/patient2-ES.csv", "LV_EPI"),
]
# Values across each parameter's allowed range (Params::schema), ends included.
VALUES = {
    "iterations": [1, 2, 5, 20, 60, 400, 800],
    "lambda": None,  # log-uniform over 1e-2 .. 1e9
    "beta": [0.01, 0.05, 0.3, 0.6, 1.0],
    "attractors": [1, 3, 10, 50, 600, 1500],
    "attractor-spacing": [0.1, 0.5, 5, 20, 50],
    "resample-attractors-every": [1, 2, 7, 100, 2000],
    "remesh-every": [1, 2, 5, 50, 2000],
    "smoothing-iterations": [0, 1, 10, 500, 1000, 2000],
    "smoothing-factor": [0.0, 0.3, 0.5, 0.8, 1.0],
    "target-reduction": [0.0, 0.5, 0.75, 0.8, 0.9, 0.95],
    "ring-points": [8, 12, 20, 100, 300, 500],
}
# Each smoothing method's largest stable factor (the core refuses more: a refusal, not a run).
FACTOR_LIMIT = {"taubin": 0.6, "laplacian-twicing": 0.5}


def settings(rng):
    chosen = {}
    for name in rng.sample(sorted(VALUES), rng.randint(1, 4)):
        values = VALUES[name]
        chosen[name] = 10 ** rng.uniform(-2, 9) if values is None else rng.choice(values)
    if "attractors" in chosen and "attractor-spacing" in chosen:
        del chosen["attractors"]
    method = rng.choice(["laplacian-affine"] * 3 + ["taubin", "laplacian-hc", "laplacian-twicing"])
    limit = FACTOR_LIMIT.get(method)
    if limit is not None and chosen.get("smoothing-factor", 0.1) > limit:
        chosen["smoothing-factor"] = limit
    return chosen, method


def flags_of(code, report):
    if code == "TIMEOUT":
        return ["TIMEOUT"]
    if code != 0:
        return [] if code == 2 else [f"EXIT{code}"]
    out = []
    v = report["volume_ml"]
    if not (isinstance(v, (int, float)) and v > 0):
        out.append(f"VOL{v}")
    if report["quality"]["self_intersections"] > 0:
        out.append(f"SELFX{report['quality']['self_intersections']}")
    if report["contour_to_mesh"]["mean"] > 2:
        out.append(f"C2M{report['contour_to_mesh']['mean']:.1f}")
    if report.get("skipped_remeshes"):
        out.append(f"SKIP{len(report['skipped_remeshes'])}")
    if not report["watertight"]:
        out.append("OPEN")
    return out


def main(argv):
    if not argv or argv[0].startswith("-"):
        sys.exit(__doc__)
    out = argv[0]
    opt = dict(zip(argv[1::2], argv[2::2]))
    seed, count = int(opt.get("--seed", 1)), int(opt.get("--count", 60))
    timeout = float(opt.get("--timeout", 120))
    os.makedirs(out, exist_ok=True)
    rng = random.Random(seed)
    defects = 0
    for k in range(count):
        (name, surface), (chosen, method) = rng.choice(INPUTS), settings(rng)
        mesh, rep = os.path.join(out, "mesh.obj"), os.path.join(out, "report.json")
        args = [BIN, "reconstruct", os.path.join(DATA, "contours", name), "-o", mesh, "--report", rep,
                "--quiet", "--smoothing-method", method]
        if surface:
            args += ["--surface", surface]
        for key, v in chosen.items():
            args += [f"--{key}", f"{v:g}" if isinstance(v, float) else str(v)]
        t = time.time()
        try:
            p = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
            code, err = p.returncode, p.stderr.strip()
        except subprocess.TimeoutExpired:
            code, err = "TIMEOUT", ""
        report = json.load(open(rep)) if code == 0 else None
        flags = flags_of(code, report)
        defects += any(f.startswith("EXIT") for f in flags)
        last = err.splitlines()[-1][:160] if err and code != 0 else ""
        print(f"{' '.join(flags) or 'ok':20s} {time.time() - t:6.1f}s {name} {surface or ''} {method} "
              f"{chosen} {last}", flush=True)
    print(f"{defects} run(s) of {count} failed (EXIT)")
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
