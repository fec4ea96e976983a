#!/usr/bin/env python3
"""Makes volcano_changed.xyz: the terrain_volcano example's moving surface
(volcano_moved.xyz) with a landslide on the volcano's flank between the two
surveys, for the stable-terrain example (configs/terrain_changed.yaml).

Usage: python3 configs/data/make_changed_example.py configs/data

Each point of volcano_moved.xyz is taken back to the reference's frame by the
known motion in its header (reference_from_moving), changed there, and moved
again: a scar (a smooth pit, 9 m deep at its centre) at (560, 380) m and its
deposit (a smooth mound, 6 m) at (640, 430) m, each a cosine bell of radius
90 m. The changed part is about a tenth of the area. Standard library only,
deterministic: rerunning rewrites an identical file.
"""
import math
import os
import re
import sys

BELLS = [((560.0, 380.0), 90.0, -9.0), ((640.0, 430.0), 90.0, 6.0)]  # centre, radius, height (m)


def change(x, y):
    dz = 0.0
    for (cx, cy), radius, height in BELLS:
        r = math.hypot(x - cx, y - cy)
        if r < radius:
            dz += height * 0.5 * (1 + math.cos(math.pi * r / radius))
    return dz


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    lines = open(os.path.join(data, "volcano_moved.xyz")).read().splitlines()
    header = [l for l in lines if l.startswith("#")]
    matrix_line = next(l for l in header if l.startswith("# reference_from_moving:"))
    m = [float(v) for v in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", matrix_line)]
    r = [m[0:3], m[4:7], m[8:11]]
    t = [m[3], m[7], m[11]]
    out = [l for l in header if not l.startswith("# columns")]
    out.append("# volcano_changed: volcano_moved.xyz with a landslide between the surveys (make_changed_example.py):")
    out.append("#   in the reference frame, a 9 m deep scar at (560, 380) m and a 6 m deposit at (640, 430) m,")
    out.append("#   cosine bells of radius 90 m; the known motion above is unchanged")
    out.append("# columns: x_m y_m z_m")
    for l in lines:
        if l.startswith("#") or not l.strip():
            continue
        p = [float(v) for v in l.split()[:3]]
        q = [sum(r[i][k] * p[k] for k in range(3)) + t[i] for i in range(3)]  # reference frame
        dz = change(q[0], q[1])
        # The moved point's height changes by dz along the reference's vertical,
        # seen in the moving frame through R^T.
        p = [p[i] + r[2][i] * dz for i in range(3)]
        out.append("%.3f %.3f %.3f" % tuple(p))
    with open(os.path.join(data, "volcano_changed.xyz"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
