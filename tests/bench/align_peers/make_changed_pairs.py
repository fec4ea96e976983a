#!/usr/bin/env python3
"""Changed surface pairs for the peer benchmark (deterministic, seeded): the
moving surface is the reference surface with part of it changed (terrain
between two surveys, a face whose jaw moved), then moved rigidly.

    make_changed_pairs.py --out DIR [--data configs/data] [--seeds 4] [--seed 20261202]
                          [--families glacier20,glacier35,glacier50,lidar_blobs,landslide,lake,face_jaw]

Writes DIR/<family>_s<k>/{reference.xyz, moving.xyz, reference_stable.xyz,
truth.json}. Sampling, noise model and motion are make_pairs.py's (imported,
not copied): two independent samplings of one surface (variant "noise"), the
change applied to the moving cloud in the true frame, then the same random
rigid motion (1-5 deg, 2-10 spacings); truth.json's `matrix` maps moving ->
reference. reference_stable.xyz is the reference with a 4th column, the
oracle's weight: 1 on truly stable terrain, 0 in the changed region (true
|dz| > 0; for the face the part that moved). See tests/bench/README.md.

Terrain: even seeds use a random 100 x 100-cell Jacksboro crop (relief
124-808 m), odd seeds the volcano (relief 101 m); lidar_blobs always uses the
LIDAR family's 96 x 96-cell Jacksboro crop and scan lines. Both reliefs are
above 100 m, so the glaciers' 5-30 m thinning is used as given; a flatter
terrain would scale it by relief / 100 m (recorded in truth.json).
"""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_pairs as mp  # noqa: E402  (reused as a module, not modified)

FAMILIES = ["glacier20", "glacier35", "glacier50", "lidar_blobs", "landslide", "lake", "face_jaw"]
VARIANT = "changed"
SOURCES = {"jacksboro": "jacksboro_fault_dem.xyz", "volcano": "volcano.xyz", "face": "mannequin_face_dense.xyz"}


# ---------------------------------------------------------------- sampling

def sample_terrain(rng, grids, terrain, lidar=False):
    """Two independent samplings (uv grid-index coordinates) of one surface,
    as make_pairs.terrain_clouds samples its full-window pairs, but keeping
    the surface and the uv so the change can be defined on them."""
    if terrain == "volcano":
        surf, where = grids["volcano"], "volcano (whole grid)"
    else:
        g = grids["jacksboro"]
        cells = mp.LIDAR_CELLS if lidar else mp.JACKSBORO_CELLS
        r0, c0 = rng.integers(0, g.shape[0] - cells), rng.integers(0, g.shape[1] - cells)
        surf = mp.GridSurface(g[r0:r0 + cells + 1, c0:c0 + cells + 1])
        where = f"jacksboro crop rows {r0}-{r0 + cells}, columns {c0}-{c0 + cells}"
    full = ((0.0, 0.0), surf.size)

    def uv():
        if lidar:
            return mp.scan_lines(rng, full)
        return mp.uniform_uv(rng, full, int(round(np.prod(surf.size))))

    return surf, uv(), uv(), where


# ---------------------------------------------------------------- changes
# Each returns (z_ref, z_mov, changed_ref, sigma_ref, sigma_mov, description):
# the noise-free z of both clouds, the reference samples in the changed region,
# per-point noise sigmas, and a description for truth.json.

def glacier(rng, t_ref, t_mov, share):
    """Top `share` of the elevations thins, most at the lowest ice (the
    thinning is correlated with elevation: the case that biases Nuth-Kaab)."""
    z_q = float(np.quantile(t_ref, 1.0 - share))
    z_top = float(max(t_ref.max(), t_mov.max()))
    relief = z_top - float(min(t_ref.min(), t_mov.min()))
    scale = min(1.0, relief / 100.0)  # 1 on all terrains used here
    lo, hi = 5.0 * scale, 30.0 * scale

    def thinning(t):
        return np.where(t > z_q, lo + (hi - lo) * (z_top - t) / (z_top - z_q), 0.0)

    desc = {"kind": "glacier thinning", "share_target": share, "z_quantile": z_q, "z_top": z_top,
            "thinning_m": [lo, hi], "relief_m": relief,
            "text": f"z > {z_q:.1f} (top {share:.0%} of elevations) lowered by {lo:.3g} m at the top to "
                    f"{hi:.3g} m at z = {z_q:.1f}, linear in z"}
    return t_ref, t_mov - thinning(t_mov), t_ref > z_q, np.ones(len(t_ref)), np.ones(len(t_mov)), desc


