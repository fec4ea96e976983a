#!/usr/bin/env python3
"""Makes the example pairs of `surfreg align`, each with a known motion.

Usage: python3 configs/data/make_align_examples.py DATA_DIR

DATA_DIR holds volcano.xyz and mannequin_face_dense.xyz (configs/data/).

  volcano_moved.xyz  an irregular resampling of the volcano grid (COUNT
                     points uniformly random in its extent, heights the
                     grid's bilinear interpolation), then moved by a known
                     rigid motion: about 2 degrees about a tilted axis and a
                     shift of a few grid spacings. Its reference is
                     volcano_a.xyz (the grid itself).
  face_a.xyz         a random subset of the dense mannequin face scan.
  face_b_moved.xyz   another, disjoint random subset of the same scan, moved
                     by a known motion: about 3 degrees and 0.1 units.

Each motion is p_moved = R (p - c) + c + s (R: a rotation of ANGLE degrees
about the unit AXIS, c a centre, s a shift). `surfreg align` recovers the
inverse, reference_from_moving, written in each moved file's header as a
row-major 4x4 JSON matrix on the line "# reference_from_moving: [...]".

Standard library only, deterministic: rerunning rewrites identical files.
"""
import json
import math
import os
import random
import sys

sys.dont_write_bytecode = True  # no __pycache__ in configs/data
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_volcano_pair as pair  # noqa: E402  (the grid reader and bilinear interpolation)

VOLCANO = dict(seed=20240611, count=4000, angle_deg=2.0, axis=(0.4, -0.3, 0.866),
               centre=(430.0, 300.0, 140.0), shift=(23.0, -17.0, 2.5), decimals=3)
FACE = dict(seed=20240612, count=15000, angle_deg=3.0, axis=(0.3, 0.9, -0.2),
            centre=(0.0, 0.5, 8.0), shift=(0.06, -0.07, 0.05), decimals=6)
VOLCANO_LICENCE = pair.LICENCE
FACE_LICENCE = ("# licence: as the CGAL demo data it is derived from (Debian libcgal-demo; "
                "see /usr/share/doc/libcgal-dev/copyright: LGPL/GPL, files without their own "
                "notice CC0 1.0)")


