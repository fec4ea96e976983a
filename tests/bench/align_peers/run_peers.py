#!/usr/bin/env python3
"""Registration accuracy of surfreg vs Open3D point-to-plane ICP and generalized
ICP on the pairs of make_pairs.py, all from the same start (identity).

    run_peers.py --pairs DIR --out DIR [--surfreg BIN] [--methods surfreg,icp_plane,gicp]
                 [--surfreg_args="--cost=axial ..."]

Methods: surfreg, icp_plane, gicp (the default) and, for changed pairs
(make_changed_pairs.py), surfreg_all (surfreg with --stable=all: every
sample counts, the behaviour before automatic stable-terrain detection) and
surfreg_oracle (reference_stable.xyz, the true stable part as per-point
weights, with --stable=all). --surfreg_args go to every surfreg run.

Writes DIR/align_peers.csv (one row per pair x method) and DIR/align_peers.md
(the Markdown tables, also printed). See tests/bench/README.md.
"""
import argparse
import csv
import json
import math
import concurrent.futures
import multiprocessing
import os
import shlex
import subprocess
import sys
import time

import numpy as np
import open3d as o3d

REG = o3d.pipelines.registration
METHODS = ["surfreg", "icp_plane", "gicp"]  # the default --methods
SURFREG_METHODS = ["surfreg", "surfreg_all", "surfreg_oracle"]
LABELS = {"surfreg": "surfreg align (defaults)",
          "surfreg_all": "surfreg align --stable=all",
          "surfreg_oracle": "surfreg align, true stable part as weights",
          "icp_plane": "Open3D ICP point-to-plane",
          "gicp": "Open3D generalized ICP"}
# Peers' setup, in sample spacings: normals / covariances from the neighbours
# within NORMAL_RADIUS (at most NORMAL_NN); coarse-to-fine maximum
# correspondence distances SCHEDULE, at most MAX_ITER iterations per stage.
# SCHEDULE was the best of six candidates for both peers on held-out pairs
# (make_pairs.py --seed 7); see tests/bench/README.md.
NORMAL_RADIUS = 3.0
NORMAL_NN = 30
SCHEDULE = [7.0, 3.0, 1.0]
MAX_ITER = 100
SUCCESS_ROT_DEG = 0.1
SUCCESS_TRANS_SPACINGS = 0.5


def load_xyz(path):
    return np.loadtxt(path, comments="#", dtype=float)[:, :3]


def rotation_angle_deg(r):
    """Angle of a rotation matrix, accurate near zero."""
    s = 0.5 * math.sqrt((r[2, 1] - r[1, 2]) ** 2 + (r[0, 2] - r[2, 0]) ** 2 + (r[1, 0] - r[0, 1]) ** 2)
    c = 0.5 * (np.trace(r) - 1.0)
    return math.degrees(math.atan2(s, c))


def errors(est, truth, centroid, spacing):
    rot = rotation_angle_deg(est[:3, :3] @ truth[:3, :3].T)
    c = np.append(centroid, 1.0)
    trans = float(np.linalg.norm((est @ c - truth @ c)[:3])) / spacing
    return rot, trans


# ---------------------------------------------------------------- surfreg

def surfreg_supports_align(binary):
    if not binary or not os.path.isfile(binary) or not os.access(binary, os.X_OK):
        return False, f"no executable at {binary}"
    p = subprocess.run([binary, "align"], capture_output=True, text=True, timeout=60)
    if "unknown command" in p.stderr:
        return False, f"{binary} has no 'align' command yet"
    return True, ""


def parse_json_output(text):
    """The JSON object on stdout (tolerates lines before it)."""
    start = text.find("{")
    if start < 0:
        raise ValueError("no JSON object on stdout")
    return json.JSONDecoder().raw_decode(text[start:])[0]


class SurfregError(RuntimeError):
    """A failed surfreg run; keeps its stderr."""

    def __init__(self, message, stderr):
        super().__init__(message)
        self.stderr = stderr


