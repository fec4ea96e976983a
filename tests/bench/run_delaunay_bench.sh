#!/usr/bin/env bash
# Runs the Delaunay benchmarks and prints a Markdown summary.
#
#   tests/bench/run_delaunay_bench.sh [build_dir] [extra delaunay_bench flags...]
#
# build_dir defaults to build-bench at the top of the source tree. Raw results
# go to <build_dir>/bench-results/ (delaunay_bench.json, memory_*.txt).
# Exit status: that of delaunay_bench (2 = surfreg and CGAL disagreed on some
# input; see its stderr), else 0.
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build_dir=${1:-$script_dir/../../build-bench}
[[ $# -gt 0 ]] && shift
bench=$build_dir/tests/bench/delaunay_bench
memory=$build_dir/tests/bench/delaunay_memory
for exe in "$bench" "$memory"; do
  if [[ ! -x $exe ]]; then
    echo "missing $exe: build the delaunay_bench and delaunay_memory targets first" >&2
    exit 1
  fi
done
out_dir=$build_dir/bench-results
mkdir -p "$out_dir"
json=$out_dir/delaunay_bench.json
start=$(date +%s)

# Console output stays on the terminal as progress; the JSON file is what
# the summary reads.
bench_status=0
"$bench" --benchmark_out="$json" --benchmark_out_format=json "$@" || bench_status=$?
if [[ ! -s $json ]]; then
  echo "delaunay_bench wrote no results (exit status $bench_status)" >&2
  exit 1
fi

# One process per measurement so each peak RSS is a single triangulation's.
for dist in uniform grid; do
  "$memory" 1000000 "$dist" >"$out_dir/memory_$dist.txt"
done
elapsed=$(($(date +%s) - start))

python3 - "$json" "$out_dir" "$elapsed" "$bench_status" <<'PY'
import json
import os
import sys

json_path, out_dir, elapsed, bench_status = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
with open(json_path) as f:
    data = json.load(f)

# name: BM_Triangulate/<impl>/<distribution>/<N>[/iterations:k][/real_time]
rows = {}
for b in data["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue
    parts = b["name"].split("/")
    impl, dist, n = parts[1], parts[2], int(parts[3])
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b.get("time_unit", "ns")]
    rows.setdefault((dist, n), {})[impl] = {
        "error": b.get("error_message") if b.get("error_occurred") else None,
        "real": b.get("real_time", 0.0) * scale,  # seconds per triangulation
        "cpu": b.get("cpu_time", 0.0) * scale,
        "points": b.get("points", 0.0),
        "triangles": b.get("triangles", -1),
    }

def mpts(r):
    return "%.2f" % (r["points"] / r["real"] / 1e6) if r and not r["error"] and r["real"] > 0 else "-"

def ratio(a, b, key):
    if not a or not b or a["error"] or b["error"] or b[key] <= 0:
        return None
    return a[key] / b[key]

order = {"uniform": 0, "jittered": 1, "grid": 2}
print()
print("| distribution | N | surfreg Mpts/s | CGAL Mpts/s | surfreg/CGAL time | (CPU time) | triangles |")
print("|---|---:|---:|---:|---:|---:|---|")
problems, large = [], []
for (dist, n) in sorted(rows, key=lambda k: (order.get(k[0], 9), k[1])):
    s, c = rows[(dist, n)].get("surfreg"), rows[(dist, n)].get("cgal")
    r_real, r_cpu = ratio(s, c, "real"), ratio(s, c, "cpu")
    if s and s["error"]:
        problems.append("%s/%d: surfreg error: %s" % (dist, n, s["error"]))
    tri = "%d" % s["triangles"] if s and not s["error"] else "-"
    if s and c and not s["error"] and not c["error"] and s["triangles"] != c["triangles"]:
        tri = "MISMATCH %d vs CGAL %d" % (s["triangles"], c["triangles"])
        problems.append("%s/%d: triangle count %d (surfreg) vs %d (CGAL)"
                        % (dist, n, s["triangles"], c["triangles"]))
    elif s and c:
        tri += " (= CGAL)"
    if n >= 1000000 and r_real is not None:
        large.append((dist, r_real))
    print("| %s | %d | %s | %s | %s | %s | %s |" % (
        dist, n, mpts(s), mpts(c),
        "%.2f" % r_real if r_real is not None else "-",
        "%.2f" % r_cpu if r_cpu is not None else "-", tri))

print()
print("| memory at 1e6 (surfreg) | points | peak RSS before | peak RSS after | increase B/pt | process peak B/pt |")
print("|---|---:|---:|---:|---:|---:|")
for dist in ("uniform", "grid"):
    path = os.path.join(out_dir, "memory_%s.txt" % dist)
    kv = {}
    with open(path) as f:
        for line in f:
            key, _, value = line.partition(":")
            kv[key.strip()] = value.strip()
    print("| %s | %s | %.1f MiB | %.1f MiB | %s | %s |" % (
        dist, kv["points"], int(kv["peak_rss_before_kib"]) / 1024.0,
        int(kv["peak_rss_after_kib"]) / 1024.0, kv["increase_bytes_per_point"],
        kv["peak_bytes_per_point"]))

print()
for dist, r in large:
    print("- %s 1e6: surfreg/CGAL time %.2f, target <= 1.5: %s" % (dist, r, "met" if r <= 1.5 else "NOT met"))
ctx = data.get("context", {})
if "load_avg" in ctx:
    print("- load average at start: %s (wall times are inflated if other jobs share the cores;"
          " the CPU-time ratio is less affected)" % ", ".join("%.2f" % x for x in ctx["load_avg"]))
for p in problems:
    print("- PROBLEM: " + p)
if bench_status:
    print("- delaunay_bench exited with status %d (2 = disagreement with CGAL, see its stderr)" % bench_status)
print("- wall time of the whole run: %d s" % elapsed)
PY
exit "$bench_status"
