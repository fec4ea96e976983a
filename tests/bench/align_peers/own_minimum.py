#!/usr/bin/env python3
"""Does `surfreg align` reach its own cost's minimum? (issue 20)

    own_minimum.py --pairs DIR --surfreg BIN [--out CSV] [--grid N] [--extra "--key=v ..."]

For every pair written by make_pairs.py: run `surfreg align` from the default
start (identity) and from the true motion with the same settings, and compare
the final volume cost (the last `volume` row of --log) and the errors against
the truth. A solver that reaches its minimum ends at the same cost from both
starts (relative gap <= 1e-6) and at the same motion. With --grid N, also N
starts spread over rotations up to 10 deg and shifts up to 20 spacings about
the truth: the spread of their returned motions (deg, spacings) and how many
ended in the same minimum.

Prints a Markdown table; --out writes one CSV row per pair and start.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_peers import errors, parse_json_output, rotation_angle_deg  # noqa: E402


def rotation_vector(r):
    angle = math.radians(rotation_angle_deg(r))
    if angle < 1e-15:
        return np.zeros(3)
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return axis / np.linalg.norm(axis) * angle


def rotation_matrix(w):
    angle = float(np.linalg.norm(w))
    if angle < 1e-300:
        return np.eye(3)
    k = w / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * (kx @ kx)


def run(binary, pair, start=None, extra=()):
    """(matrix, json, final volume cost, final gradient norm, seconds)."""
    with tempfile.TemporaryDirectory() as tmp:
        log = os.path.join(tmp, "log.csv")
        cmd = [binary, "align", os.path.join(pair, "reference.xyz"), os.path.join(pair, "moving.xyz"),
               "--json", f"--log={log}"] + list(extra)
        if start is not None:
            w, t = start
            cmd += ["--initial_rotation_deg=" + ",".join(f"{math.degrees(x):.17g}" for x in w),
                    "--initial_translation=" + ",".join(f"{x:.17g}" for x in t)]
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if p.returncode != 0:
            raise RuntimeError(f"{pair}: exit {p.returncode}: {p.stderr.strip()[-300:]}")
        out = parse_json_output(p.stdout)
        cost = grad = math.nan
        with open(log) as f:
            for row in csv.DictReader(f):
                if row["cost_kind"] == "volume":
                    cost, grad = float(row["cost"]), float(row["gradient_norm"])
    return np.array(out["matrix"], dtype=float).reshape(4, 4), out, cost, grad


def start_of(matrix, centre):
    """The (rotation vector, translation of the centre) of a 4x4 moving -> reference."""
    r = matrix[:3, :3]
    c = np.asarray(centre, dtype=float)
    return rotation_vector(r), matrix[:3, :3] @ c + matrix[:3, 3] - c


def grid_starts(truth_start, spacing, n, max_deg=10.0, max_spacings=20.0, at_max=False):
    """n deterministic starts about the truth: rotations and shifts up to the
    maxima (evenly growing to them; all at them with at_max), random axes."""
    rng = np.random.default_rng(20)
    w0, t0 = truth_start
    out = []
    for k in range(n):
        scale = 1.0 if at_max else (k + 1) / n
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        r = rotation_matrix(axis * math.radians(max_deg * scale)) @ rotation_matrix(w0)
        out.append((rotation_vector(r), t0 + direction * max_spacings * spacing * scale))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pairs", required=True)
    ap.add_argument("--surfreg", required=True)
    ap.add_argument("--out", default="")
    ap.add_argument("--only", default="", help="comma-separated substrings of pair names")
    ap.add_argument("--grid", type=int, default=0, help="starts about the truth per pair")
    ap.add_argument("--max-deg", type=float, default=10.0, help="the grid's largest rotation away")
    ap.add_argument("--max-spacings", type=float, default=20.0, help="the grid's largest shift away")
    ap.add_argument("--at-max", action="store_true", help="every start at the largest rotation and shift")
    ap.add_argument("--extra", default="", help="extra flags for surfreg align")
    a = ap.parse_args()
    extra = a.extra.split()
    names = sorted(d for d in os.listdir(a.pairs) if os.path.isfile(os.path.join(a.pairs, d, "truth.json")))
    if a.only:
        names = [n for n in names if any(s in n for s in a.only.split(","))]
    rows = []
    print("| pair | cost default | cost from truth | rel. gap | rot err default / truth (deg) "
          "| trans err default / truth (spacings) | verdict |" +
          (" grid: spread (deg / sp), same minimum, succeeded (< 0.1 deg, < 0.5 sp) |" if a.grid else ""))
    print("|---|---:|---:|---:|---:|---:|---|" + ("---|" if a.grid else ""))
    worst = 0.0
    for name in names:
        pair = os.path.join(a.pairs, name)
        truth = json.load(open(os.path.join(pair, "truth.json")))
        tm = np.array(truth["matrix"], dtype=float)
        spacing = truth["spacing"]
        m0, out0, c0, g0 = run(a.surfreg, pair, None, extra)
        centre = out0["centre"]
        ts = start_of(tm, centre)
        mt, outt, ct, gt = run(a.surfreg, pair, ts, extra)
        e0 = errors(m0, tm, centre, spacing)
        et = errors(mt, tm, centre, spacing)
        gap = (c0 - ct) / ct
        worst = max(worst, gap)
        rows.append(dict(pair=name, start="default", cost=c0, gradient=g0, rot_err=e0[0], trans_err=e0[1],
                         verdict=out0["verdict"], seconds=out0["seconds"]))
        rows.append(dict(pair=name, start="truth", cost=ct, gradient=gt, rot_err=et[0], trans_err=et[1],
                         verdict=outt["verdict"], seconds=outt["seconds"]))
        cell = ""
        if a.grid:
            ms, same, ok = [], 0, 0
            for k, s in enumerate(grid_starts(ts, spacing, a.grid, a.max_deg, a.max_spacings, a.at_max)):
                try:
                    mg, outg, cg, _ = run(a.surfreg, pair, s, extra)
                except RuntimeError as e:
                    print(f"  {e}", file=sys.stderr)
                    continue
                eg = errors(mg, tm, centre, spacing)
                rows.append(dict(pair=name, start=f"grid{k}", cost=cg, gradient=math.nan, rot_err=eg[0],
                                 trans_err=eg[1], verdict=outg["verdict"], seconds=outg["seconds"]))
                ms.append(mg)
                same += abs(cg - ct) <= 1e-6 * ct
                ok += eg[0] < 0.1 and eg[1] < 0.5
            spread_r = max((errors(x, ms[0], centre, spacing)[0] for x in ms), default=math.nan)
            spread_t = max((errors(x, ms[0], centre, spacing)[1] for x in ms), default=math.nan)
            cell = f" {spread_r:.2g} / {spread_t:.2g}, {same}/{a.grid}, {ok} succeeded |"
        print(f"| {name} | {c0:.9g} | {ct:.9g} | {gap:.1e} | {e0[0]:.2g} / {et[0]:.2g} | "
              f"{e0[1]:.2g} / {et[1]:.2g} | {out0['verdict']} |{cell}", flush=True)
    print(f"\nworst relative gap (default above truth): {worst:.2e}")
    if a.out:
        with open(a.out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
