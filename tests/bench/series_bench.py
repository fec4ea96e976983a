"""Joint alignment of a series against chained and to-reference pairwise
alignments (issue 48), on series built from the project's real surfaces
with known motions (tests/make_series.py):

  strips  the Jacksboro DEM (configs/data/jacksboro_fault_dem.xyz) cut into
          6 strips sliding east (neighbours overlapping by 3/4, the next but
          one by 1/2), 20000 random samples each, 0.5 m noise;
  repeat  the Maunga Whau DEM (configs/data/volcano.xyz), 5 repeat surveys
          of most of it, 3000 samples each, 0.2 m noise, with a landslide
          deepening by 4 m per epoch (the stable terrain must be found);
  chewing the mannequin face scan (configs/data/mannequin_face_dense.xyz) in
          mm, 6 frames of 6000 of its points each, 0.05 mm noise, the jaw
          opening by up to 8 degrees over a chewing cycle: each frame's head
          motion is the known one, the jaw the part that changed.

For each series and seed: `surfreg series` (the joint motion, one process);
`surfreg align` of every pair of its overlap graph, each its own process;
from those, the chain (epoch k onto k - 1, composed) and the direct
alignment onto the reference (epoch 0), where they overlap. Errors against
the truth for every epoch: the rotation angle (degrees) and the distance
between where the estimate and the truth take the epoch's centroid (in the
grid's sample spacings). Also |error| / sigma of the joint motion per
parameter (its calibration) and the time of the series against the sum of
the pairwise alignments' times.

Usage: series_bench.py SURFREG DATA_DIR SEEDS [FAMILY ...] (strips, repeat, chewing; default all)
Prints Markdown tables (the per-epoch errors as geometric means over the seeds).
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
FAMILIES = {
    "strips": ("jacksboro_fault_dem.xyz", 6, "strips", 20000, 0.5, 0.0),
    "repeat": ("volcano.xyz", 5, "repeat", 3000, 0.2, 4.0),
    "chewing": ("mannequin_face_dense.xyz", 6, "chewing", 6000, 0.05, 8.0),
}


def run(args):
    start = time.perf_counter()
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def rotation_vector(r):
    angle = math.acos(max(-1.0, min(1.0, (np.trace(r) - 1) / 2)))
    if angle < 1e-12:
        return np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2
    axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / (2 * math.sin(angle))
    return axis * angle


def errors(estimate, truth, centre):
    """Rotation angle (degrees), translation at the centre, and the six
    parameter errors (rotation vector of R_est R_true^T, shift of the centre)."""
    c = np.append(centre, 1.0)
    w = rotation_vector(estimate[:3, :3] @ truth[:3, :3].T)
    t = (estimate @ c - truth @ c)[:3]
    return math.degrees(np.linalg.norm(w)), np.linalg.norm(t), np.concatenate([w, t])


def gmean(values):
    values = [max(v, 1e-12) for v in values]
    return math.exp(sum(math.log(v) for v in values) / len(values))


def one_series(surfreg, data, family, seed, work):
    grid, epochs, layout, points, noise, change = FAMILIES[family]
    out = os.path.join(work, "%s_%d" % (family, seed))
    subprocess.run([sys.executable, os.path.join(HERE, "..", "make_series.py"), os.path.join(data, grid), out,
                    str(epochs), layout, str(seed), str(points), str(noise), str(change)], check=True)
    truth_file = json.load(open(os.path.join(out, "truth.json")))
    world = [np.array(m).reshape(4, 4) for m in truth_file["world_from_epoch"]]
    spacing = truth_file["spacing"]
    files = [os.path.join(out, "e%d.xyz" % k) for k in range(epochs)]
    series_seconds = run([surfreg, "series", *files, "--quiet", "--output=" + os.path.join(out, "series.json")])
    series = json.load(open(os.path.join(out, "series.json")))
    pairwise, pair_seconds, pair_z = {}, 0.0, []
    for p in series["pairs"]:
        i, j = p["reference"], p["moving"]
        path = os.path.join(out, "pair_%d_%d.json" % (i, j))
        pair_seconds += run([surfreg, "align", files[i], files[j], "--quiet", "--output=" + path])
        result = json.load(open(path))
        pairwise[(i, j)] = np.array(result["matrix"])
        truth = np.linalg.inv(world[i]) @ world[j]
        sigma = np.array([result["stddev"][n] for n in ("rx", "ry", "rz", "tx", "ty", "tz")])
        pair_z.extend(np.abs(errors(pairwise[(i, j)], truth, np.array(result["centre"]))[2]) / sigma)
    chained = [np.eye(4)]
    for k in range(1, epochs):
        chained.append(chained[-1] @ pairwise[(k - 1, k)] if (k - 1, k) in pairwise else None)
    rows = []
    for k in range(1, epochs):
        truth = np.linalg.inv(world[0]) @ world[k]
        e = series["epochs"][k]
        centre = np.array(e["centre"])
        joint = errors(np.array(e["matrix"]), truth, centre)
        sigma = np.array([e["stddev"][n] for n in ("rx", "ry", "rz", "tx", "ty", "tz")])
        chain = errors(chained[k], truth, centre) if chained[k] is not None else None
        direct = errors(pairwise[(0, k)], truth, centre) if (0, k) in pairwise else None
        rows.append({"epoch": k, "joint": joint, "sigma": sigma, "chain": chain, "direct": direct})
    return rows, series_seconds, pair_seconds, spacing, series.get("pair_correlation", 0.0), pair_z


def main():
    surfreg, data, seeds = sys.argv[1], sys.argv[2], int(sys.argv[3])
    families = sys.argv[4:] or list(FAMILIES)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    print("CPU: %s, %d cores; %d seeds per family\n" % (cpu, os.cpu_count(), seeds))
    ratios, z_all, time_rows, pair_z_all = [], [], [], []
    with tempfile.TemporaryDirectory() as work:
        for family in families:
            per_epoch = {}
            series_total = pair_total = 0.0
            correlations, family_pair_z = [], []
            for seed in range(1, seeds + 1):
                rows, s_sec, p_sec, spacing, correlation, z_pairs = one_series(surfreg, data, family, seed, work)
                correlations.append(correlation)
                pair_z_all.extend(z_pairs)
                family_pair_z.extend(z_pairs)
                series_total += s_sec
                pair_total += p_sec
                for r in rows:
                    per_epoch.setdefault(r["epoch"], []).append((r, spacing))
            time_rows.append((family, series_total, pair_total))
            print("### %s\n" % family)
            print("pair_correlation chosen: %s\n" % ", ".join("%.2f" % c for c in correlations))
            family_z = []
            print("| epoch | joint rotation (°) | chained | to reference | joint translation (spacings) | chained | "
                  "to reference | joint / chained |")
            print("|---:|---:|---:|---:|---:|---:|---:|---:|")
            for k, items in sorted(per_epoch.items()):
                jr = gmean([r["joint"][0] for r, _ in items])
                jt = gmean([r["joint"][1] / s for r, s in items])
                cr = gmean([r["chain"][0] for r, _ in items])
                ct = gmean([r["chain"][1] / s for r, s in items])
                has_direct = all(r["direct"] is not None for r, _ in items)
                dr = "%.4f" % gmean([r["direct"][0] for r, _ in items]) if has_direct else "-"
                dt = "%.4f" % gmean([r["direct"][1] / s for r, s in items]) if has_direct else "-"
                # One number per epoch: the error's size as a whole (rotation at the lever of
                # the translation is not comparable across families, so the two ratios' mean).
                ratio = math.sqrt((jr / cr) * (jt / ct))
                ratios.append((family, k, ratio, jr <= cr and jt <= ct))
                print("| %d | %.4f | %.4f | %s | %.4f | %.4f | %s | %.2f |" % (k, jr, cr, dr, jt, ct, dt, ratio))
                for r, _ in items:
                    z_all.extend(np.abs(r["joint"][2]) / r["sigma"])
                    family_z.extend(np.abs(r["joint"][2]) / r["sigma"])
            print()
            print("joint |error| / sigma: median %.2f, beyond 3 sigma %.1f%%; the pairs' own: median %.2f, beyond 3 "
                  "sigma %.1f%%\n" % (float(np.median(family_z)), 100.0 * float(np.mean(np.array(family_z) > 3)),
                                     float(np.median(family_pair_z)),
                                     100.0 * float(np.mean(np.array(family_pair_z) > 3))))
    z = np.array(z_all)
    print("### Summary\n")
    print("- geometric mean of joint / chained over every epoch: %.2f (%d epochs; joint <= chained on %d)" %
          (gmean([r[2] for r in ratios]), len(ratios), sum(r[3] for r in ratios)))
    print("- joint sigma: median |error| / sigma %.2f, beyond 3 sigma %.1f%% (%d parameters)" %
          (float(np.median(z)), 100.0 * float(np.mean(z > 3)), len(z)))
    pz = np.array(pair_z_all)
    print("- the pairwise alignments' own sigma: median |error| / sigma %.2f, beyond 3 sigma %.1f%% (%d parameters)" %
          (float(np.median(pz)), 100.0 * float(np.mean(pz > 3)), len(pz)))
    for family, s, p in time_rows:
        print("- %s: series %.1f s, the pairwise alignments of its graph %.1f s: %.2f x" % (family, s, p, s / p))


main()
