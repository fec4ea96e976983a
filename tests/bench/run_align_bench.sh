#!/usr/bin/env bash
# Builds and runs the registration benchmarks and prints a Markdown summary:
# re-measure speedups over a full Measure, walk steps per point, and whole
# Align runs in units of full measures.
#
#   tests/bench/run_align_bench.sh [build_dir] [extra align_bench flags...]
#
# build_dir defaults to build-bench at the top of the source tree (configured
# Release if new; the align_bench target is built). `--with_1e6` adds the
# N = 1e6 rows. Raw results go to <build_dir>/bench-results/align_bench.json.
# On a shared machine add --benchmark_repetitions=5
# --benchmark_enable_random_interleaving=true: each row is then the
# repetition of median wall time.
# Exit status: that of align_bench (2 = a check failed, see its stderr).
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source_dir=$(cd "$script_dir/../.." && pwd)
build_dir=${1:-$source_dir/build-bench}
[[ $# -gt 0 ]] && shift
if [[ ! -f $build_dir/CMakeCache.txt ]]; then
  cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build_dir" -j2 --target align_bench
bench=$build_dir/tests/bench/align_bench
out_dir=$build_dir/bench-results
mkdir -p "$out_dir"
json=$out_dir/align_bench.json
start=$(date +%s)

bench_status=0
"$bench" --benchmark_out="$json" --benchmark_out_format=json "$@" || bench_status=$?
if [[ ! -s $json ]]; then
  echo "align_bench wrote no results (exit status $bench_status)" >&2
  exit 1
fi
elapsed=$(($(date +%s) - start))

python3 - "$json" "$elapsed" "$bench_status" <<'PY'
import json
import sys

json_path, elapsed, bench_status = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
with open(json_path) as f:
    data = json.load(f)

# BM_Remeasure|BM_Scratch|BM_ScratchOwnMesh/<work>/<step>/<N>/..., BM_Measure/<threads>/<N>/...,
# BM_Align/<cost>/<N>/...: key (kind, what, step, N).
rows = {}
problems = []
for b in data["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue
    parts = b["name"].split("/")
    kind = parts[0][3:]
    if kind in ("Remeasure", "Scratch", "ScratchOwnMesh"):
        key = (kind, parts[1], parts[2], int(parts[3]))
    else:
        key = (kind, parts[1], "", int(parts[2]))
    if b.get("error_occurred"):
        problems.append("%s: %s" % (b["name"], b.get("error_message")))
        continue
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b.get("time_unit", "ns")]
    rows.setdefault(key, []).append(dict(b, real=b["real_time"] * scale, cpu=b["cpu_time"] * scale))
# With --benchmark_repetitions=K: the repetition of median wall time (its
# counters with it), so one slow or lucky run on a shared machine does not
# decide a row.
repetitions = max(len(v) for v in rows.values()) if rows else 1
rows = {k: sorted(v, key=lambda r: r["real"])[(len(v) - 1) // 2] for k, v in rows.items()}

sizes = sorted({k[3] for k in rows})
steps = [s for s in ("small", "large") if any(k[2] == s for k in rows)]
works = [("update", "Update only"), ("axial", "axial (Update + residuals, J)"),
         ("volume_1t", "volume 1 thread (Update + cost, ∇)"),
         ("volume_2t", "volume 2 threads (Update + cost, ∇)"),
         ("volinc_1t", "volume incremental 1 thread (Update + cached overlay, ∇)"),
         ("volinc_2t", "volume incremental 2 threads (Update + cached overlay, ∇)")]
single_thread = {"update", "axial", "volume_1t", "volinc_1t"}

def fmt_n(n):
    return "1e%d" % (len(str(n)) - 1) if str(n).strip("0") == "1" else str(n)

def ms(seconds):
    return "%.3g ms" % (seconds * 1e3) if seconds < 1 else "%.2f s" % seconds

def ratio(x):
    return "%.1f" % x if x >= 10 else "%.2f" % x

print()
print("### Re-measure after a step vs full Measure")
print()
print("Step small: δ = 1e-4 rad, 0.01 spacing; large: 1e-3 rad, 0.1 spacing (all six parameters).")
print("Speedup = full Measure time / this time: wall time against Measure with 2 threads (the")
print("default), and thread CPU time against Measure with 1 thread (single-threaded rows only;")
print("steadier when other jobs share the cores). Scratch = a fresh state locating everything")
print("(LocateAll) at the same new θ, then the same work. Target: ≥ 10 for the re-measure.")
print()
print("| N | step | re-measure | walk: time | speedup (wall, vs 2t) | speedup (CPU, vs 1t) "
      "| walk steps/pt | remeshes/update | scratch: time | scratch speedup (wall) | scratch / walk |")
print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
targets = []
for n in sizes:
    m2, m1 = rows.get(("Measure", "2t", "", n)), rows.get(("Measure", "1t", "", n))
    for step in steps:
        for work, label in works:
            w = rows.get(("Remeasure", work, step, n))
            s = rows.get(("Scratch", work, step, n))
            if not w:
                continue
            wall = m2["real"] / w["real"] if m2 else None
            cpu = m1["cpu"] / w["cpu"] if m1 and work in single_thread else None
            if work in ("axial", "volume_1t", "volume_2t", "volinc_1t", "volinc_2t") and wall is not None:
                targets.append((n, step, work, wall, cpu))
            print("| %s | %s | %s | %s | %s | %s | %.2f | %.2g | %s | %s | %s |" % (
                fmt_n(n), step, label, ms(w["real"]),
                ratio(wall) if wall else "-", ratio(cpu) if cpu else "-",
                w.get("walk_steps_per_point", 0), w.get("remeshes_per_update", 0),
                ms(s["real"]) if s else "-",
                ratio(m2["real"] / s["real"]) if s and m2 else "-",
                ratio(s["real"] / w["real"]) if s else "-"))

print()
print("Fresh state from B's own mesh (as each new state in Align starts), Update only:")
print()
print("| N | step | time | remeshes/update | walk steps/pt | vs scratch at the state's mesh |")
print("|---|---|---:|---:|---:|---:|")
for n in sizes:
    for step in steps:
        o = rows.get(("ScratchOwnMesh", "update", step, n))
        s = rows.get(("Scratch", "update", step, n))
        if o:
            print("| %s | %s | %s | %.2g | %.2f | %s |" % (
                fmt_n(n), step, ms(o["real"]), o.get("remeshes_per_update", 0),
                o.get("walk_steps_per_point", 0), ratio(o["real"] / s["real"]) + "x" if s else "-"))

print()
print("### Full Measure (B moved by θ_true + δ_large): where its time goes")
print()
print("| N | threads | wall | thread CPU | triangulate | spanning tree | locate | interpolate | volume | walk steps/pt |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
for n in sizes:
    for t in ("2t", "1t"):
        m = rows.get(("Measure", t, "", n))
        if not m:
            continue
        total = m.get("t_total", 0) or 1.0
        split = ["%.0f%%" % (100.0 * m.get(k, 0) / total) for k in (
            "t_triangulate", "t_spanning_tree", "t_locate", "t_interpolate", "t_volume")]
        print("| %s | %s | %s | %s | %s | %.2f |" % (
            fmt_n(n), t, ms(m["real"]), ms(m["cpu"]), " | ".join(split),
            m.get("walk_steps_per_point", 0)))

aligns = sorted(k for k in rows if k[0] == "Align")
if aligns:
    print()
    print("### Whole Align from the identity (2° about (1, -2, 0.5), shift (3, -2, 1) spacings)")
    print()
    print("Align / Measure: Align's wall time over BM_Measure/2t at the same N (this run); the")
    print("in-row count re-times Measure right after Align. Target (axial): < 20 full measures.")
    print()
    print("| N | cost | Align | Measure (2t) | Align / Measure | in-row count | iterations | converged "
          "| rotation error | translation error | before solve / solve / after |")
    print("|---|---|---:|---:|---:|---:|---:|---|---:|---:|---|")
    for key in aligns:
        a = rows[key]
        n = key[3]
        m2 = rows.get(("Measure", "2t", "", n))
        r = a["real"] / m2["real"] if m2 else None
        if key[1] == "axial" and r is not None:
            targets.append((n, "-", "align_axial", r, a.get("full_measures")))
        print("| %s | %s | %s | %s | %s | %.1f | %d | %s | %.3g° | %.3g spacings | %.1f / %.1f / %.1f s |" % (
            fmt_n(n), {"axial": "axial", "default": "default (volume, axial prealign)",
                       "information": "default, `stddev: information`"}.get(key[1], key[1]),
            ms(a["real"]), ms(m2["real"]) if m2 else "-", ratio(r) if r else "-",
            a.get("full_measures", 0), a.get("iterations", 0),
            "yes" if a.get("converged", 0) else "no", a.get("rotation_error_deg", 0),
            a.get("translation_error_spacings", 0), a.get("t_before_solve", 0),
            a.get("t_solve", 0), a.get("t_after_solve", 0)))

    for n in sorted({key[3] for key in aligns}):
        d, i = rows.get(("Align", "default", "", n)), rows.get(("Align", "information", "", n))
        if d and i:
            print()
            print("%s: the sandwich standard deviations' own cost (default − information) %.0f ms, "
                  "%.1f%% of the default alignment" % (fmt_n(n), 1e3 * (d["real"] - i["real"]),
                                                       100 * (d["real"] - i["real"]) / d["real"]))

print()
for n, step, work, wall, cpu in targets:
    if work == "align_axial":
        print("- %s axial Align: %.1f full measures (in-row %.1f), target < 20: %s"
              % (fmt_n(n), wall, cpu or 0, "met" if wall < 20 else "NOT met"))
    else:
        print("- %s %s step, %s re-measure: %.1fx faster than Measure (wall)%s, target ≥ 10: %s"
              % (fmt_n(n), step, work, wall, (", %.1fx in CPU" % cpu) if cpu else "",
                 "met" if wall >= 10 else "NOT met"))
ctx = data.get("context", {})
if "load_avg" in ctx:
    print("- load average at start: %s (2 cores; wall times are inflated when other jobs run)"
          % ", ".join("%.2f" % x for x in ctx["load_avg"]))
for p in problems:
    print("- PROBLEM: " + p)
if bench_status:
    print("- align_bench exited with status %d (2 = a check failed, see its stderr)" % bench_status)
if repetitions > 1:
    print("- each row: the median of %d repetitions (by wall time)" % repetitions)
print("- wall time of the whole run: %d s" % elapsed)
PY
exit "$bench_status"
