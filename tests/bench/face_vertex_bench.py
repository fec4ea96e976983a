#!/usr/bin/env python3
"""Face pairs sampled at a mesh's vertices: surfreg align against Open3D ICP.

    /usr/bin/python3 tests/bench/face_vertex_bench.py --surfreg build/tools/surfreg
        [--out DIR] [--seeds 3] [--seed 20251206] [--families same,halves,...]
        [--surfreg_args="--flag=value ..."] [--methods surfreg,icp_plane,gicp]
        [--pairs_only] [--summary_only]

The face part of configs/data/mannequin_head.off (`surfreg normalize
--orientation=-90,0,0 --depth_limit=12`: 6991 vertices, 13188 triangles whose
three vertices are all kept) gives the clouds; each pair's moving cloud is
moved by make_pairs.py's motion (1-5 deg about a random axis through its
centroid, 2-10 spacings in a random direction) and the truth is its inverse.
Families (the reference first, then the moving cloud; V = the face mesh's
vertices; noise: Gaussian z-noise of 0.1 spacing on both clouds, independent):

  same            V and V (every sample in both clouds)
  same_noise      V and V, each with its own noise
  halves          two disjoint random halves of V
  halves_noise    the same with noise
  overlap70       two random 70% subsets of V (40% of V in both)
  subdiv          V and the vertices of its midpoint subdivision (V plus the
                  edge midpoints: V shared, the rest on V's linear surface)
  midpoints       V and the edge midpoints only (disjoint)
  decimated       V and the vertices of a quadric decimation to half of the
                  triangles (different vertices of nearly the same surface)
  loop            V and the vertices of one Loop subdivision (a smoother
                  surface through nearby points; the 11 vertices Open3D
                  leaves NaN dropped)

Pairs go to DIR/pairs/<family>_s<k>/ in make_pairs.py's layout (reference.xyz,
moving.xyz, truth.json), then align_peers/run_peers.py runs every method from
the identity with the peer benchmark's settings (Open3D point-to-plane and
generalized ICP: normals / covariances within 3 spacings, <= 30 neighbours,
maximum correspondence distance 7 -> 3 -> 1 spacings) and writes
DIR/align_peers.{csv,md}. Errors as there: the angle of R_est R_true^T
(degrees) and |T_est(c) - T_true(c)| / spacing at the moving centroid c.
Last, the summary (DIR/summary.md, also printed): per family the geometric
means of each method's errors and of the per-pair ratio surfreg / generalized
ICP, and the ratio's geometric mean over all pairs (target <= 0.7). DIR
defaults to build/bench-results/face_vertex. Deterministic (numpy's seeded
generator per family and seed; Open3D's mesh operations are deterministic).
About 3 minutes for 27 pairs on 2 cores. See tests/bench/README.md.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
import open3d as o3d
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "../.."))
sys.path.insert(0, os.path.join(HERE, "align_peers"))
import make_pairs  # noqa: E402  (the motion and the spacing, shared with the peer benchmark)
import run_peers  # noqa: E402  (the peers' settings and the error definitions)

FAMILIES = ["same", "same_noise", "halves", "halves_noise", "overlap70", "subdiv", "midpoints",
            "decimated", "loop"]
NOISE_SPACINGS = 0.1
# Errors below this (degrees, spacings) are the files' rounding (6 decimals):
# the ratio counts them as this, so two exact results score 1.
FLOOR = 1e-5
ORIENTATION = "-90,0,0"
DEPTH_LIMIT = 12


def read_off(path):
    rows = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    assert rows[0] == ["OFF"], path
    nv, nf = int(rows[1][0]), int(rows[1][1])
    v = np.array(rows[2:2 + nv], dtype=float)
    f = np.array([r[1:4] for r in rows[2 + nv:2 + nv + nf]], dtype=int)
    return v, f


def face_mesh(surfreg, mesh_path, work):
    """The face part of the mesh in the face frame: `surfreg normalize` gives
    the kept vertices and the frame's rotation and translation; the kept
    vertices are found among the mesh's transformed ones (exact to rounding)
    and the triangles with all three kept."""
    out = os.path.join(work, "face_frame.xyz")
    p = subprocess.run([surfreg, "normalize", mesh_path, f"--orientation={ORIENTATION}",
                        f"--depth_limit={DEPTH_LIMIT}", f"--output={out}", "--json"],
                       capture_output=True, text=True, check=True)
    info = json.loads(p.stdout[p.stdout.find("{"):])
    rot = np.array(info["rotation"], dtype=float).reshape(3, 3)
    v, f = read_off(mesh_path)
    w = v @ rot.T + np.array(info["translation"], dtype=float)
    kept = np.loadtxt(out, comments="#")[:, :3]
    dist, idx = cKDTree(w).query(kept)
    assert dist.max() < 1e-6, dist.max()
    keep = np.zeros(len(w), bool)
    keep[idx] = True
    tri = f[keep[f].all(axis=1)]
    new = -np.ones(len(w), int)
    new[keep] = np.arange(keep.sum())
    return w[keep], new[tri]


def o3d_mesh(v, t):
    return o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(v), o3d.utility.Vector3iVector(t))


def edge_midpoints(v, t):
    e = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    return 0.5 * (v[e[:, 0]] + v[e[:, 1]])


def clouds(family, rng, v, t):
    """The two clouds of a family, before the noise and the motion."""
    n = len(v)
    if family.startswith("same"):
        return v.copy(), v.copy()
    if family.startswith("halves"):
        order = rng.permutation(n)
        return v[np.sort(order[:n // 2])], v[np.sort(order[n // 2:])]
    if family == "overlap70":
        a, b = rng.permutation(n)[:int(0.7 * n)], rng.permutation(n)[:int(0.7 * n)]
        return v[np.sort(a)], v[np.sort(b)]
    if family == "subdiv":
        return v.copy(), np.asarray(o3d_mesh(v, t).subdivide_midpoint(1).vertices)
    if family == "midpoints":
        return v.copy(), edge_midpoints(v, t)
    if family == "decimated":
        m = o3d_mesh(v, t).simplify_quadric_decimation(len(t) // 2)
        m.remove_unreferenced_vertices()
        return v.copy(), np.asarray(m.vertices)
    if family == "loop":
        w = np.asarray(o3d_mesh(v, t).subdivide_loop(1).vertices)
        return v.copy(), w[np.isfinite(w).all(axis=1)]  # Open3D leaves 11 of 27182 NaN
    raise ValueError(family)


def make_pair(family, k, seed, v, t, d):
    rng = np.random.default_rng([seed, FAMILIES.index(family), k])
    ref, mov = clouds(family, rng, v, t)
    spacing = math.sqrt(make_pairs.hull_area(mov[:, :2]) / len(mov))
    sigma = NOISE_SPACINGS * spacing if family.endswith("_noise") else 0.0
    if sigma > 0:
        ref = ref + np.column_stack([np.zeros((len(ref), 2)), rng.normal(scale=sigma, size=len(ref))])
        mov = mov + np.column_stack([np.zeros((len(mov), 2)), rng.normal(scale=sigma, size=len(mov))])
    deg = rng.uniform(*make_pairs.ROT_DEG)
    rot = make_pairs.random_rotation(rng, deg)
    tdir = rng.normal(size=3)
    tr = tdir / np.linalg.norm(tdir) * rng.uniform(*make_pairs.TRANS_SPACINGS) * spacing
    c0 = mov.mean(0)
    moved = (mov - c0) @ rot.T + c0 + tr
    truth = np.eye(4)
    truth[:3, :3] = rot.T
    truth[:3, 3] = c0 - rot.T @ (c0 + tr)
    name = f"{family}_s{k}"
    os.makedirs(d, exist_ok=True)
    tag = f"{name} from mannequin_head.off (face_vertex_bench.py, seed {seed})"
    make_pairs.write_xyz(os.path.join(d, "reference.xyz"), ref, f"reference of {tag}")
    make_pairs.write_xyz(os.path.join(d, "moving.xyz"), moved, f"moving of {tag}")
    meta = {"name": name, "family": family, "variant": "vertices", "seed_index": k,
            "source": "mannequin_head.off", "matrix": truth.tolist(), "spacing": spacing,
            "units": "model units", "noise_sigma": sigma, "true_rotation_deg": deg,
            "true_translation_spacings": float(np.linalg.norm(tr) / spacing),
            "n_reference": len(ref), "n_moving": len(moved)}
    with open(os.path.join(d, "truth.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print(f"{name}: {len(ref)} / {len(moved)} points, spacing {spacing:.4g}, rotation {deg:.2f} deg, "
          f"translation {meta['true_translation_spacings']:.2f} spacings", file=sys.stderr)


def run_gicp_normals(ref, mov, spacing, schedule):
    """Generalized ICP with Open3D's own covariances from the normals (the
    GICP paper's plane-to-plane: eigenvalues 1, 1, 1e-3 about each normal),
    where run_peers.py gives it the neighbours' raw covariances. The raw ones
    are singular where a mesh's vertices lie in a plane or a line (flat
    patches, edge midpoints), and Open3D aborts there (an Eigen assertion in
    the matrix square root); these never are. Same neighbourhoods, schedule
    and stopping rule as run_peers.py."""
    shift = ref.mean(0)
    t0 = time.perf_counter()
    src = run_peers.cloud(mov - shift, spacing, False)
    tgt = run_peers.cloud(ref - shift, spacing, False)
    est = run_peers.REG.TransformationEstimationForGeneralizedICP()
    criteria = run_peers.REG.ICPConvergenceCriteria(relative_fitness=1e-9, relative_rmse=1e-9,
                                                    max_iteration=run_peers.MAX_ITER)
    t = np.eye(4)
    for dist in schedule:
        t = run_peers.REG.registration_generalized_icp(src, tgt, dist * spacing, t, est, criteria).transformation
    secs = time.perf_counter() - t0
    s, si = np.eye(4), np.eye(4)
    s[:3, 3], si[:3, 3] = shift, -shift
    return s @ t @ si, secs


def add_gicp_normals(pairs_dir, csv_path):
    """Runs gicp_normals on every pair and appends its rows to the CSV."""
    rows = list(csv.DictReader(open(csv_path)))
    fields = list(rows[0].keys())
    rows = [r for r in rows if r["method"] != "gicp_normals"]
    isolated = run_peers.Isolated()
    for name in sorted({r["pair"] for r in rows}):
        d = os.path.join(pairs_dir, name)
        truth = json.load(open(os.path.join(d, "truth.json")))
        ref, mov = run_peers.load_xyz(os.path.join(d, "reference.xyz")), run_peers.load_xyz(os.path.join(d, "moving.xyz"))
        row = dict(next(r for r in rows if r["pair"] == name), method="gicp_normals", status="ok", note="",
                   sigma_rot_deg="nan", sigma_trans_spacings="nan", matrix="")
        try:
            est, secs = isolated(run_gicp_normals, ref, mov, truth["spacing"], run_peers.SCHEDULE)
            rot, tr = run_peers.errors(est, np.array(truth["matrix"]), mov.mean(0), truth["spacing"])
            row.update(rot_err_deg=rot, trans_err_spacings=tr, seconds=secs, wall_seconds=secs)
        except Exception as e:  # noqa: BLE001  (a failure counts as one)
            row.update(status="error", note=f"{type(e).__name__}: {e}", rot_err_deg="nan", trans_err_spacings="nan")
        rows.append(row)
        print(f"{name:24s} gicp_normals {row['status']} rot {row['rot_err_deg']} trans {row['trans_err_spacings']}",
              file=sys.stderr)
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)


def gmean(x):
    x = [max(v, 1e-12) for v in x]
    return math.exp(sum(math.log(v) for v in x) / len(x)) if x else math.nan


def summary(csv_path, families):
    rows = list(csv.DictReader(open(csv_path)))
    by = {}
    for r in rows:
        ok = r["status"] == "ok"
        by[(r["pair"], r["method"])] = (float(r["rot_err_deg"]) if ok else math.inf,
                                        float(r["trans_err_spacings"]) if ok else math.inf)
    pairs = sorted({k[0] for k in by})
    # GICP: per pair the better (by the sum of the two errors' logs) of the
    # two set-ups that ran; a pair where neither ran has no ratio.
    for p in pairs:
        runs = [by[(p, m)] for m in ("gicp", "gicp_normals") if (p, m) in by and by[(p, m)][0] < math.inf]
        by[(p, "gicp_best")] = min(runs, key=lambda e: math.log(max(e[0], 1e-12)) + math.log(max(e[1], 1e-12))) \
            if runs else (math.inf, math.inf)
    methods = [m for m in ("surfreg", "gicp", "gicp_normals", "gicp_best", "icp_plane") if any(k[1] == m for k in by)]
    fams = [f for f in families if any(p.rsplit("_s", 1)[0] == f for p in pairs)]

    def cell(errs):
        ok = [e for e in errs if e[0] < math.inf]
        if not ok:
            return "fail"
        text = f"{gmean([a for a, _ in ok]):.2g} / {gmean([b for _, b in ok]):.2g}"
        return text + (f" ({len(errs) - len(ok)} fail)" if len(ok) < len(errs) else "")

    out = ["Geometric means over each family's pairs: rotation error (deg) / translation error at the moving "
           "centroid (spacings); failed runs left out and counted. gicp: run_peers.py's (the neighbours' raw "
           "covariances); gicp_normals: covariances from the normals (plane-to-plane); gicp_best: per pair the "
           "better of the two. Ratio: the geometric mean of surfreg's error / gicp_best's per pair (pairs where "
           "both GICPs failed left out; errors below 1e-5 count as 1e-5, the files' rounding), rotation / translation.", "",
           "| family | pairs | " + " | ".join(methods) + " | ratio surfreg / gicp_best |",
           "|---|---:|" + "---:|" * (len(methods) + 1)]
    all_r, all_t = [], []
    for f in fams + ["all"]:
        ps = [p for p in pairs if f == "all" or p.rsplit("_s", 1)[0] == f]
        cells = [cell([by[(p, m)] for p in ps if (p, m) in by]) for m in methods]
        rr, rt = [], []
        for p in ps:
            s, g = by.get((p, "surfreg")), by[(p, "gicp_best")]
            if s and g[0] < math.inf:
                rr.append(max(s[0], FLOOR) / max(g[0], FLOOR))
                rt.append(max(s[1], FLOOR) / max(g[1], FLOOR))
        ratio = f"{gmean(rr):.2f} / {gmean(rt):.2f}" if rr else "n/a"
        if f == "all":
            all_r, all_t = rr, rt
            ratio = f"**{ratio}**"
        out.append(f"| {f} | {len(ps)} | " + " | ".join(cells) + f" | {ratio} |")
    if all_r:
        out += ["", f"All {len(all_r)} pairs with a GICP result: geometric mean of surfreg / GICP (the better "
                f"set-up per pair): rotation {gmean(all_r):.3f}, translation {gmean(all_t):.3f}, both "
                f"{gmean(all_r + all_t):.3f} (target <= 0.7: "
                f"{'met' if max(gmean(all_r), gmean(all_t)) <= 0.7 else 'unmet'})."]
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--surfreg", default=os.path.join(ROOT, "build/tools/surfreg"))
    ap.add_argument("--mesh", default=os.path.join(ROOT, "configs/data/mannequin_head.off"))
    ap.add_argument("--out", default=os.path.join(ROOT, "build/bench-results/face_vertex"))
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--seed", type=int, default=20251206)
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--methods", default="surfreg,icp_plane,gicp")
    ap.add_argument("--surfreg_args", default="")
    ap.add_argument("--pairs_only", action="store_true", help="write the pairs, run nothing")
    ap.add_argument("--summary_only", action="store_true", help="summarise DIR/align_peers.csv only")
    args = ap.parse_args()
    families = [f for f in args.families.split(",") if f]
    for f in families:
        if f not in FAMILIES:
            ap.error(f"unknown family {f} (known: {', '.join(FAMILIES)})")
    pairs_dir = os.path.join(args.out, "pairs")
    if not args.summary_only:
        os.makedirs(pairs_dir, exist_ok=True)
        v, t = face_mesh(args.surfreg, args.mesh, args.out)
        print(f"face mesh: {len(v)} vertices, {len(t)} triangles", file=sys.stderr)
        for f in families:
            for k in range(args.seeds):
                make_pair(f, k, args.seed, v, t, os.path.join(pairs_dir, f"{f}_s{k}"))
        if args.pairs_only:
            return
        cmd = [sys.executable, os.path.join(HERE, "align_peers/run_peers.py"), "--pairs", pairs_dir,
               "--out", args.out, "--surfreg", args.surfreg, "--methods", args.methods]
        if args.surfreg_args:
            cmd.append(f"--surfreg_args={args.surfreg_args}")
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        if "gicp" in args.methods.split(","):
            add_gicp_normals(pairs_dir, os.path.join(args.out, "align_peers.csv"))
    text = summary(os.path.join(args.out, "align_peers.csv"), families)
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
