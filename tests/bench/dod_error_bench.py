#!/usr/bin/env python3
"""Calibration of the DoD error model of `surfreg measure --error_model=variogram`.

Simulated DEM pairs with a known change and a Gaussian error field of KNOWN
covariance; the reported standard deviation of the net change must match the
spread of the net's actual error.

Design:
  terrain  configs/data/jacksboro_fault_dem.xyz (a regular 344 x 403 grid of
           ~75 x 92 m cells, written row by row from the north): its central
           N x N window (mirror-tiled if N is larger), rewritten with cells of
           h = 10 m in EPSG:32616, north-up GeoTIFF Float64. Only dz enters the
           measure, and the heteroscedastic sigma uses slope / its 99th
           percentile, which the horizontal rescaling leaves alone.
  change   two rectangles raised by 6 m and a disc lowered by 5 m (~23% of
           the area; --change), all at least 5 cells from the border (where
           nodes have other areas), so true_net = sum(change) h^2 exactly.
           Without a mask the model takes as stable every cell within 4 NMAD
           of dz's median (~0.7 m here): +6/-5 keeps the change out of it
           (with +3/-2 over half of the changed cells would count as noise,
           and the fit would measure the plateaus rather than the errors).
  error    e = sigma(x) (sqrt(1 - f) G_R + sqrt(f) W): W white N(0,1), f the
           nugget share, G_R unit-variance Gaussian with spherical covariance
           C(d) = 1 - 1.5 d/R + 0.5 (d/R)^3 (d < R cells; 0 beyond), simulated
           exactly by circulant embedding on a 2N torus (negative eigenvalues
           clipped; --selfcheck compares the empirical variogram of many
           fields with the model at lags 1, R/2, R, 2R). sigma: homoscedastic
           0.5 m, or heteroscedastic 0.25 (1 + 3 min(slope / p99(slope), 1)) m
           (1x to 4x). B = A + change + e.
  measure  per pair, with and without --lod_confidence=0.95:
           measure A B --error_model=variogram --json --quiet; from
           change.uncertainty: net, net_sigma_{spatial,independent,correlated},
           variogram {nugget, sills, ranges}. z = (net - true_net) / sigma.
           --fake replaces the binary by an oracle in numpy: the budget's
           convention (sums over the detected nodes) with the TRUE covariance
           and sigma(x) in place of the fitted ones (plumbing; and what a
           perfect fit would give).
Families: R in {1, 2, 5, 10, 20} cells x {homo, hetero} x {no LoD, LoD 95%},
seeds 0..S-1 (numpy default_rng([seed, R, hetero]): families independent).
Targets (PASS/FAIL per family): share of |z_spatial| > 1.96 in [2%, 10%];
median |z_spatial| in [0.45, 0.9]; for R >= 2 the fitted correlated
component (largest sill among ranges above one cell) within 20% of the true
range and of the sill 1 - f (R = 1 is pure nugget on the grid: not judged;
there the ideal nugget/f is 1/f).
With 30 seeds a perfectly calibrated sigma meets the share target with
probability 0.73 only (binomial 1..3 of 30), so pooled lines follow the table.
Diagnostics (not judged): `range > 5R`, the share of fits with a component
of range above 5R cells (spurious long range: its variance grows with
sill x range^2); `σ/oracle`, the median of net_sigma_spatial over the
oracle's (the true covariance, same nodes): calibration of sigma itself,
far tighter than 30 z's can show. `E bias/σ` is the analytic mean of net - true_net that the LoD itself causes
(changed nodes dropped under the threshold), over the median spatial sigma.

Usage: dod_error_bench.py [--surfreg PATH] [--ranges 1,2,5,10,20] [--size N]
       [--seeds S] [--nugget F] [--change UP,DOWN] [--quick] [--fake]
       [--selfcheck] [--out F.md]
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from osgeo import gdal, osr

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
H = 10.0  # cell size, metres
EPSG = 32616
gdal.UseExceptions()


def load_terrain(n):
    d = np.loadtxt(os.path.join(ROOT, "configs", "data", "jacksboro_fault_dem.xyz"), comments="#")
    cols = int(np.argmax(np.diff(d[:, 0]) < 0)) + 1  # x falls back at each new row
    z = d[:, 2].reshape(-1, cols)  # row 0 is the northern one (y falls down the rows)
    while z.shape[0] < n or z.shape[1] < n:
        z = np.pad(z, ((0, z.shape[0]), (0, z.shape[1])), mode="symmetric")
    r0, c0 = (z.shape[0] - n) // 2, (z.shape[1] - n) // 2
    return z[r0:r0 + n, c0:c0 + n].astype(float)


def make_change(n, up, down):
    r, c = np.mgrid[0:n, 0:n]
    change = np.zeros((n, n))
    change[(r >= .12 * n) & (r < .42 * n) & (c >= .10 * n) & (c < .38 * n)] = up
    change[(r >= .58 * n) & (r < .86 * n) & (c >= .08 * n) & (c < .30 * n)] = up
    change[(r - .66 * n) ** 2 + (c - .66 * n) ** 2 < (.16 * n) ** 2] = down
    inner = np.zeros((n, n), bool)
    inner[5:-5, 5:-5] = True
    assert not change[~inner].any(), "change within 5 cells of the border"
    return change


def sigma_map(z, variant):
    if variant == "homo":
        return np.full(z.shape, 0.5)
    gy, gx = np.gradient(z, H)  # central differences inside
    slope = np.hypot(gx, gy)
    return 0.25 * (1 + 3 * np.minimum(slope / np.percentile(slope, 99), 1.0))


def node_areas(n):
    a = np.full((n, n), H * H)
    for edge in (a[0], a[-1], a[:, 0], a[:, -1]):
        edge *= 0.5  # corners twice: a quarter
    return a


def spherical(d, r):
    x = np.minimum(d / r, 1.0)
    return 1 - 1.5 * x + 0.5 * x ** 3


_EMBEDDINGS = {}


def embedding(n, r):
    """Torus side m >= n + r, sqrt of the circulant's eigenvalues / m^2, clipped share."""
    if (n, r) not in _EMBEDDINGS:
        m = max(2 * n, n + r + (n + r) % 2)
        i = np.arange(m)
        i = np.minimum(i, m - i)
        lam = np.fft.fft2(spherical(np.hypot(i[:, None], i[None, :]), r)).real
        clipped = max(0.0, -lam.min()) / lam.max()
        _EMBEDDINGS[(n, r)] = (m, np.sqrt(np.maximum(lam, 0.0) / (m * m)), clipped)
    return _EMBEDDINGS[(n, r)]


