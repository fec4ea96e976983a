#!/usr/bin/env python3
"""The issue-20 summary of a peer benchmark CSV (run_peers.py --out):
per pair, surfreg's error divided by the better peer's (rotation and
translation separately), their geometric mean over all pairs and medians per
family/variant, and total times.

    ratios.py align_peers.csv [--floor-deg 1e-6 --floor-spacings 1e-6] [--each [--block N]]

Errors below the floors count as the floor (a peer's exact 0 would make any
ratio infinite). With --each, also every method against the better of the
other two (what three equally good methods would each score: above 1), the
medians over blocks of N seeds (default 10) and root-mean-square errors."""
import argparse
import csv
import math
import statistics
from collections import defaultdict


def EachMethod(by_pair, a):
    """Each method's error over the better of the other two, per group."""
    keys = (("rot_err_deg", a.floor_deg), ("trans_err_spacings", a.floor_spacings))
    groups = defaultdict(list)
    for (family, variant, _), m in sorted(by_pair.items(), key=lambda kv: (kv[0][0], kv[0][1],
                                                                          int(next(iter(kv[1].values()))["seed_index"]))):
        if len(m) >= 3:
            groups[(family, variant)].append(m)
    methods = sorted({k for ms in groups.values() for m in ms for k in m})
    print(f"| family / variant | method | median ratio, rotation / translation | blocks of {a.block}, rotation "
          "| RMS error, rotation (deg) / translation (spacings) |")
    print("|---|---|---:|---|---:|")
    for (family, variant), pairs in sorted(groups.items()):
        for method in methods:
            ratios = ([], [])
            squares = [0.0, 0.0]
            for m in pairs:
                others = [v for k, v in m.items() if k != method]
                for i, (key, floor) in enumerate(keys):
                    mine = max(float(m[method][key]), floor)
                    ratios[i].append(mine / max(min(float(o[key]) for o in others), floor))
                    squares[i] += float(m[method][key]) ** 2
            blocks = [statistics.median(ratios[0][i:i + a.block]) for i in range(0, len(pairs), a.block)]
            rms = [math.sqrt(q / len(pairs)) for q in squares]
            print(f"| {family} / {variant} | {method} | {statistics.median(ratios[0]):.2f} / "
                  f"{statistics.median(ratios[1]):.2f} | {' '.join(f'{b:.2f}' for b in blocks)} | "
                  f"{rms[0]:.2g} / {rms[1]:.2g} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--floor-deg", type=float, default=1e-6)
    ap.add_argument("--floor-spacings", type=float, default=1e-6)
    ap.add_argument("--each", action="store_true")
    ap.add_argument("--block", type=int, default=10)
    a = ap.parse_args()
    by_pair = defaultdict(dict)
    times = defaultdict(float)
    for row in csv.DictReader(open(a.csv)):
        if row["status"] != "ok":
            continue
        by_pair[(row["family"], row["variant"], row["pair"])][row["method"]] = row
        times[row["method"]] += float(row["wall_seconds"])
    groups = defaultdict(lambda: ([], []))
    logs = ([], [])
    for (family, variant, _), m in sorted(by_pair.items()):
        if "surfreg" not in m:
            continue
        peers = [v for k, v in m.items() if k != "surfreg"]
        if not peers:
            continue
        for i, (key, floor) in enumerate((("rot_err_deg", a.floor_deg), ("trans_err_spacings", a.floor_spacings))):
            mine = max(float(m["surfreg"][key]), floor)
            best = max(min(float(p[key]) for p in peers), floor)
            ratio = mine / best
            groups[(family, variant)][i].append(ratio)
            logs[i].append(math.log(ratio))
    print("| family / variant | median ratio, rotation | median ratio, translation |")
    print("|---|---:|---:|")
    for (family, variant), (r, t) in sorted(groups.items()):
        print(f"| {family} / {variant} | {statistics.median(r):.2f} | {statistics.median(t):.2f} |")
    print(f"| all {len(logs[0])} pairs, geometric mean | {math.exp(statistics.fmean(logs[0])):.2f} | "
          f"{math.exp(statistics.fmean(logs[1])):.2f} |")
    if a.each:
        print()
        EachMethod(by_pair, a)
    print()
    print("| method | total wall time (s) |")
    print("|---|---:|")
    for method, s in sorted(times.items()):
        print(f"| {method} | {s:.1f} |")


if __name__ == "__main__":
    main()
