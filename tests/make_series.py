"""A series of surveys with known motions, for `surfreg series` (issue 48):
tests/cli_series_test.sh and tests/bench/run_series_bench.sh.

From a grid surface ("x y z" lines of a regular grid, e.g.
configs/data/jacksboro_fault_dem.xyz), N epochs, each its own random
resampling of the grid's bilinear surface (points uniform in its window),
with Gaussian height noise, then moved by the inverse of its own known
motion world_from_epoch (a rotation of a few tenths of a degree about a
random axis through the epoch's centroid and a shift of a few sample
spacings), so that an alignment must find that motion.

Layouts:
  strips  windows sliding along x, each a quarter of its width past the
          previous: neighbours overlap by 3/4, the next but one by 1/2, and
          epochs four apart not at all.
  repeat  windows over most of the grid (each trimmed by a random tenth on
          every side), with a change growing from epoch to epoch: a
          landslide (a Gaussian depression) of CHANGE metres per epoch on a
          fifth of the width: the stable terrain must be found.
  chewing GRID is a face scan's points (configs/data/mannequin_face_dense.xyz,
          model units), scaled to millimetres (x 6) and centred (max z = 0);
          each frame a random subset of them (different samplings of one
          scan), the part below the mouth line (y < -35 mm) opened as a jaw
          by up to CHANGE degrees about a hinge behind the face (0, 10, -90)
          mm over a chewing cycle of 8 frames: the skull is the stable part,
          and the known motions are the head's.

Writes DIR/e<k>.xyz and DIR/truth.json: {"world_from_epoch": [16 numbers
row-major per epoch], "spacing": the grid's spacing}. The epochs' truth
relative to epoch r is inverse(W_r) W_k.

Usage: make_series.py GRID.xyz DIR EPOCHS LAYOUT SEED [POINTS] [NOISE] [CHANGE]
"""
import json
import math
import os
import random
import re
import sys


def read_grid(path):
    """The grid's points in file order (rows of `columns` points): the header
    comment says its size ("344 rows x 403 cols", "87 x 61 matrix")."""
    rows = columns = None
    points = []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                m = re.search(r"(\d+)\s*(?:rows\s*)?x\s*(\d+)", line)
                if m and rows is None:
                    rows, columns = int(m.group(1)), int(m.group(2))
                continue
            parts = line.replace(",", " ").split()
            if len(parts) >= 3:
                points.append(tuple(float(v) for v in parts[:3]))
    if rows is None or rows * columns != len(points):
        sys.exit("%s: no '# R x C' grid size that matches its %d points" % (path, len(points)))
    return [points[r * columns:(r + 1) * columns] for r in range(rows)]


def bilinear(grid, u, v):
    """x, y, z at fractional row u and column v (coordinates and height
    alike: the grid may be a projected geographic one)."""
    i, j = min(int(u), len(grid) - 2), min(int(v), len(grid[0]) - 2)
    a, b = u - i, v - j
    p00, p01, p10, p11 = grid[i][j], grid[i][j + 1], grid[i + 1][j], grid[i + 1][j + 1]
    return tuple((1 - a) * (1 - b) * p00[k] + (1 - a) * b * p01[k] + a * (1 - b) * p10[k] + a * b * p11[k]
                 for k in range(3))


def read_face(path):
    """A face scan's points in millimetres, centred on the mean xy, max z = 0;
    and its mean sample spacing."""
    points = []
    with open(path) as f:
        for line in f:
            parts = line.split("#")[0].split()
            if len(parts) >= 3:
                points.append(tuple(6.0 * float(v) for v in parts[:3]))
    mx = sum(p[0] for p in points) / len(points)
    my = sum(p[1] for p in points) / len(points)
    top = max(p[2] for p in points)
    points = [(p[0] - mx, p[1] - my, p[2] - top) for p in points]
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    spacing = math.sqrt((max(xs) - min(xs)) * (max(ys) - min(ys)) * math.pi / 4 / len(points))
    return points, spacing


