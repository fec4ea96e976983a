#!/usr/bin/env python3
"""Accuracy against z-noise level: surfreg and point-to-plane ICP on the same
noisy clouds, many draws per pair.

One draw of 10 noisy pairs (run_peers.py) is too few to rank two methods
whose errors are noise-limited. This takes the noise-free pairs of one family
(make_pairs.py's `<family>_clean_s*`), adds independent Gaussian z-noise of
each sigma to both clouds, `--draws` times per pair, aligns each draw with
both methods and prints, per sigma, the medians of the rotation error
(degrees) and of the translation error at the moving cloud's centre (sample
spacings), and their root-mean-square per axis.

    noise_levels.py --pairs DIR --surfreg BIN [--family volcano]
                    [--sigmas 0,0.25,0.5,1] [--in_spacings] [--draws 5] [--surfreg_args "--cost=axial"]
                    [--no_peer]
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_peers import SCHEDULE, parse_json_output, rotation_angle_deg, run_open3d  # noqa: E402


def errors(est, truth, centre, spacing):
    c = np.append(centre, 1.0)
    return (rotation_angle_deg(est[:3, :3] @ truth[:3, :3].T),
            *(((est @ c - truth @ c)[:3]) / spacing))


def surfreg_motion(binary, ref, mov, extra, scratch):
    rp, mp = os.path.join(scratch, "r.xyz"), os.path.join(scratch, "m.xyz")
    np.savetxt(rp, ref, fmt="%.6f")
    np.savetxt(mp, mov, fmt="%.6f")
    p = subprocess.run([binary, "align", rp, mp, "--json", *extra], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"surfreg exit {p.returncode}: {p.stderr.strip()[-300:]}")
    return np.array(parse_json_output(p.stdout)["matrix"], dtype=float).reshape(4, 4)


def summary(label, rows):
    a = np.array(rows)
    rms = np.sqrt((a[:, 1:] ** 2).mean(0))
    return (f"  {label:10s} median {np.median(a[:, 0]):.4f} deg / "
            f"{np.median(np.linalg.norm(a[:, 1:], axis=1)):.4f} spacings; "
            f"rms tx ty tz {rms[0]:.4f} {rms[1]:.4f} {rms[2]:.4f} ({len(a)} runs)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pairs", required=True, help="directory written by make_pairs.py")
    ap.add_argument("--surfreg", required=True)
    ap.add_argument("--family", default="volcano")
    ap.add_argument("--sigmas", default="0,0.25,0.5,1", help="z-noise sigmas, in the data's units")
    ap.add_argument("--in_spacings", action="store_true", help="sigmas in each pair's sample spacings")
    ap.add_argument("--draws", type=int, default=5, help="noise draws per pair and sigma")
    ap.add_argument("--surfreg_args", default="", help="extra flags for surfreg align")
    ap.add_argument("--no_peer", action="store_true", help="surfreg only")
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    if not os.path.isdir(args.pairs):
        sys.exit(f"--pairs {args.pairs}: no such directory (make it with make_pairs.py)")
    if not os.access(args.surfreg, os.X_OK):
        sys.exit(f"--surfreg {args.surfreg}: not an executable")
    names = sorted(d for d in os.listdir(args.pairs) if d.startswith(f"{args.family}_clean_s"))
    if not names:
        sys.exit(f"no {args.family}_clean_s* pairs in {args.pairs}")
    extra = shlex.split(args.surfreg_args)
    rng = np.random.default_rng(args.seed)
    with tempfile.TemporaryDirectory() as scratch:
        for sigma in (float(s) for s in args.sigmas.split(",")):
            ours, peer = [], []
            for name in names:
                d = os.path.join(args.pairs, name)
                truth = json.load(open(os.path.join(d, "truth.json")))
                t, spacing = np.array(truth["matrix"], dtype=float), truth["spacing"]
                ref0 = np.loadtxt(os.path.join(d, "reference.xyz"), comments="#")[:, :3]
                mov0 = np.loadtxt(os.path.join(d, "moving.xyz"), comments="#")[:, :3]
                centre = mov0.mean(0)
                scale = sigma * spacing if args.in_spacings else sigma
                for _ in range(args.draws if sigma > 0 else 1):
                    ref, mov = ref0.copy(), mov0.copy()
                    ref[:, 2] += rng.normal(scale=scale, size=len(ref))
                    mov[:, 2] += rng.normal(scale=scale, size=len(mov))
                    ours.append(errors(surfreg_motion(args.surfreg, ref, mov, extra, scratch), t, centre, spacing))
                    if not args.no_peer:
                        est = run_open3d("icp_plane", ref, mov, spacing, SCHEDULE)[0]
                        peer.append(errors(est, t, centre, spacing))
            unit = " spacings" if args.in_spacings else ""
            print(f"{args.family}, z-noise sigma {sigma:g}{unit}:")
            print(summary("surfreg", ours), flush=True)
            if peer:
                print(summary("icp_plane", peer), flush=True)


if __name__ == "__main__":
    main()
