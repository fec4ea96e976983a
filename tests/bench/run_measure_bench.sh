#!/usr/bin/env bash
# Runs the whole-measure benchmarks and prints a Markdown summary.
#
#   tests/bench/run_measure_bench.sh [build_dir] [extra measure_bench flags...]
#
# build_dir defaults to build-bench at the top of the source tree. Raw results
# go to <build_dir>/bench-results/ (measure_bench.json, measure_memory_*.txt).
# Exit status: that of measure_bench (2 = a check failed, see its stderr),
# else 3 if a comparison exceeded the 1 GB memory budget, else 0.
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build_dir=${1:-$script_dir/../../build-bench}
[[ $# -gt 0 ]] && shift
bench=$build_dir/tests/bench/measure_bench
memory=$build_dir/tests/bench/measure_memory
budget=1073741824  # bytes, whole process, two 1e6-point clouds
for exe in "$bench" "$memory"; do
  if [[ ! -x $exe ]]; then
    echo "missing $exe: build the measure_bench and measure_memory targets first" >&2
    exit 1
  fi
done
out_dir=$build_dir/bench-results
mkdir -p "$out_dir"
json=$out_dir/measure_bench.json
start=$(date +%s)

# Console output stays on the terminal as progress; the JSON file is what
# the summary reads.
bench_status=0
"$bench" --benchmark_out="$json" --benchmark_out_format=json "$@" || bench_status=$?
if [[ ! -s $json ]]; then
  echo "measure_bench wrote no results (exit status $bench_status)" >&2
  exit 1
fi

# One process per comparison so each peak RSS is a single Measure's.
memory_status=0
for dist in uniform jittered; do
  status=0
  "$memory" 1000000 "$dist" "$budget" >"$out_dir/measure_memory_$dist.txt" || status=$?
  echo "status: $status" >>"$out_dir/measure_memory_$dist.txt"
  if [[ $status -ne 0 && $memory_status -eq 0 ]]; then memory_status=$status; fi
done
elapsed=$(($(date +%s) - start))

python3 - "$json" "$out_dir" "$elapsed" "$bench_status" "$budget" <<'PY'
import json
import os
import sys

json_path, out_dir = sys.argv[1], sys.argv[2]
elapsed, bench_status, budget = int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
with open(json_path) as f:
    data = json.load(f)

# name: BM_Stage/<stage>/<distribution>/<N>[/iterations:k][/real_time]
#       BM_Measure/<impl>/<distribution>/<N>[...]
rows = {}
for b in data["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue
    parts = b["name"].split("/")
    what, dist, n = parts[1], parts[2], int(parts[3])
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b.get("time_unit", "ns")]
    rows[(what, dist, n)] = {
        "error": b.get("error_message") if b.get("error_occurred") else None,
        "real": b.get("real_time", 0.0) * scale,  # seconds per iteration
        "cpu": b.get("cpu_time", 0.0) * scale,
        "points": b.get("points", 0.0),  # 2N: both clouds
        "counters": b,
    }

def ok(r):
    return r is not None and not r["error"] and r["real"] > 0 and r["points"] > 0

def ns_per_point(r):
    return r["real"] / r["points"] * 1e9

stages = [("triangulate", "triangulate (both)"), ("domain", "data domain (both)"),
          ("spanning_tree", "spanning tree (both EMSTs)"),
          ("locate", "locate (both ways)"), ("interpolate", "interpolate (node gaps)"),
          ("overlay", "overlay volume"), ("union", "union volume"),
          ("surfreg", "**whole Measure** (2 threads)"), ("surfreg_serial", "whole Measure, 1 thread"),
          ("cgal_union_triangulation", "CGAL union triangulation")]
dists = [d for d in ("uniform", "jittered") if any(k[1] == d for k in rows)]
sizes = sorted({k[2] for k in rows})
problems, notes = [], []
for key, r in sorted(rows.items()):
    if r["error"]:
        problems.append("%s/%s/%d: %s" % (key + (r["error"],)))

def fmt_n(n):
    return "1e%d" % len(str(n)[1:]) if str(n).strip("0") == "1" else str(n)

print()
print("### Per stage: wall ns per input point (time / 2N)")
print()
print("Flat across N means linear time. The last column is ns/point at the largest N over the")
print("smallest; triangulation may grow (N log N), every other stage should stay near 1.")
for dist in dists:
    print()
    print("| %s | %s | largest / smallest |" % (dist, " | ".join("N = %s" % fmt_n(n) for n in sizes)))
    print("|---|%s---:|" % ("---:|" * len(sizes)))
    for key, label in stages:
        cells, values = [], []
        for n in sizes:
            r = rows.get((key, dist, n))
            if ok(r):
                values.append(ns_per_point(r))
                cells.append("%.0f" % values[-1] if values[-1] >= 100 else "%.1f" % values[-1])
            else:
                values.append(None)
                cells.append("-")
        growth = "-"
        if values and values[0] and values[-1]:
            g = values[-1] / values[0]
            growth = "%.2f" % g
            if key not in ("triangulate", "cgal_union_triangulation", "surfreg",
                           "surfreg_serial") and g > 1.5:
                growth += " (grows)"
                # Per step of N: a jump only at the last step points to the
                # caches (the 1e6 working set is larger than L3), steady
                # growth at every step to a superlinear algorithm.
                steps = ["%s->%s: %.2fx" % (fmt_n(sizes[k]), fmt_n(sizes[k + 1]),
                                           values[k + 1] / values[k])
                         for k in range(len(sizes) - 1) if values[k] and values[k + 1]]
                notes.append("%s %s: ns/point grows %.2fx from N = %s to %s (%s)"
                             % (dist, key, g, fmt_n(sizes[0]), fmt_n(sizes[-1]), ", ".join(steps)))
        print("| %s | %s | %s |" % (label, " | ".join(cells), growth))

print()
print("### Whole measure vs CGAL's Delaunay triangulation of A ∪ B (2N points)")
print()
print("| distribution | N | surfreg Measure (2 threads) | CGAL union | surfreg/CGAL time | 1 thread/CGAL time | Measure: triangulate / domain / tree / locate / interpolate / volume |")
print("|---|---:|---:|---:|---:|---:|---|")
large = []
for dist in dists:
    for n in sizes:
        s, c = rows.get(("surfreg", dist, n)), rows.get(("cgal_union_triangulation", dist, n))
        ratio = s["real"] / c["real"] if ok(s) and ok(c) else None
        serial = rows.get(("surfreg_serial", dist, n))
        cpu_ratio = serial["real"] / c["real"] if ok(serial) and ok(c) else None
        if n == max(sizes) and ratio is not None:
            large.append((dist, n, ratio))
        split = "-"
        if ok(s):
            t = s["counters"]
            total = t.get("t_total", 0.0)
            if total > 0:
                split = " / ".join("%.0f%%" % (100.0 * t.get(k, 0.0) / total) for k in (
                    "t_triangulate", "t_domain", "t_spanning_tree", "t_locate", "t_interpolate",
                    "t_volume"))
        print("| %s | %s | %s | %s | %s | %s | %s |" % (
            dist, fmt_n(n),
            "%.1f ms" % (s["real"] * 1e3) if ok(s) else "-",
            "%.1f ms" % (c["real"] * 1e3) if ok(c) else "-",
            "%.2f" % ratio if ratio is not None else "-",
            "%.2f" % cpu_ratio if cpu_ratio is not None else "-", split))

print()
print("| memory at N = 1e6 (Measure) | points | peak RSS before | peak RSS after | increase B/pt | process peak B/pt | budget 1 GiB |")
print("|---|---:|---:|---:|---:|---:|---|")
for dist in ("uniform", "jittered"):
    path = os.path.join(out_dir, "measure_memory_%s.txt" % dist)
    kv = {}
    with open(path) as f:
        for line in f:
            key, _, value = line.partition(":")
            kv[key.strip()] = value.strip()
    if "peak_rss_after_kib" not in kv:
        problems.append("measure_memory %s failed (status %s)" % (dist, kv.get("status", "?")))
        print("| %s | - | - | - | - | - | failed (status %s) |" % (dist, kv.get("status", "?")))
        continue
    peak = float(kv["peak_bytes"])
    within = peak <= budget
    if not within:
        problems.append("measure_memory %s: peak %.0f MiB exceeds the budget" % (dist, peak / 2**20))
    print("| %s | %s | %.1f MiB | %.1f MiB | %s | %s | %s (%.0f%%) |" % (
        dist, kv["points"], int(kv["peak_rss_before_kib"]) / 1024.0,
        int(kv["peak_rss_after_kib"]) / 1024.0, kv["increase_bytes_per_point"],
        kv["peak_bytes_per_point"], "within" if within else "EXCEEDED", 100.0 * peak / budget))

print()
for dist, n, r in large:
    print("- %s %s: Measure / CGAL union triangulation time %.2f, target <= 3: %s"
          % (dist, fmt_n(n), r, "met" if r <= 3.0 else "NOT met"))
ctx = data.get("context", {})
if "load_avg" in ctx:
    print("- load average at start: %s (wall times are inflated if other jobs share the cores;"
          " the CPU-time ratio is less affected)" % ", ".join("%.2f" % x for x in ctx["load_avg"]))
for note in notes:
    print("- growth: " + note)
for p in problems:
    print("- PROBLEM: " + p)
if bench_status:
    print("- measure_bench exited with status %d (2 = a check failed, see its stderr)" % bench_status)
print("- wall time of the whole run: %d s" % elapsed)
PY
if [[ $bench_status -ne 0 ]]; then exit "$bench_status"; fi
exit "$memory_status"
