#!/usr/bin/env python3
"""Registration test pairs for the peer benchmark (deterministic, seeded).

    make_pairs.py --data configs/data --out DIR [--seeds 3] [--seed 20240611]
                  [--sampling random|grid|lines_same_heading|lines_irregular]
                  [--thin reference|moving --thin_factor K]

Writes DIR/<family>_<variant>_s<k>/{reference.xyz, moving.xyz, truth.json}.
truth.json holds `matrix`, the true 4x4 row-major transform moving -> reference
(input coordinates), `spacing` (sqrt(xy hull area / N) of the moving cloud
before the motion, before any thinning) and the pair's description. With
--thin, one cloud keeps a seeded random 1/K of its points (pairs sampled at
different densities; the pair's name gets _thin<K><r|m>). See
tests/bench/README.md.
"""
import argparse
import json
import math
import os

import numpy as np
from scipy.interpolate import RectBivariateSpline
from scipy.spatial import ConvexHull, Delaunay

FAMILIES = ["volcano", "jacksboro", "lidar", "face"]
VARIANTS = ["clean", "noise", "overlap60"]
TERRAIN_NOISE_M = 0.5      # z-noise sigma for terrain (metres)
FACE_NOISE_SPACINGS = 0.1  # z-noise sigma for faces (sample spacings)
FACE_POINTS = 15000        # per cloud (before an overlap crop)
JACKSBORO_CELLS = 100      # terrain crop, cells per side
LIDAR_CELLS = 96           # LIDAR crop: about 2 points per cell -> ~18.4k points
ROT_DEG = (1.0, 5.0)       # rotation angle range
TRANS_SPACINGS = (2.0, 10.0)
OVERLAP = 0.6


def load_xyz(path):
    return np.loadtxt(path, comments="#", dtype=float)[:, :3]


class GridSurface:
    """Bicubic interpolating spline of x, y and z over grid index space (u, v)
    (the Jacksboro grid is lat/lon cells in a transverse Mercator frame, so x, y
    are smooth functions of the indices, not an exact lattice)."""

    def __init__(self, grid):
        nu, nv = grid.shape[:2]
        u, v = np.arange(nu, dtype=float), np.arange(nv, dtype=float)
        self.splines = [RectBivariateSpline(u, v, grid[:, :, k], kx=3, ky=3, s=0)
                        for k in range(3)]
        self.size = (nu - 1.0, nv - 1.0)  # extent in cells

    def __call__(self, uv):
        return np.column_stack([s.ev(uv[:, 0], uv[:, 1]) for s in self.splines])


def random_rotation(rng, deg):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    a = math.radians(deg)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)


def overlap_draws(rng):
    return rng.random(), rng.random() < 0.5, rng.random(2) < 0.5


def overlap_windows(draws, size, q=OVERLAP):
    """Two equal windows in [0, size[0]] x [0, size[1]], shifted so each overlaps
    the other by q of its area: (1 - fx)(1 - fy) = q."""
    u, swap, flips = draws
    fx = u * (1.0 - q)
    fy = 1.0 - q / (1.0 - fx)
    if swap:
        fx, fy = fy, fx
    w, h = size[0] / (1 + fx), size[1] / (1 + fy)
    lo_a, lo_b = np.zeros(2), np.array([fx * w, fy * h])
    for k in range(2):  # random side of the shift per axis
        if flips[k]:
            lo_a[k], lo_b[k] = lo_b[k], lo_a[k]
    return (lo_a, lo_a + [w, h]), (lo_b, lo_b + [w, h])


def inside(p, win):
    return np.all((p[:, :2] >= win[0]) & (p[:, :2] <= win[1]), axis=1)


def uniform_uv(rng, win, n):
    return win[0] + rng.random((n, 2)) * (np.asarray(win[1]) - win[0])


# How terrain is sampled (--sampling): `random` (the benchmark: uniform points,
# LIDAR lines at random headings), or one regular pattern to test against:
# `grid` (terrain on regular grids, the moving one offset by a random
# fraction of a cell), `lines_same_heading` (both LIDAR clouds' lines at one
# heading per pair), `lines_irregular` (LIDAR lines at random offsets).
SAMPLING = "random"


