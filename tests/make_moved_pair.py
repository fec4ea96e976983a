"""A DEM pair with a known rigid motion, for the tiled alignment (issue 24):
cli_tiled_align_test.sh and tests/bench/run_tiled_align_bench.sh.

A: N x N cells of 1 m, a smooth terrain with two round nodata holes. B: the
same terrain moved rigidly by the inverse of a known motion K (rotation of
a few hundredths of a degree about A's centre, a shift of a few cells), on
its own grid offset by a fraction of a cell, with a hole of its own. K (the
moving -> reference matrix, row-major) is written to known.txt as 16
numbers on one line. ESRI .bil rasters (float32) with .hdr, written a band
of rows at a time (numpy when present; the standard library otherwise, for
the tests' small sizes).

With STRETCH (e.g. 0.002), B is also stretched along x about A's centre by
1 + STRETCH after the motion: a misregistration that varies in space, which
no rigid motion removes (the patch shifts' test).

Usage: make_moved_pair.py DIR N [STRETCH]
"""
import math
import os
import struct
import sys

try:
    import numpy as np
except ImportError:  # the tests' small pairs
    np = None

out, n = sys.argv[1], int(sys.argv[2])
stretch = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
X0, Y0 = 400000.0, 5200000.0  # UTM-sized
centre = (X0 + n / 2, Y0 - n / 2, 0.0)


def rotation(rx, ry, rz):
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    # Rz Ry Rx
    return [[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
            [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
            [-sy, cy * sx, cy * cx]]


deg = math.pi / 180
R = rotation(0.012 * deg, -0.017 * deg, 0.031 * deg)
shift = (2.37, -1.61, 0.35)
# K p = R (p - c) + c + shift
T = [shift[i] + centre[i] - sum(R[i][j] * centre[j] for j in range(3)) for i in range(3)]
K = [R[0] + [T[0]], R[1] + [T[1]], R[2] + [T[2]], [0.0, 0.0, 0.0, 1.0]]

sin = np.sin if np else math.sin
cos = np.cos if np else math.cos
exp = np.exp if np else math.exp


def terrain(x, y):
    lx, ly = x - X0, Y0 - y
    return (300 + 20 * sin(lx / 37) * cos(ly / 23) + 6 * sin(lx / 211 + 1) * sin(ly / 173)
            + 0.01 * lx - 0.004 * ly + 15 * exp(-((lx - 0.6 * n) ** 2 + (ly - 0.3 * n) ** 2) / (0.05 * n * n)))


def in_holes(x, y, holes):
    lx, ly = x - X0, Y0 - y
    inside = False
    for hx, hy, hr in holes:
        h = (lx - hx) ** 2 + (ly - hy) ** 2 < hr * hr
        inside = (inside | h) if np else (inside or h)
    return inside


def moved_height(x, y):
    """B's height at its node (x, y): the point p of A's surface with
    (K^-1 p).xy = (x, y), found by iterating on B's height; with a stretch,
    (x, y) is first taken back to where it was before it."""
    x = centre[0] + (x - centre[0]) / (1.0 + stretch)
    z = terrain(x, y)
    for _ in range(8):
        px = K[0][0] * x + K[0][1] * y + K[0][2] * z + K[0][3]
        py = K[1][0] * x + K[1][1] * y + K[1][2] * z + K[1][3]
        pz = K[2][0] * x + K[2][1] * y + K[2][2] * z + K[2][3]
        z = z - (pz - terrain(px, py)) / K[2][2]
    return z, px, py


def write(name, x0, y0, holes, moved):
    with open(os.path.join(out, name + ".bil"), "wb") as f:
        for r0 in range(0, n, 256):
            rows = range(r0, min(n, r0 + 256))
            if np:
                y = y0 - (np.arange(r0, min(n, r0 + 256))[:, None] + 0.5)
                x = x0 + (np.arange(n)[None, :] + 0.5)
                x, y = np.broadcast_arrays(x, y)
                if moved:
                    z, px, py = moved_height(x, y)
                    z = np.where(in_holes(px, py, holes[:2]) | in_holes(x, y, holes[2:]), -9999.0, z)
                else:
                    z = np.where(in_holes(x, y, holes), -9999.0, terrain(x, y))
                f.write(z.astype("<f4").tobytes())
                continue
            for r in rows:
                values = []
                y = y0 - (r + 0.5)
                for c in range(n):
                    x = x0 + (c + 0.5)
                    if moved:
                        z, px, py = moved_height(x, y)
                        hole = in_holes(px, py, holes[:2]) or in_holes(x, y, holes[2:])
                    else:
                        z, hole = terrain(x, y), in_holes(x, y, holes)
                    values.append(-9999.0 if hole else z)
                f.write(struct.pack("<%df" % n, *values))
    with open(os.path.join(out, name + ".hdr"), "w") as f:
        f.write(f"BYTEORDER I\nLAYOUT BIL\nNROWS {n}\nNCOLS {n}\nNBANDS 1\nNBITS 32\n"
                f"PIXELTYPE FLOAT\nULXMAP {x0 + 0.5}\nULYMAP {y0 - 0.5}\n"
                f"XDIM 1\nYDIM 1\nNODATA -9999\n")


# A's holes (in A's frame: B has them where A has, moved), then B's own.
holes = [(0.3 * n, 0.3 * n, 0.04 * n), (0.7 * n, 0.6 * n, 9.0), (0.5 * n, 0.8 * n, 0.03 * n)]
write("a", X0, Y0, holes[:2], False)
write("b", X0 + 0.37, Y0 + 0.61, holes, True)
with open(os.path.join(out, "known.txt"), "w") as f:
    f.write(" ".join("%.17g" % v for row in K for v in row) + "\n")