def run_surfreg(binary, ref_path, mov_path, timeout, extra=()):
    t0 = time.perf_counter()
    p = subprocess.run([binary, "align", ref_path, mov_path, "--json", *extra],
                       capture_output=True, text=True, timeout=timeout)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise SurfregError(f"exit {p.returncode}: {p.stderr.strip().splitlines()[-1:] or ''}", p.stderr)
    out = parse_json_output(p.stdout)
    m = np.array(out["matrix"], dtype=float).reshape(4, 4)
    secs = out.get("seconds")
    if isinstance(secs, dict):
        secs = secs.get("total")
    note = str(out.get("verdict", out.get("termination", "")))
    if out.get("verdict_reason"):
        note += f" ({out['verdict_reason']})"
    return m, float(secs) if isinstance(secs, (int, float)) else wall, wall, note, out.get("stddev")


def run_surfreg_method(method, binary, pair_dir, timeout, extra):
    """One surfreg variant on a pair: the reference file and the flags."""
    ref_path, mov_path = os.path.join(pair_dir, "reference.xyz"), os.path.join(pair_dir, "moving.xyz")
    if method == "surfreg":
        return run_surfreg(binary, ref_path, mov_path, timeout, extra)
    if method == "surfreg_all":
        return run_surfreg(binary, ref_path, mov_path, timeout, ["--stable=all", *extra])
    ref_path = os.path.join(pair_dir, "reference_stable.xyz")
    if not os.path.isfile(ref_path):
        raise FileNotFoundError("no reference_stable.xyz (not a make_changed_pairs.py pair)")
    flags = ["--weights=per_point", "--stable=all"]
    try:
        return run_surfreg(binary, ref_path, mov_path, timeout, [*flags, *extra])
    except SurfregError as e:
        # A binary from before `stable` refuses the flag; without it, it does
        # what --stable=all means (every sample, weighted), so the oracle runs.
        if "unknown flag '--stable" not in e.stderr:
            raise
        m, secs, wall, note, stddev = run_surfreg(binary, ref_path, mov_path, timeout, [flags[0], *extra])
        return m, secs, wall, note + " (--stable refused: run without it)", stddev


def sigma_norms(stddev, spacing):
    """surfreg's reported standard deviations as the errors are measured: the
    rotation's (norm of rx, ry, rz) in degrees, the translation's at the
    centre (norm of tx, ty, tz) in spacings; NaN where not reported."""
    try:
        rot = math.degrees(math.sqrt(sum(stddev[k] ** 2 for k in ("rx", "ry", "rz"))))
        trans = math.sqrt(sum(stddev[k] ** 2 for k in ("tx", "ty", "tz"))) / spacing
        return rot, trans
    except (TypeError, KeyError):
        return math.nan, math.nan


# ---------------------------------------------------------------- Open3D

def cloud(points, spacing, with_covariances):
    pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    search = o3d.geometry.KDTreeSearchParamHybrid(radius=NORMAL_RADIUS * spacing, max_nn=NORMAL_NN)
    if with_covariances:
        pc.estimate_covariances(search)
    else:
        pc.estimate_normals(search)
        pc.orient_normals_to_align_with_direction([0.0, 0.0, 1.0])
    return pc


def run_open3d(method, ref, mov, spacing, schedule):
    """Both clouds shifted by the reference centroid (conditioning of the
    rotation about the origin; the result is shifted back). Time covers the
    normal / covariance estimation and all ICP stages, not file reading."""
    shift = ref.mean(0)
    t0 = time.perf_counter()
    gicp = method == "gicp"
    src = cloud(mov - shift, spacing, gicp)
    tgt = cloud(ref - shift, spacing, gicp)
    est = REG.TransformationEstimationForGeneralizedICP() if gicp \
        else REG.TransformationEstimationPointToPlane()
    criteria = REG.ICPConvergenceCriteria(relative_fitness=1e-9, relative_rmse=1e-9,
                                          max_iteration=MAX_ITER)
    t = np.eye(4)
    for dist in schedule:
        fn = REG.registration_generalized_icp if gicp else REG.registration_icp
        res = fn(src, tgt, dist * spacing, t, est, criteria)
        t = res.transformation
    secs = time.perf_counter() - t0
    s = np.eye(4)
    s[:3, 3] = shift
    si = np.eye(4)
    si[:3, 3] = -shift
    note = f"fitness {res.fitness:.3f} rmse/spacing {res.inlier_rmse / spacing:.3f}"
    return s @ t @ si, secs, secs, note