def scan_lines(rng, win, across=1.0, along=0.5, jitter=0.1, heading=None):
    """A LIDAR-like survey of a window (grid-index units): parallel lines
    `across` apart at a random heading (or `heading`) and offset, samples
    `along` apart, each line with its own along-track phase, positions
    jittered (Gaussian)."""
    lo, hi = np.asarray(win[0], float), np.asarray(win[1], float)
    th = rng.uniform(0, math.pi) if heading is None else heading
    d = np.array([math.cos(th), math.sin(th)])   # along-track
    nrm = np.array([-d[1], d[0]])                # across-track
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [lo[0], hi[1]], [hi[0], hi[1]]])
    a, b = corners @ nrm, corners @ d
    pts = []
    offsets = np.arange(a.min() + rng.uniform(0, across), a.max(), across)
    if SAMPLING == "lines_irregular":
        offsets = np.sort(rng.uniform(a.min(), a.max(), len(offsets)))
    for a_k in offsets:
        bs = np.arange(b.min() + rng.uniform(0, along), b.max(), along)
        pts.append(a_k * nrm + bs[:, None] * d)
    p = np.concatenate(pts)
    p += rng.normal(scale=jitter, size=p.shape)
    return p[inside(p, (lo, hi))]


def hull_area(xy):
    return ConvexHull(xy).volume


def fraction_inside(p, q):
    """Fraction of points p whose xy lies in the convex hull of q's xy."""
    return float(np.mean(Delaunay(q[:, :2]).find_simplex(p[:, :2]) >= 0))


def terrain_clouds(rng, family, variant, grids):
    if family == "volcano":
        surf = grids["volcano"]
    else:
        g = grids["jacksboro"]
        cells = JACKSBORO_CELLS if family == "jacksboro" else LIDAR_CELLS
        r0 = rng.integers(0, g.shape[0] - cells)
        c0 = rng.integers(0, g.shape[1] - cells)
        surf = GridSurface(g[r0:r0 + cells + 1, c0:c0 + cells + 1])
    full = ((0.0, 0.0), surf.size)
    win_a, win_b = overlap_windows(overlap_draws(rng), surf.size) if variant == "overlap60" else (full, full)

    heading = rng.uniform(0, math.pi) if SAMPLING == "lines_same_heading" else None

    def sample(win):
        if family == "lidar":
            uv = scan_lines(rng, win, heading=heading)
        elif SAMPLING == "grid":  # one point per grid cell, at a random sub-cell offset
            lo, hi = np.asarray(win[0], float), np.asarray(win[1], float)
            start = np.floor(lo) + rng.random(2)
            u, v = np.arange(start[0], hi[0], 1.0), np.arange(start[1], hi[1], 1.0)
            uu, vv = np.meshgrid(u[u >= lo[0]], v[v >= lo[1]], indexing="ij")
            uv = np.column_stack([uu.ravel(), vv.ravel()])
        else:  # about one point per grid cell of the window
            area = np.prod(np.asarray(win[1]) - win[0])
            uv = uniform_uv(rng, win, int(round(area)))
        return surf(uv)

    ref, mov = sample(win_a), sample(win_b)
    return ref, mov, (TERRAIN_NOISE_M if variant == "noise" else 0.0), "m"


def face_clouds(rng, variant, face):
    order = rng.permutation(len(face))
    ref, mov = face[order[:FACE_POINTS]], face[order[FACE_POINTS:2 * FACE_POINTS]]
    if variant == "overlap60":
        # The face is an ellipse, not its bounding box: pick the windows' box
        # overlap q by bisection so that OVERLAP of the face points in each
        # window lie in both.
        xy = face[:, :2] - face[:, :2].min(0)
        size, draws = xy.max(0), overlap_draws(rng)
        lo_q, hi_q = 0.2, 0.95
        for _ in range(30):
            q = 0.5 * (lo_q + hi_q)
            win_a, win_b = overlap_windows(draws, size, q)
            in_a, in_b = inside(xy, win_a), inside(xy, win_b)
            both = np.sum(in_a & in_b)
            frac = 0.5 * (both / in_a.sum() + both / in_b.sum())
            lo_q, hi_q = (q, hi_q) if frac < OVERLAP else (lo_q, q)
        ref = ref[inside(ref[:, :2] - face[:, :2].min(0), win_a)]
        mov = mov[inside(mov[:, :2] - face[:, :2].min(0), win_b)]
    spacing = math.sqrt(hull_area(mov[:, :2]) / len(mov))
    return ref, mov, (FACE_NOISE_SPACINGS * spacing if variant == "noise" else 0.0), "model units"