def chewing_frame(face, k, count, opening_deg, noise, rng):
    """Frame k: `count` of the scan's points, those below the mouth line
    turned about the hinge by the chewing cycle's opening, then noise."""
    alpha = math.radians(opening_deg * (1 - math.cos(2 * math.pi * k / 8)) / 2)
    hinge = (0.0, 10.0, -90.0)
    c, s = math.cos(alpha), math.sin(alpha)
    out = []
    for p in rng.sample(face, count):
        x, y, z = p
        if y < -35.0:
            # About the x axis through the hinge: the chin goes down and back.
            dy, dz = y - hinge[1], z - hinge[2]
            y, z = hinge[1] + c * dy - s * dz, hinge[2] + s * dy + c * dz
        out.append((x, y, z + rng.gauss(0, noise)))
    return out


def rotation(axis, angle):
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    c, s = math.cos(angle), math.sin(angle)
    t = 1 - c
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]


def main():
    grid_path, out, epochs, layout, seed = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], int(sys.argv[5])
    points = int(sys.argv[6]) if len(sys.argv) > 6 else 20000
    noise = float(sys.argv[7]) if len(sys.argv) > 7 else 0.5
    change = float(sys.argv[8]) if len(sys.argv) > 8 else 5.0
    rng = random.Random(seed)
    if layout == "chewing":
        face, spacing = read_face(grid_path)
    else:
        grid = read_grid(grid_path)
        rows, columns = len(grid), len(grid[0])
        spacing = math.dist(grid[0][0][:2], grid[0][1][:2])
    os.makedirs(out, exist_ok=True)
    # The landslide of the repeat layout, in grid indices: centre and radius.
    slide = (0.6 * rows, 0.35 * columns, 0.1 * columns) if layout != "chewing" else None
    truths = []
    for k in range(epochs):
        # The epoch's window in grid indices: rows [r0, r1], columns [c0, c1].
        samples = []
        if layout == "chewing":
            samples = chewing_frame(face, k, points, change, noise, rng)
        elif layout == "strips":
            width = (columns - 1) / (1 + (epochs - 1) / 4)
            r0, r1, c0, c1 = 0, rows - 1, k * width / 4, k * width / 4 + width
        elif layout == "repeat":
            r0, r1 = rng.uniform(0, 0.1) * rows, (rows - 1) * (1 - rng.uniform(0, 0.1))
            c0, c1 = rng.uniform(0, 0.1) * columns, (columns - 1) * (1 - rng.uniform(0, 0.1))
        else:
            sys.exit("layout must be strips, repeat or chewing")
        for _ in range(points if layout != "chewing" else 0):
            u, v = rng.uniform(r0, r1), rng.uniform(c0, c1)
            x, y, z = bilinear(grid, u, v)
            if layout == "repeat":
                d2 = (u - slide[0]) ** 2 + (v - slide[1]) ** 2
                z -= change * k * math.exp(-d2 / (2 * slide[2] ** 2))
            samples.append((x, y, z + rng.gauss(0, noise)))
        c = [sum(p[i] for p in samples) / len(samples) for i in range(3)]
        if k == 0:
            r, s = rotation((0, 0, 1), 0.0), (0.0, 0.0, 0.0)
        else:
            axis = (rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))
            r = rotation(axis, math.radians(rng.uniform(0.05, 0.3)))
            s = (rng.gauss(0, 2 * spacing), rng.gauss(0, 2 * spacing), rng.gauss(0, spacing))
        # world_from_epoch W(p) = R (p - c) + c + s; the epoch's points are W^-1 of the samples.
        t = [c[i] + s[i] - sum(r[i][j] * c[j] for j in range(3)) for i in range(3)]
        truths.append([r[0][0], r[0][1], r[0][2], t[0], r[1][0], r[1][1], r[1][2], t[1],
                       r[2][0], r[2][1], r[2][2], t[2], 0.0, 0.0, 0.0, 1.0])
        with open(os.path.join(out, "e%d.xyz" % k), "w") as f:
            f.write("# make_series.py %s %s epoch %d of %d, seed %d\n" % (os.path.basename(grid_path), layout, k,
                                                                        epochs, seed))
            for p in samples:
                q = [p[i] - t[i] for i in range(3)]
                e = [sum(r[j][i] * q[j] for j in range(3)) for i in range(3)]  # R^T (p - t)
                f.write("%.4f %.4f %.4f\n" % (e[0], e[1], e[2]))
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump({"world_from_epoch": truths, "spacing": spacing}, f)


main()