def gaussian_field(n, r, rng):
    m, root, _ = embedding(n, r)
    xi = rng.standard_normal((m, m)) + 1j * rng.standard_normal((m, m))
    return np.fft.fft2(root * xi).real[:n, :n]


def error_field(n, r, f, sigma, seed, family=0):
    rng = np.random.default_rng([seed, r, family])  # families independent of each other
    g = gaussian_field(n, r, rng)
    return sigma * (math.sqrt(1 - f) * g + math.sqrt(f) * rng.standard_normal((n, n)))


def semivariogram(fields, lag):
    """Mean of 0.5 (g(x + lag) - g(x))^2 along rows and columns."""
    dx = [0.5 * np.mean((g[:, lag:] - g[:, :-lag]) ** 2) for g in fields]
    dy = [0.5 * np.mean((g[lag:] - g[:-lag]) ** 2) for g in fields]
    return 0.5 * (np.mean(dx) + np.mean(dy))


def selfcheck(n, ranges, f, count=150):
    lines = ["| R | torus | clipped λ | lag | γ empirical | γ model | rel. error |", "|---:|---:|---:|---:|---:|---:|---:|"]
    worst = 0.0
    for r in ranges:
        rng = np.random.default_rng(1000 + r)
        fields = [gaussian_field(n, r, rng) for _ in range(count)]
        m, _, clipped = embedding(n, r)
        for lag in sorted({1, max(1, round(r / 2)), r, 2 * r}):
            got, want = semivariogram(fields, lag), 1 - spherical(float(lag), r)
            worst = max(worst, abs(got / want - 1))
            lines.append("| %d | %d | %.1e | %d | %.4f | %.4f | %+.2f%% |" % (r, m, clipped, lag, got, want, 100 * (got / want - 1)))
        e = [error_field(n, r, f, 1.0, s) for s in range(count // 3)]
        got, want = semivariogram(e, 1), f + (1 - f) * (1 - spherical(1.0, r))
        lines.append("| %d | e/σ, f=%.2f | var %.4f | 1 | %.4f | %.4f | %+.2f%% |" % (r, f, np.mean([x.var() for x in e]), got, want, 100 * (got / want - 1)))
    lines.append("\n%d fields of %d x %d per R; worst relative error of G_R: %.2f%%" % (count, n, n, 100 * worst))
    return "\n".join(lines)


def write_tif(path, z):
    ds = gdal.GetDriverByName("GTiff").Create(path, z.shape[1], z.shape[0], 1, gdal.GDT_Float64)
    ds.SetGeoTransform((500000.0, H, 0.0, 4000000.0 + z.shape[0] * H, 0.0, -H))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(EPSG)
    ds.SetProjection(srs.ExportToWkt())
    ds.GetRasterBand(1).WriteArray(z)
    ds.FlushCache()
    ds = None


def quantile(confidence):
    return statistics.NormalDist().inv_cdf(0.5 + confidence / 2) if confidence else 0.0


def fake_measure(a, b, sigma, r, f, confidence):
    """The oracle: the budget over detected nodes, true covariance and sigma(x)."""
    n = a.shape[0]
    dz, area = b - a, node_areas(n)
    detected = np.abs(dz) > quantile(confidence) * sigma
    u = np.where(detected, area * sigma, 0.0)
    m = embedding(n, r)[0]
    i = np.arange(m)
    i = np.minimum(i, m - i)
    d = np.hypot(i[:, None], i[None, :])
    rho = np.where(d == 0, 1.0, (1 - f) * spherical(d, r))
    up = np.zeros((m, m))
    up[:n, :n] = u
    var = float(np.sum(up * np.fft.ifft2(np.fft.fft2(up) * np.fft.fft2(rho)).real))
    return {"net": float(np.sum((dz * area)[detected])), "net_sigma_spatial": math.sqrt(var),
            "net_sigma_independent": math.sqrt(float(np.sum(u * u))), "net_sigma_correlated": float(np.sum(u)),
            "variogram": {"nugget": f, "sills": [1 - f], "ranges": [r * H]}}


def real_measure(binary, a_path, b_path, confidence):
    cmd = [binary, "measure", a_path, b_path, "--error_model=variogram", "--json", "--quiet"]
    if confidence:
        cmd.append("--lod_confidence=%g" % confidence)
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        print("FAILED (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr))
        sys.exit(1)
    return json.loads(p.stdout)["change"]["uncertainty"]


def lod_bias(change, sigma, confidence):
    """E[net] - true_net caused by the threshold t sigma (true sigma), analytic."""
    t = quantile(confidence)
    if t == 0:
        return 0.0
    cdf = np.frompyfunc(lambda x: 0.5 * (1 + math.erf(x / math.sqrt(2))), 1, 1)
    pdf = lambda x: np.exp(-0.5 * x * x) / math.sqrt(2 * math.pi)
    lo, hi = (-t * sigma - change) / sigma, (t * sigma - change) / sigma
    inside = change * (cdf(hi).astype(float) - cdf(lo).astype(float)) + sigma * (pdf(lo) - pdf(hi))
    return -float(np.sum(node_areas(change.shape[0]) * inside))


def correlated_component(v):
    """(range in cells, sill) of the larger-sill component with a range above one cell."""
    parts = [(s, rg / H) for s, rg in zip(v["sills"], v["ranges"]) if rg > H * (1 + 1e-9)]
    if not parts:
        return math.nan, math.nan
    s, rg = max(parts)
    return rg, s


def family_row(r, variant, conf, rows, f, bias):
    z = np.array([[u["net"] - u["true_net"]] * 3 for u in rows]) / np.array(
        [[u["net_sigma_spatial"], u["net_sigma_independent"], u["net_sigma_correlated"]] for u in rows])
    share, med = np.mean(np.abs(z) > 1.96, axis=0), np.median(np.abs(z), axis=0)
    fits = [u.get("variogram") or {"nugget": math.nan, "sills": [], "ranges": []} for u in rows]
    comp = np.array([correlated_component(v) for v in fits])
    range_ratio = np.nanmedian(comp[:, 0]) / r if np.isfinite(comp[:, 0]).any() else math.nan
    sill_ratio = np.nanmedian(comp[:, 1]) / (1 - f) if np.isfinite(comp[:, 1]).any() else math.nan
    nugget_ratio = np.median([v["nugget"] for v in fits]) / f if f > 0 else math.nan
    spurious = np.mean([any(sl > 0 and rg > 5 * r * H for sl, rg in zip(v["sills"], v["ranges"])) for v in fits])
    oracle = np.median([u["net_sigma_spatial"] / u["oracle"] for u in rows])
    ok = 0.02 <= share[0] <= 0.10 and 0.45 <= med[0] <= 0.9
    if r >= 2:
        ok = ok and abs(range_ratio - 1) <= 0.2 and abs(sill_ratio - 1) <= 0.2
    sig = np.median([u["net_sigma_spatial"] for u in rows])
    cells = ["%d" % r, variant, "95%" if conf else "-", "%d" % len(rows)]
    for k in range(3):
        cells += ["%.0f%%" % (100 * share[k]), "%.2f" % med[k]]
    cells.insert(6, "%+.2f" % np.mean(z[:, 0]))
    cells += ["%.2f" % range_ratio, "%.2f" % sill_ratio, "%.2f" % nugget_ratio, "%.0f%%" % (100 * spurious),
              "%.2f" % oracle, "%+.2f" % (bias / sig),
              "PASS" if ok else "FAIL"]
    debiased = z[:, 0] - bias / np.array([u["net_sigma_spatial"] for u in rows])
    return "| " + " | ".join(cells) + " |", z[:, 0], debiased


def has_error_model(binary):
    p = subprocess.run([binary, "help", "measure"], capture_output=True, text=True)
    return "error_model" in p.stdout + p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--surfreg", default=os.path.join(ROOT, "build", "tools", "surfreg"))
    ap.add_argument("--ranges", default="1,2,5,10,20")
    ap.add_argument("--size", type=int, default=300)
    ap.add_argument("--seeds", type=int, default=30)
    ap.add_argument("--nugget", type=float, default=0.3)
    ap.add_argument("--change", default="6,-5", help="the plateaus' heights UP,DOWN (m)")
    ap.add_argument("--quick", action="store_true", help="3 seeds, size 150")
    ap.add_argument("--fake", action="store_true", help="numpy oracle instead of the binary")
    ap.add_argument("--selfcheck", action="store_true", help="check the simulated variograms and stop")
    ap.add_argument("--out")
    args = ap.parse_args()
    if args.quick:
        args.seeds, args.size = 3, 150
    ranges, n, f = [int(x) for x in args.ranges.split(",")], args.size, args.nugget
    start = time.perf_counter()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    if args.selfcheck:
        print(selfcheck(n, ranges, f))
        print("\nwall time %.1f s; CPU: %s, %d cores" % (time.perf_counter() - start, cpu, os.cpu_count()))
        return 0
    if not args.fake and not has_error_model(args.surfreg):
        print("%s: `help measure` lists no error_model (use --fake until it does)" % args.surfreg)
        return 1
    a, change = load_terrain(n), make_change(n, *[float(x) for x in args.change.split(",")])
    true_net = float(np.sum(change)) * H * H
    header = ("| R | σ | LoD | seeds | spatial >1.96 | med\\|z\\| | mean z | indep. >1.96 | med\\|z\\| | "
              "corr. >1.96 | med\\|z\\| | range fit/true | sill/(1−f) | nugget/f | range > 5R | σ/oracle | E bias/σ | "
              "verdict |")
    lines = [header, "|" + "---:|" * 17 + ":---|"]
    pooled, measures, measure_seconds = {0: [], 0.95: []}, 0, 0.0
    with tempfile.TemporaryDirectory(prefix="dod_error_bench_") as work:
        a_path, b_path = os.path.join(work, "A.tif"), os.path.join(work, "B.tif")
        write_tif(a_path, a)
        for r in ranges:
            for variant in ("homo", "hetero"):
                sigma = sigma_map(a, variant)
                results = {0: [], 0.95: []}
                for seed in range(args.seeds):
                    b = a + change + error_field(n, r, f, sigma, seed, variant == "hetero")
                    write_tif(b_path, b)
                    for conf in results:
                        t0 = time.perf_counter()
                        u = fake_measure(a, b, sigma, r, f, conf) if args.fake else real_measure(args.surfreg, a_path, b_path, conf)
                        measure_seconds += time.perf_counter() - t0
                        measures += 1
                        u["true_net"] = true_net
                        u["oracle"] = fake_measure(a, b, sigma, r, f, conf)["net_sigma_spatial"]
                        results[conf].append(u)
                for conf, rows in results.items():
                    line, z, debiased = family_row(r, variant, conf, rows, f, lod_bias(change, sigma, conf))
                    lines.append(line)
                    if r >= 2:
                        pooled[conf].append((z, debiased))
    lines.append("")
    for conf, parts in pooled.items():
        for k, what in enumerate(("", ", against true_net + E bias") if conf else ("",)):
            z = np.abs(np.concatenate([p[k] for p in parts])) if parts else []
            if len(z):
                lines.append("- pooled R >= 2, %s%s: %d nets, |z_spatial| > 1.96 in %.1f%%, median |z_spatial| %.2f" %
                             ("LoD 95%" if conf else "no LoD", what, len(z), 100 * np.mean(z > 1.96), np.median(z)))
    hetero = sigma_map(a, "hetero")
    lines.append("- %s; grid %d x %d, h = %g m, changed %.1f%% of the nodes, true net %.0f m³ (+/-: %s), nugget share %g; "
                 "hetero σ %.2f to %.2f m (median %.2f)" %
                 ("FAKE (numpy oracle)" if args.fake else "binary " + args.surfreg, n, n, H,
                  100 * np.mean(change != 0), true_net, args.change, f, hetero.min(), hetero.max(), np.median(hetero)))
    lines.append("- wall time %.1f s (%d measures, %.2f s each); CPU: %s, %d cores" %
                 (time.perf_counter() - start, measures, measure_seconds / max(1, measures), cpu, os.cpu_count()))
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as out:
            out.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