def make_pair(rng, family, variant, grids, face):
    if family == "face":
        ref, mov, sigma, units = face_clouds(rng, variant, face)
    else:
        ref, mov, sigma, units = terrain_clouds(rng, family, variant, grids)
    if sigma > 0:
        ref = ref + np.column_stack([np.zeros((len(ref), 2)), rng.normal(scale=sigma, size=len(ref))])
        mov = mov + np.column_stack([np.zeros((len(mov), 2)), rng.normal(scale=sigma, size=len(mov))])
    spacing = math.sqrt(hull_area(mov[:, :2]) / len(mov))
    overlap_ref, overlap_mov = fraction_inside(ref, mov), fraction_inside(mov, ref)

    # Motion M about the true-position centroid c0: p -> R(p - c0) + c0 + t;
    # the moving file holds M(mov), the truth is M^-1 (rotation R^T about the
    # moved centroid c0 + t, then translation -t).
    deg = rng.uniform(*ROT_DEG)
    rot = random_rotation(rng, deg)
    tdir = rng.normal(size=3)
    t = tdir / np.linalg.norm(tdir) * rng.uniform(*TRANS_SPACINGS) * spacing
    c0 = mov.mean(0)
    moved = (mov - c0) @ rot.T + c0 + t
    truth = np.eye(4)
    truth[:3, :3] = rot.T
    truth[:3, 3] = c0 - rot.T @ (c0 + t)
    return ref, moved, truth, {
        "spacing": spacing, "units": units, "noise_sigma": sigma,
        "true_rotation_deg": deg, "true_translation_spacings": float(np.linalg.norm(t) / spacing),
        "n_reference": len(ref), "n_moving": len(moved),
        "overlap_of_reference": overlap_ref, "overlap_of_moving": overlap_mov,
    }


def write_xyz(path, p, comment):
    np.savetxt(path, p, fmt="%.6f", header=comment, comments="# ")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=os.path.join(os.path.dirname(__file__), "../../../configs/data"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--seed", type=int, default=20240611)
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--sampling", default="random",
                    choices=["random", "grid", "lines_same_heading", "lines_irregular"],
                    help="terrain sampling: the benchmark's (random) or a regular pattern to test against")
    ap.add_argument("--thin", default="none", choices=["none", "reference", "moving"],
                    help="keep 1/thin_factor of this cloud's points (different densities)")
    ap.add_argument("--thin_factor", type=int, default=4)
    args = ap.parse_args()
    global SAMPLING
    SAMPLING = args.sampling

    volcano = load_xyz(os.path.join(args.data, "volcano.xyz")).reshape(87, 61, 3)
    jacksboro = load_xyz(os.path.join(args.data, "jacksboro_fault_dem.xyz")).reshape(344, 403, 3)
    face = load_xyz(os.path.join(args.data, "mannequin_face_dense.xyz"))
    grids = {"volcano": GridSurface(volcano), "jacksboro": jacksboro}
    sources = {"volcano": "volcano.xyz", "jacksboro": "jacksboro_fault_dem.xyz",
               "lidar": "jacksboro_fault_dem.xyz", "face": "mannequin_face_dense.xyz"}

    os.makedirs(args.out, exist_ok=True)
    for family in args.families.split(","):
        for variant in args.variants.split(","):
            for k in range(args.seeds):
                rng = np.random.default_rng([args.seed, FAMILIES.index(family), VARIANTS.index(variant), k])
                ref, mov, truth, info = make_pair(rng, family, variant, grids, face)
                label = variant
                if args.thin != "none":
                    keep = lambda p: p[np.sort(rng.permutation(len(p))[:max(3, len(p) // args.thin_factor)])]
                    if args.thin == "reference":
                        ref = keep(ref)
                    else:
                        mov = keep(mov)
                    info.update(n_reference=len(ref), n_moving=len(mov), thinned=args.thin,
                                thin_factor=args.thin_factor)
                    label = f"{variant}_thin{args.thin_factor}{args.thin[0]}"
                name = f"{family}_{label}_s{k}"
                d = os.path.join(args.out, name)
                os.makedirs(d, exist_ok=True)
                tag = f"{name} from {sources[family]} (make_pairs.py, seed {args.seed})"
                write_xyz(os.path.join(d, "reference.xyz"), ref, f"reference of {tag}")
                write_xyz(os.path.join(d, "moving.xyz"), mov, f"moving of {tag}")
                meta = {"name": name, "family": family, "variant": label, "seed_index": k,
                        "source": sources[family], "matrix": truth.tolist(), **info}
                with open(os.path.join(d, "truth.json"), "w") as f:
                    json.dump(meta, f, indent=1)
                print(f"{name}: {info['n_reference']} / {info['n_moving']} points, spacing "
                      f"{info['spacing']:.4g}, rotation {info['true_rotation_deg']:.2f} deg, translation "
                      f"{info['true_translation_spacings']:.2f} spacings, overlap "
                      f"{info['overlap_of_reference']:.2f}/{info['overlap_of_moving']:.2f}")


if __name__ == "__main__":
    main()