def rotation(axis, angle_deg):
    """The 3x3 rotation matrix (rows) of angle_deg about axis (Rodrigues)."""
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    t = math.radians(angle_deg)
    c, s, v = math.cos(t), math.sin(t), 1 - math.cos(t)
    return [[c + x * x * v, x * y * v - z * s, x * z * v + y * s],
            [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
            [z * x * v - y * s, z * y * v + x * s, c + z * z * v]]


def move(p, r, centre, shift):
    """R (p - c) + c + s."""
    d = [p[k] - centre[k] for k in range(3)]
    return [sum(r[i][k] * d[k] for k in range(3)) + centre[i] + shift[i] for i in range(3)]


def reference_from_moving(r, centre, shift):
    """The inverse motion as a 4x4 matrix: p = R^T (q - c - s) + c."""
    rt = [[r[k][i] for k in range(3)] for i in range(3)]
    cs = [centre[k] + shift[k] for k in range(3)]
    t = [centre[i] - sum(rt[i][k] * cs[k] for k in range(3)) for i in range(3)]
    return [rt[i] + [t[i]] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def motion_header(spec, r):
    """Comment lines stating the known motion and the matrix align should find."""
    n = math.sqrt(sum(a * a for a in spec["axis"]))
    axis = ", ".join(f"{a / n:.9f}" for a in spec["axis"])
    matrix = reference_from_moving(r, spec["centre"], spec["shift"])
    return [
        "# known motion: p_moved = R (p - c) + c + s, with R a rotation of "
        f"{spec['angle_deg']:g} deg about the unit axis ({axis}),",
        f"#   c = {list(spec['centre'])}, s = {list(spec['shift'])}"
        f" (coordinates rounded to {spec['decimals']} decimals after the motion)",
        "# reference_from_moving: " + json.dumps([[round(v, 15) for v in row] for row in matrix]),
    ]


def write(path, header, points, decimals):
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        for line in header:
            f.write(line + "\n")
        for p in points:
            f.write(" ".join(f"{v:.{decimals}f}" for v in p) + "\n")


def read_points(path):
    """(header comment lines, [(x, y, z), ...]) of an 'x y z' file."""
    header, points = [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("#"):
                header.append(line.rstrip("\n"))
            elif line.strip():
                points.append(tuple(float(v) for v in line.split()[:3]))
    return header, points


def volcano(data_dir):
    header, _, z_at = pair.read_grid(os.path.join(data_dir, "volcano.xyz"))
    xs, ys = pair.grid_axes(z_at)
    spec = VOLCANO
    rng = random.Random(spec["seed"])
    r = rotation(spec["axis"], spec["angle_deg"])
    points = []
    for _ in range(spec["count"]):
        x = xs[0] + (xs[-1] - xs[0]) * rng.random()
        y = ys[0] + (ys[-1] - ys[0]) * rng.random()
        points.append(move((x, y, pair.bilinear(z_at, xs, ys, x, y)), r, spec["centre"],
                           spec["shift"]))
    lines = [h for h in header if not h.startswith("# columns:")] + [
        "# volcano_moved: the moving surface of the terrain_volcano align example, made by "
        "make_align_examples.py:",
        f"#   {spec['count']} points uniformly random in the grid's extent (python "
        f"random.Random({spec['seed']}); per point x then y), z = bilinear interpolation of "
        "the grid, then moved:",
    ] + motion_header(spec, r) + [VOLCANO_LICENCE, "# columns: x_m y_m z_m"]
    write(os.path.join(data_dir, "volcano_moved.xyz"), lines, points, spec["decimals"])
    return r


def face(data_dir):
    header, points = read_points(os.path.join(data_dir, "mannequin_face_dense.xyz"))
    spec = FACE
    order = list(range(len(points)))
    random.Random(spec["seed"]).shuffle(order)
    count = spec["count"]
    subset_a, subset_b = sorted(order[:count]), sorted(order[count:2 * count])
    source = [h for h in header if not h.startswith("# columns:")]
    columns = [h for h in header if h.startswith("# columns:")]
    made = (f"random.Random({spec['seed']}).shuffle of the {len(points)} point indices; "
            f"A = the first {count}, B = the next {count} (disjoint), each kept in file order")
    write(os.path.join(data_dir, "face_a.xyz"),
          source + ["# face_a: the reference surface of the face_mannequin align example, "
                    "made by make_align_examples.py from mannequin_face_dense.xyz:",
                    "#   " + made, FACE_LICENCE] + columns,
          [points[i] for i in subset_a], spec["decimals"])
    r = rotation(spec["axis"], spec["angle_deg"])
    moved = [move(points[i], r, spec["centre"], spec["shift"]) for i in subset_b]
    write(os.path.join(data_dir, "face_b_moved.xyz"),
          source + ["# face_b_moved: the moving surface of the face_mannequin align example, "
                    "made by make_align_examples.py from mannequin_face_dense.xyz:",
                    "#   " + made + "; B then moved:"] + motion_header(spec, r) +
          [FACE_LICENCE] + columns,
          moved, spec["decimals"])
    return r


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__.split("\n\n")[1])
    data_dir = sys.argv[1]
    for name, spec, make in (("volcano_moved.xyz", VOLCANO, volcano),
                             ("face_b_moved.xyz", FACE, face)):
        r = make(data_dir)
        print(f"{name}: rotation {spec['angle_deg']:g} deg about {spec['axis']} at "
              f"{spec['centre']}, shift {spec['shift']}")
        for row in reference_from_moving(r, spec["centre"], spec["shift"]):
            print("  " + " ".join(f"{v:17.12f}" for v in row))


if __name__ == "__main__":
    main()