class Isolated:
    """Open3D runs in one worker process (spawned: it imports Open3D afresh,
    and no thread of this one crosses a fork). A run that aborts the worker
    (an Eigen assertion in generalized ICP's covariances on some sparse
    clouds) fails that pair only; the next run gets a new worker. Times are
    taken in the worker."""

    def __init__(self):
        self.pool = None

    def __call__(self, fn, *args):
        if self.pool is None:
            self.pool = concurrent.futures.ProcessPoolExecutor(
                max_workers=1, mp_context=multiprocessing.get_context("spawn"))
        try:
            return self.pool.submit(fn, *args).result()
        except concurrent.futures.process.BrokenProcessPool:
            self.pool = None
            raise RuntimeError("Open3D aborted the worker process") from None


# ---------------------------------------------------------------- report

def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if x == math.inf:
        return "fail"
    return f"{x:.{digits}g}" if abs(x) < 1e4 else f"{x:.3e}"


def table(rows, methods, pairs):
    """Markdown rows per method for one group of pairs."""
    out = ["| method | rot. err. median (deg) | rot. err. max (deg) | transl. err. median (spacings) "
           "| transl. err. max (spacings) | median time (s) | success |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for m in methods:
        rs = [rows[(p, m)] for p in pairs if (p, m) in rows]
        if not rs or all(r["status"] == "n/a" for r in rs):
            out.append(f"| {LABELS[m]} | n/a | n/a | n/a | n/a | n/a | n/a |")
            continue
        rot = [r["rot_err_deg"] if r["status"] == "ok" else math.inf for r in rs]
        tr = [r["trans_err_spacings"] if r["status"] == "ok" else math.inf for r in rs]
        secs = [r["seconds"] for r in rs if r["status"] == "ok"]
        ok = sum(1 for a, b in zip(rot, tr) if a < SUCCESS_ROT_DEG and b < SUCCESS_TRANS_SPACINGS)
        out.append(f"| {LABELS[m]} | {fmt(float(np.median(rot)))} | {fmt(max(rot))} | "
                   f"{fmt(float(np.median(tr)))} | {fmt(max(tr))} | "
                   f"{fmt(float(np.median(secs)) if secs else math.nan)} | {ok}/{len(rs)} |")
    return out


def no_worse_line(rows, methods, pairs, label):
    if "surfreg" not in methods or all(rows.get((p, "surfreg"), {}).get("status") == "n/a" for p in pairs):
        return f"{label}: surfreg n/a, no comparison."
    parts = []
    for m in methods:
        if m == "surfreg":
            continue
        n_ok = 0
        for p in pairs:
            s, q = rows.get((p, "surfreg")), rows.get((p, m))
            if s and q and s["status"] == "ok" and (q["status"] != "ok" or (
                    s["rot_err_deg"] <= q["rot_err_deg"] and s["trans_err_spacings"] <= q["trans_err_spacings"])):
                n_ok += 1
        verdict = "yes" if n_ok == len(pairs) else "no"
        parts.append(f"{LABELS[m]}: {verdict} ({n_ok}/{len(pairs)} pairs)")
    return f"{label}: surfreg's rotation and translation errors no larger than the peer's on every pair — " \
           + "; ".join(parts) + "."


def head_to_head(rows, methods, pairs):
    """Pairs on which surfreg's error is no larger than a peer's."""
    sr = [rows.get((p, "surfreg")) for p in pairs]
    if "surfreg" not in methods or all(r is None or r["status"] != "ok" for r in sr):
        return []
    out = ["| surfreg vs | rot. err. <= peer's | transl. err. <= peer's | both |", "|---|---:|---:|---:|"]
    for m in methods:
        if m == "surfreg":
            continue
        n_rot = n_tr = n_both = 0
        for p, s in zip(pairs, sr):
            q = rows.get((p, m))
            if not s or s["status"] != "ok" or not q:
                continue
            bad = q["status"] != "ok"
            a = bad or s["rot_err_deg"] <= q["rot_err_deg"]
            b = bad or s["trans_err_spacings"] <= q["trans_err_spacings"]
            n_rot, n_tr, n_both = n_rot + a, n_tr + b, n_both + (a and b)
        out.append(f"| {LABELS[m]} | {n_rot}/{len(pairs)} | {n_tr}/{len(pairs)} | {n_both}/{len(pairs)} |")
    return out


def calibration(rows, methods, names, groups):
    """surfreg's reported uncertainty against its actual error, and how far
    it is from the better peer where it is not ahead, in its own sigmas."""
    peers = [m for m in methods if m not in SURFREG_METHODS]
    if "surfreg" not in methods or not peers:
        return []
    out = ["| pairs | median error / sigma (rot., transl.) | both <= better peer | else within 1 sigma "
           "of it | else beyond |", "|---|---:|---:|---:|---:|"]
    for label, pairs in [(f"{f} / {v}", [n for n in names if (rows[(n, methods[0])]["family"],
                                                             rows[(n, methods[0])]["variant"]) == (f, v)])
                         for f, v in groups] + [(f"all {len(names)}", names)]:
        ratio_r, ratio_t, ahead, within, beyond = [], [], 0, 0, 0
        for p in pairs:
            s = rows.get((p, "surfreg"))
            qs = [rows.get((p, m)) for m in peers]
            if not s or s["status"] != "ok" or not all(q and q["status"] == "ok" for q in qs):
                continue
            sr, st = s["sigma_rot_deg"], s["sigma_trans_spacings"]
            if not (sr > 0 and st > 0):
                continue
            ratio_r.append(s["rot_err_deg"] / sr)
            ratio_t.append(s["trans_err_spacings"] / st)
            best_r = min(q["rot_err_deg"] for q in qs)
            best_t = min(q["trans_err_spacings"] for q in qs)
            gap_r, gap_t = s["rot_err_deg"] - best_r, s["trans_err_spacings"] - best_t
            if gap_r <= 0 and gap_t <= 0:
                ahead += 1
            elif gap_r <= sr and gap_t <= st:
                within += 1
            else:
                beyond += 1
        if not ratio_r:
            out.append(f"| {label} | n/a | n/a | n/a | n/a |")
            continue
        out.append(f"| {label} | {fmt(float(np.median(ratio_r)), 2)}, {fmt(float(np.median(ratio_t)), 2)} | "
                   f"{ahead}/{len(ratio_r)} | {within}/{len(ratio_r)} | {beyond}/{len(ratio_r)} |")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pairs", required=True, help="directory written by make_pairs.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--surfreg", default="", help="surfreg binary (n/a if missing or without 'align')")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--schedule", default=",".join(str(d) for d in SCHEDULE),
                    help="peers' max correspondence distances, spacings, coarse to fine")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per surfreg run")
    ap.add_argument("--surfreg_args", default="", help="extra arguments for every surfreg run (one string)")
    args = ap.parse_args()
    methods = [m for m in args.methods.split(",") if m]
    for m in methods:
        if m not in LABELS:
            ap.error(f"unknown method {m} (known: {', '.join(LABELS)})")
    surfreg_extra = shlex.split(args.surfreg_args)
    schedule = [float(d) for d in args.schedule.split(",")]
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)

    have_surfreg, why = (False, "not requested")
    if any(m in SURFREG_METHODS for m in methods):
        have_surfreg, why = surfreg_supports_align(args.surfreg)
        if not have_surfreg:
            print(f"surfreg: n/a ({why})", file=sys.stderr)

    names = sorted(d for d in os.listdir(args.pairs) if os.path.isfile(os.path.join(args.pairs, d, "truth.json")))
    os.makedirs(args.out, exist_ok=True)
    rows, t_start = {}, time.perf_counter()
    isolated = Isolated()
    for name in names:
        d = os.path.join(args.pairs, name)
        with open(os.path.join(d, "truth.json")) as f:
            truth = json.load(f)
        ref_path, mov_path = os.path.join(d, "reference.xyz"), os.path.join(d, "moving.xyz")
        ref, mov = load_xyz(ref_path), load_xyz(mov_path)
        t_true, spacing = np.array(truth["matrix"]), truth["spacing"]
        for m in methods:
            row = {"pair": name, "family": truth["family"], "variant": truth["variant"],
                   "seed_index": truth["seed_index"], "method": m, "status": "ok",
                   "rot_err_deg": math.nan, "trans_err_spacings": math.nan, "seconds": math.nan,
                   "wall_seconds": math.nan, "n_reference": len(ref), "n_moving": len(mov),
                   "spacing": spacing, "true_rotation_deg": truth["true_rotation_deg"],
                   "true_translation_spacings": truth["true_translation_spacings"], "note": "",
                   "sigma_rot_deg": math.nan, "sigma_trans_spacings": math.nan, "matrix": ""}
            try:
                if m in SURFREG_METHODS:
                    if not have_surfreg:
                        row["status"], row["note"] = "n/a", why
                        rows[(name, m)] = row
                        continue
                    est, secs, wall, note, stddev = run_surfreg_method(m, args.surfreg, d, args.timeout,
                                                                       surfreg_extra)
                    row["sigma_rot_deg"], row["sigma_trans_spacings"] = sigma_norms(stddev, spacing)
                else:
                    est, secs, wall, note = isolated(run_open3d, m, ref, mov, spacing, schedule)
                row["rot_err_deg"], row["trans_err_spacings"] = errors(est, t_true, mov.mean(0), spacing)
                row.update(seconds=secs, wall_seconds=wall, note=note,
                           matrix=" ".join(f"{v:.12g}" for v in est.ravel()))
            except Exception as e:  # a failed run counts as a failure, the benchmark goes on
                row["status"], row["note"] = "error", f"{type(e).__name__}: {e}"
            rows[(name, m)] = row
            print(f"{name:24s} {m:9s} {row['status']:5s} rot {fmt(row['rot_err_deg'])} deg, "
                  f"transl {fmt(row['trans_err_spacings'])} sp, {fmt(row['seconds'])} s  {row['note']}",
                  file=sys.stderr, flush=True)
    elapsed = time.perf_counter() - t_start

    with open(os.path.join(args.out, "align_peers.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(next(iter(rows.values())).keys()))
        w.writeheader()
        for name in names:
            for m in methods:
                w.writerow(rows[(name, m)])

    groups = []
    for name in names:
        fam_var = tuple(rows[(name, methods[0])][k] for k in ("family", "variant"))
        if fam_var not in groups:
            groups.append(fam_var)
    md = [f"Registration accuracy, {len(names)} pairs, identity start. Errors against the true transform: "
          f"rotation angle of R_est R_true^T; translation = |T_est(c) - T_true(c)| / spacing at the moving "
          f"centroid c. Success: rotation < {SUCCESS_ROT_DEG} deg and translation < "
          f"{SUCCESS_TRANS_SPACINGS} spacing. Peers: normals/covariances radius {NORMAL_RADIUS:g} spacings "
          f"(<= {NORMAL_NN} neighbours), max correspondence distance "
          f"{' -> '.join(f'{d:g}' for d in schedule)} spacings, <= {MAX_ITER} iterations per stage.", ""]
    if surfreg_extra:
        md += [f"Every surfreg run with the extra arguments `{' '.join(surfreg_extra)}`.", ""]
    for fam, var in groups:
        pairs = [n for n in names if rows[(n, methods[0])]["family"] == fam and rows[(n, methods[0])]["variant"] == var]
        md.append(f"### {fam} / {var} ({len(pairs)} pairs)")
        md.append("")
        md += table(rows, methods, pairs)
        md.append("")
        md.append(no_worse_line(rows, methods, pairs, f"{fam}/{var}"))
        md.append("")
    md.append(f"### all pairs ({len(names)})")
    md.append("")
    md += table(rows, methods, names)
    md.append("")
    md += head_to_head(rows, methods, names)
    md.append("")
    md.append(no_worse_line(rows, methods, names, f"All {len(names)} pairs"))
    md.append("")
    cal = calibration(rows, methods, names, groups)
    if cal:
        md.append("### surfreg's reported uncertainty")
        md.append("")
        md.append("sigma: the norms of surfreg's reported standard deviations (rx, ry, rz in degrees; "
                  "tx, ty, tz at the centre, in spacings). A median error / sigma near 1 means the reported "
                  "uncertainty is the size of the actual error. The last three columns split the pairs: "
                  "both errors no larger than the better peer's; else both within one of surfreg's sigmas of it; "
                  "else beyond.")
        md.append("")
        md += cal
        md.append("")
    md.append(f"(run_peers.py: {elapsed:.0f} s for all methods and pairs)")
    text = "\n".join(md) + "\n"
    with open(os.path.join(args.out, "align_peers.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