def blob_field(blobs, uv, scale):
    """Raise per point: the max over blobs; buildings flat-topped discs,
    trees smooth compact bumps h (1 - rho^2)^2."""
    dz = np.zeros(len(uv))
    for cu, cv, r, h, building in blobs:
        rho2 = ((uv[:, 0] - cu) ** 2 + (uv[:, 1] - cv) ** 2) / (r * scale) ** 2
        inside = rho2 < 1.0
        prof = np.where(inside, h if building else h * (1.0 - rho2) ** 2, 0.0)
        dz = np.maximum(dz, prof)
    return dz


def lidar_blobs(rng, surf, uv_ref, uv_mov, t_ref, t_mov, n=40, cover=0.16):
    size = np.asarray(surf.size)
    blobs = [(rng.uniform(0, size[0]), rng.uniform(0, size[1]), rng.uniform(0.6, 1.4),
              rng.uniform(3.0, 12.0), rng.random() < 0.5) for _ in range(n)]
    # Radii scaled (bisection) so the blobs' union covers `cover` of the crop,
    # measured on a 0.25-cell lattice (overlaps counted once).
    gu, gv = np.meshgrid(np.arange(0.125, size[0], 0.25), np.arange(0.125, size[1], 0.25), indexing="ij")
    lattice = np.column_stack([gu.ravel(), gv.ravel()])
    lo, hi = 0.5, 20.0
    for _ in range(40):
        s = 0.5 * (lo + hi)
        lo, hi = (s, hi) if np.mean(blob_field(blobs, lattice, s) > 0) < cover else (lo, s)
    s = 0.5 * (lo + hi)
    d_ref, d_mov = blob_field(blobs, uv_ref, s), blob_field(blobs, uv_mov, s)
    n_build = sum(b[4] for b in blobs)
    desc = {"kind": "raised blobs", "n_blobs": n, "n_buildings": int(n_build), "height_m": [3.0, 12.0],
            "radius_cells": [0.6 * s, 1.4 * s], "area_share": float(np.mean(blob_field(blobs, lattice, s) > 0)),
            "text": f"{n} blobs raised 3-12 m ({n_build} flat-topped discs, {n - n_build} smooth bumps), "
                    f"radius {0.6 * s:.1f}-{1.4 * s:.1f} cells"}
    return (t_ref, t_mov + d_mov, d_ref > 0, np.full(len(t_ref), 0.1), np.full(len(t_mov), 0.1), desc)


def landslide(rng, surf, uv_ref, uv_mov, t_ref, t_mov):
    """A scar (-40 m deepest) upslope and a deposit (+25 m) downslope, two
    touching ellipses (long axis across the slope), compact smooth bumps."""
    size = np.asarray(surf.size)
    # The centre: of 20 random candidates in the inner 60%, the one with the
    # steepest plane fit of its neighbourhood (a cone's summit has no slope).
    radius = 0.25 * size.min()
    best = None
    for _ in range(20):
        c = size * rng.uniform(0.2, 0.8, 2)
        near = np.sum((uv_ref - c) ** 2, axis=1) < radius ** 2
        a = np.column_stack([np.ones(near.sum()), uv_ref[near] - c])
        grad = np.linalg.lstsq(a, t_ref[near], rcond=None)[0][1:]
        if best is None or np.linalg.norm(grad) > np.linalg.norm(best[1]):
            best = (c, grad)
    c, grad = best
    down = -grad / np.linalg.norm(grad)
    across = np.array([-down[1], down[0]])
    share = rng.uniform(0.30, 0.40)
    ratio = rng.uniform(1.2, 1.6)  # across / along semi-axes

    def field(uv, a_len):
        d = uv - c
        s, q = d @ down, d @ across
        out = np.zeros(len(uv))
        for off, amp in ((-a_len, -40.0), (a_len, 25.0)):  # scar upslope, deposit downslope
            rho2 = ((s - off) / a_len) ** 2 + (q / (ratio * a_len)) ** 2
            out += np.where(rho2 < 1.0, amp * (1.0 - rho2) ** 2, 0.0)
        return out

    # Size by bisection on the measured share of reference samples (the
    # ellipses may reach the crop's edge).
    lo, hi = 1.0, size.max()
    for _ in range(40):
        a_len = 0.5 * (lo + hi)
        lo, hi = (a_len, hi) if np.mean(field(uv_ref, a_len) != 0) < share else (lo, a_len)
    a_len = 0.5 * (lo + hi)
    d_ref, d_mov = field(uv_ref, a_len), field(uv_mov, a_len)
    desc = {"kind": "landslide", "share_target": share, "centre_uv": c.tolist(), "downslope_uv": down.tolist(),
            "semi_axes_cells": [a_len, ratio * a_len], "scar_m": -40.0, "deposit_m": 25.0,
            "text": f"scar -40 m and deposit +25 m, ellipses {a_len:.1f} x {ratio * a_len:.1f} cells, "
                    f"downslope ({down[0]:.2f}, {down[1]:.2f}) in grid indices"}
    return (t_ref, t_mov + d_mov, d_ref != 0, np.full(len(t_ref), 0.5), np.full(len(t_mov), 0.5), desc)


