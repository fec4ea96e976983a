#!/usr/bin/env python3
"""Are surfreg's standard deviations calibrated? (issue 25)

    coverage.py --pairs DIR --surfreg BIN [--extra "--stddev_subsamples=8"] [--out CSV]

Runs `surfreg align --json` on every pair written by make_pairs.py (from
the identity, as run_peers.py does) and compares each parameter's actual
error with its reported sigma: z = error / sigma for rx, ry, rz (the
rotation vector of R_est R_true^T, per axis) and tx, ty, tz (the shift of
the moving centroid, est - true). For a calibrated sigma, z is standard
normal: median |z| 0.674, 4.6% beyond 2, 0.27% beyond 3. Prints a Markdown
table per family and overall (all six parameters pooled, then per
parameter) and the total time; --out writes one row per pair and parameter.
"""
import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import time
from collections import defaultdict

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from own_minimum import rotation_vector  # noqa: E402
from run_peers import parse_json_output  # noqa: E402

NAMES = ["rx", "ry", "rz", "tx", "ty", "tz"]


def row(zs):
    a = [abs(z) for z in zs if math.isfinite(z)]
    if not a:
        return "n/a | n/a | n/a | 0"
    return "%.2f | %.1f%% | %.1f%% | %d" % (statistics.median(a), 100 * sum(z > 2 for z in a) / len(a),
                                           100 * sum(z > 3 for z in a) / len(a), len(a))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pairs", required=True)
    ap.add_argument("--surfreg", required=True)
    ap.add_argument("--extra", default="", help="extra flags for surfreg align")
    ap.add_argument("--out", default="")
    a = ap.parse_args()
    z_by = defaultdict(list)
    rows = []
    seconds = 0.0
    for name in sorted(os.listdir(a.pairs)):
        pair = os.path.join(a.pairs, name)
        truth_path = os.path.join(pair, "truth.json")
        if not os.path.isfile(truth_path):
            continue
        truth = json.load(open(truth_path))
        t_mat = np.array(truth["matrix"], dtype=float).reshape(4, 4)
        t0 = time.perf_counter()
        p = subprocess.run([a.surfreg, "align", os.path.join(pair, "reference.xyz"),
                            os.path.join(pair, "moving.xyz"), "--json"] + a.extra.split(),
                           capture_output=True, text=True, timeout=600)
        seconds += time.perf_counter() - t0
        if p.returncode != 0:
            print(f"{name}: exit {p.returncode}", file=sys.stderr)
            continue
        out = parse_json_output(p.stdout)
        est = np.array(out["matrix"], dtype=float).reshape(4, 4)
        centre = np.array(out["centre"] + [1.0])
        rot_err = rotation_vector(est[:3, :3] @ t_mat[:3, :3].T)
        trans_err = (est @ centre - t_mat @ centre)[:3]
        errors = list(rot_err) + list(trans_err)
        family = truth["family"]
        for k, key in enumerate(NAMES):
            sigma = out["stddev"][key]
            z = errors[k] / sigma if sigma else math.nan
            z_by[(family, key)].append(z)
            rows.append({"pair": name, "family": family, "variant": truth["variant"], "parameter": key,
                         "error": errors[k], "sigma": sigma, "z": z})
        print(f"{name}: max |z| {max(abs(r['z']) for r in rows[-6:]):.2f}", file=sys.stderr)
    families = sorted({f for f, _ in z_by})
    print("| pairs | median \\|error\\| / sigma | beyond 2 sigma | beyond 3 sigma | values |")
    print("|---|---:|---:|---:|---:|")
    for f in families:
        print(f"| {f} (all parameters) | " + row([z for (g, _), zs in z_by.items() if g == f for z in zs]) + " |")
    for key in NAMES:
        print(f"| all, {key} | " + row([z for (_, k), zs in z_by.items() if k == key for z in zs]) + " |")
    print("| all | " + row([z for zs in z_by.values() for z in zs]) + " |")
    print(f"\nsurfreg total time {seconds:.1f} s ({a.extra or 'defaults'})")
    if a.out:
        with open(a.out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
