#!/usr/bin/env python3
"""Makes the sample surface pair volcano_a.xyz / volcano_b.xyz.

Usage: python3 configs/data/make_volcano_pair.py VOLCANO_XYZ OUT_DIR

VOLCANO_XYZ is the Maunga Whau grid as shipped in configs/data/volcano.xyz
(87 x 61 nodes, 10 m spacing, "x y z" lines, '#' header comments).

  volcano_a.xyz  the grid itself: the input's header comments and data lines
                 unchanged, plus two comment lines before the "# columns:" one
                 (what the file is, the licence).
  volcano_b.xyz  an irregular resampling of the same terrain: COUNT points
                 uniformly random in the grid's xy extent (Python's
                 random.Random(SEED), x then y per point), x and y rounded to
                 3 decimals, z the bilinear interpolation of the grid at the
                 rounded (x, y), printed with 3 decimals.

Standard library only, deterministic: rerunning rewrites identical files.
"""
import os
import random
import sys

SEED = 20100401
COUNT = 4000
LICENCE = ("# licence: GPL (R package 'datasets', part of R, GPL-2 | GPL-3); "
           "the data are R's, these files are derived from them")


def read_grid(path):
    """Returns (header comment lines, data lines, {(x, y): z}) of a grid file."""
    header, lines, z_at = [], [], {}
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            text = line.rstrip("\n")
            if text.startswith("#"):
                if lines:
                    sys.exit(f"{path}:{number}: comment after the data")
                header.append(text)
                continue
            if not text.strip():
                continue
            fields = text.split()
            if len(fields) != 3:
                sys.exit(f"{path}:{number}: expected 'x y z', got {text!r}")
            x, y, z = (float(v) for v in fields)
            if (x, y) in z_at:
                sys.exit(f"{path}:{number}: duplicate node ({x}, {y})")
            z_at[(x, y)] = z
            lines.append(text)
    return header, lines, z_at


def grid_axes(z_at):
    """The sorted distinct x and y of a complete, evenly spaced grid."""
    xs = sorted({x for x, _ in z_at})
    ys = sorted({y for _, y in z_at})
    if len(xs) * len(ys) != len(z_at):
        sys.exit(f"not a complete grid: {len(xs)} x {len(ys)} != {len(z_at)} nodes")
    for axis in (xs, ys):
        steps = {round(b - a, 9) for a, b in zip(axis, axis[1:])}
        if len(steps) != 1:
            sys.exit(f"grid spacing is not uniform: {sorted(steps)}")
    return xs, ys


def bilinear(z_at, xs, ys, x, y):
    """Bilinear interpolation of the grid at (x, y) inside its extent."""
    dx, dy = xs[1] - xs[0], ys[1] - ys[0]
    i = min(int((x - xs[0]) // dx), len(xs) - 2)
    j = min(int((y - ys[0]) // dy), len(ys) - 2)
    u = (x - xs[i]) / dx
    v = (y - ys[j]) / dy
    z00 = z_at[(xs[i], ys[j])]
    z10 = z_at[(xs[i + 1], ys[j])]
    z01 = z_at[(xs[i], ys[j + 1])]
    z11 = z_at[(xs[i + 1], ys[j + 1])]
    return (1 - u) * (1 - v) * z00 + u * (1 - v) * z10 + (1 - u) * v * z01 + u * v * z11


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.split("\n\n")[1])
    source, out_dir = sys.argv[1], sys.argv[2]
    header, lines, z_at = read_grid(source)
    xs, ys = grid_axes(z_at)
    x0, x1, y0, y1 = xs[0], xs[-1], ys[0], ys[-1]
    source_header = [h for h in header if not h.startswith("# columns:")]

    with open(os.path.join(out_dir, "volcano_a.xyz"), "w", encoding="utf-8", newline="\n") as f:
        for h in source_header:
            f.write(h + "\n")
        f.write(f"# volcano_a: surface A of the sample pair, the {len(xs)} x {len(ys)} grid "
                "exactly as in configs/data/volcano.xyz (made by make_volcano_pair.py)\n")
        f.write(LICENCE + "\n")
        for h in header:
            if h.startswith("# columns:"):
                f.write(h + "\n")
        for text in lines:
            f.write(text + "\n")

    rng = random.Random(SEED)
    with open(os.path.join(out_dir, "volcano_b.xyz"), "w", encoding="utf-8", newline="\n") as f:
        for h in source_header:
            f.write(h + "\n")
        f.write("# volcano_b: surface B of the sample pair, an irregular resampling of the "
                "grid above (volcano_a.xyz), made by make_volcano_pair.py:\n")
        f.write(f"#   {COUNT} points uniformly random in the grid's extent "
                f"[{x0:g}, {x1:g}] x [{y0:g}, {y1:g}] m "
                f"(python random.Random({SEED}); per point x then y, "
                "each lo + (hi - lo) * random()),\n")
        f.write("#   x and y rounded to 3 decimals; z = bilinear interpolation of the grid "
                "at the rounded (x, y), rounded to 3 decimals\n")
        f.write(LICENCE + "\n")
        f.write("# columns: x_m y_m z_m\n")
        for _ in range(COUNT):
            x = round(x0 + (x1 - x0) * rng.random(), 3)
            y = round(y0 + (y1 - y0) * rng.random(), 3)
            z = bilinear(z_at, xs, ys, x, y)
            f.write(f"{x:.3f} {y:.3f} {z:.3f}\n")


if __name__ == "__main__":
    main()