def lake(rng, t_ref, t_mov):
    """A lake's flat surface L dropped by D: the changed region (terrain <
    L) is flat in the reference; water is quieter than land."""
    q, drop = rng.uniform(0.25, 0.35), rng.uniform(3.0, 8.0)
    level = float(np.quantile(t_ref, q))
    z_ref, z_mov = np.maximum(t_ref, level), np.maximum(t_mov, level - drop)
    s_ref = np.where(t_ref < level, 0.1, 0.5)
    s_mov = np.where(t_mov < level - drop, 0.1, 0.5)
    desc = {"kind": "lake drop", "level_quantile": q, "level": level, "drop_m": drop,
            "text": f"lake at z = {level:.1f} ({q:.0%} quantile) dropped by {drop:.2f} m"}
    return z_ref, z_mov, t_ref < level, s_ref, s_mov, desc


def face_jaw(rng, face):
    """make_pairs' face clouds; the moving cloud's lower third (by y, the
    face's vertical axis: chin at low y, nose tip near y = -1.5, z towards the
    viewer) turned about an x-direction hinge behind and above it, opening."""
    ref, mov, _, units = mp.face_clouds(rng, "noise", face)
    sigma = 0.05 * math.sqrt(mp.hull_area(mov[:, :2]) / len(mov))
    y0, y1 = face[:, 1].min(), face[:, 1].max()
    height = y1 - y0
    y_cut = y0 + height / 3.0
    # Hinge: half a third above the cut, a third of the face height behind
    # the median surface (about where a jaw joint sits behind a face).
    hinge = np.array([0.0, y_cut + height / 6.0, float(np.median(face[:, 2])) - height / 3.0])
    deg = rng.uniform(3.0, 5.0)
    a = math.radians(deg)  # about +x: +z turns towards -y, the chin moves down and back
    rot = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    jaw = mov[:, 1] < y_cut
    moved = mov.copy()
    moved[jaw] = (mov[jaw] - hinge) @ rot.T + hinge
    shift = np.linalg.norm(moved[jaw] - mov[jaw], axis=1)
    desc = {"kind": "jaw opening", "angle_deg": deg, "hinge": hinge.tolist(), "y_cut": y_cut,
            "mean_shift": float(shift.mean()),
            "text": f"y < {y_cut:.2f} (lower third) turned {deg:.2f} deg about the x-direction hinge through "
                    f"y = {hinge[1]:.2f}, z = {hinge[2]:.2f} (mean shift {shift.mean():.3g} {units})"}
    return ref, moved, ref[:, 1] < y_cut, np.full(len(ref), sigma), np.full(len(mov), sigma), desc, units


# ---------------------------------------------------------------- pairs

def rigid_motion(rng, mov, spacing):
    """make_pairs.make_pair's motion, the same draws in the same order: M
    about the centroid c0, p -> R(p - c0) + c0 + t; the truth is M^-1."""
    deg = rng.uniform(*mp.ROT_DEG)
    rot = mp.random_rotation(rng, deg)
    tdir = rng.normal(size=3)
    t = tdir / np.linalg.norm(tdir) * rng.uniform(*mp.TRANS_SPACINGS) * spacing
    c0 = mov.mean(0)
    truth = np.eye(4)
    truth[:3, :3] = rot.T
    truth[:3, 3] = c0 - rot.T @ (c0 + t)
    return (mov - c0) @ rot.T + c0 + t, truth, deg, float(np.linalg.norm(t) / spacing)


def make_changed_pair(rng, family, grids, face, k):
    if family == "face_jaw":
        ref, mov, changed, s_ref, s_mov, desc, units = face_jaw(rng, face)
        source, where = SOURCES["face"], "face"
    else:
        lidar = family == "lidar_blobs"
        terrain = "jacksboro" if lidar or k % 2 == 0 else "volcano"
        surf, uv_ref, uv_mov, where = sample_terrain(rng, grids, terrain, lidar)
        p_ref, p_mov = surf(uv_ref), surf(uv_mov)
        t_ref, t_mov = p_ref[:, 2], p_mov[:, 2]
        if family.startswith("glacier"):
            out = glacier(rng, t_ref, t_mov, int(family[len("glacier"):]) / 100.0)
        elif lidar:
            out = lidar_blobs(rng, surf, uv_ref, uv_mov, t_ref, t_mov)
        elif family == "landslide":
            out = landslide(rng, surf, uv_ref, uv_mov, t_ref, t_mov)
        elif family == "lake":
            out = lake(rng, t_ref, t_mov)
        else:
            raise ValueError(f"unknown family {family}")
        z_ref, z_mov, changed, s_ref, s_mov, desc = out
        ref = np.column_stack([p_ref[:, :2], z_ref])
        mov = np.column_stack([p_mov[:, :2], z_mov])
        source, units = SOURCES[terrain], "m"
    ref = ref.copy()
    mov = mov.copy()
    ref[:, 2] += rng.normal(size=len(ref)) * s_ref
    mov[:, 2] += rng.normal(size=len(mov)) * s_mov
    spacing = math.sqrt(mp.hull_area(mov[:, :2]) / len(mov))
    overlap_ref, overlap_mov = mp.fraction_inside(ref, mov), mp.fraction_inside(mov, ref)
    moved, truth, deg, trans = rigid_motion(rng, mov, spacing)
    info = {"spacing": spacing, "units": units, "noise_sigma": [float(s_ref.min()), float(s_ref.max())],
            "true_rotation_deg": deg, "true_translation_spacings": trans,
            "n_reference": len(ref), "n_moving": len(moved),
            "overlap_of_reference": overlap_ref, "overlap_of_moving": overlap_mov,
            "changed_share": float(np.mean(changed)), "change": desc, "surface": where}
    return ref, moved, changed, truth, source, info


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../configs/data"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--seed", type=int, default=20261202)
    ap.add_argument("--families", default=",".join(FAMILIES))
    args = ap.parse_args()
    families = [f for f in args.families.split(",") if f]
    for f in families:
        if f not in FAMILIES:
            ap.error(f"unknown family {f} (known: {', '.join(FAMILIES)})")

    volcano = mp.load_xyz(os.path.join(args.data, "volcano.xyz")).reshape(87, 61, 3)
    jacksboro = mp.load_xyz(os.path.join(args.data, "jacksboro_fault_dem.xyz")).reshape(344, 403, 3)
    face = mp.load_xyz(os.path.join(args.data, "mannequin_face_dense.xyz"))
    grids = {"volcano": mp.GridSurface(volcano), "jacksboro": jacksboro}

    os.makedirs(args.out, exist_ok=True)
    for family in families:
        for k in range(args.seeds):
            rng = np.random.default_rng([args.seed, FAMILIES.index(family), k])
            ref, mov, changed, truth, source, info = make_changed_pair(rng, family, grids, face, k)
            name = f"{family}_s{k}"
            d = os.path.join(args.out, name)
            os.makedirs(d, exist_ok=True)
            tag = f"{name} from {source} (make_changed_pairs.py, seed {args.seed})"
            mp.write_xyz(os.path.join(d, "reference.xyz"), ref, f"reference of {tag}")
            mp.write_xyz(os.path.join(d, "moving.xyz"), mov, f"moving of {tag}: {info['change']['text']}")
            mp.write_xyz(os.path.join(d, "reference_stable.xyz"),
                         np.column_stack([ref, np.where(changed, 0.0, 1.0)]),
                         f"reference of {tag}; 4th column: weight 1 on stable terrain, 0 in the changed region")
            meta = {"name": name, "family": family, "variant": VARIANT, "seed_index": k, "source": source,
                    "matrix": truth.tolist(), **info}
            with open(os.path.join(d, "truth.json"), "w") as f:
                json.dump(meta, f, indent=1)
            print(f"{name}: {info['n_reference']} / {info['n_moving']} points, spacing {info['spacing']:.4g}, "
                  f"changed {info['changed_share']:.1%} ({info['change']['text']}), rotation "
                  f"{info['true_rotation_deg']:.2f} deg, translation {info['true_translation_spacings']:.2f} spacings")


if __name__ == "__main__":
    main()
