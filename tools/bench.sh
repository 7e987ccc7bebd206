#!/usr/bin/env bash
# Every benchmark behind the table in docs/benchmarks.md, in one command:
#
#   tools/bench.sh            # after tools/setup.sh has built build/
#
# Run it on a quiet machine (nothing else running): the figures are medians of
# wall time on this 2-core machine. ROSY_BENCH_REPETITIONS (5) sets the repetitions,
# ROSY_BUILD_DIR the build folder. The 1M-face cases run in processes of their own,
# three times each, so their peak memory counters cover only them.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
build=${ROSY_BUILD_DIR:-$here/build}
reps=${ROSY_BENCH_REPETITIONS:-5}
cmake --build "$build" -j "${ROSY_JOBS:-2}" --target field_bench render_bench plotter_bench remesh_bench rosyhatch >/dev/null
agg=(--benchmark_repetitions="$reps" --benchmark_report_aggregates_only=true)

echo "== field stages, bunny00 =="
"$build/bench/field_bench" --benchmark_filter=-1M "${agg[@]}" 2>/dev/null | grep -E '_median|^Benchmark|^---'
echo "== render stages, scenes/bunny.yaml at 1024² =="
"$build/bench/render_bench" --benchmark_filter=-1M "${agg[@]}" 2>/dev/null | grep -E '_median|^Benchmark|^---'
echo "== plotter output =="
"$build/bench/plotter_bench" "${agg[@]}" 2>/dev/null | grep -E '_median|^Benchmark|^---'
echo "== field stage, 1.2M faces (3 processes) =="
for _ in 1 2 3; do "$build/bench/field_bench" --benchmark_filter=1M 2>/dev/null | grep '^BM_'; done
echo "== render at 4096², 1.2M faces (3 processes) =="
for _ in 1 2 3; do "$build/bench/render_bench" --benchmark_filter=Render1MFaces 2>/dev/null | grep '^BM_'; done
echo "== whole process: rosyhatch render scenes/bunny.yaml (1024²), $reps runs: wall s, peak KiB =="
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$build/cli/rosyhatch" render scenes/bunny.yaml -o "$out/bunny.png" --quiet >/dev/null # warm the file cache
for _ in $(seq "$reps"); do
  /usr/bin/time -f "%e %M" "$build/cli/rosyhatch" render scenes/bunny.yaml -o "$out/bunny.png" --quiet 2>&1 >/dev/null
done | sort -n | awk '{w[NR]=$1; m=$2} END {printf "median wall %.2f s (min %.2f, max %.2f), peak %.0f MiB\n", w[int((NR+1)/2)], w[1], w[NR], m/1024}'
echo "== whole process against its floor (issue 17): render_floor and rosyhatch render alternating, $reps rounds, median wall s =="
cmake --build "$build" -j "${ROSY_JOBS:-2}" --target render_floor >/dev/null
for _ in $(seq "$reps"); do
  /usr/bin/time -f "%e" -o "$out/floor" "$build/bench/render_floor" data/meshes/bunny00.off 1024
  /usr/bin/time -f "%e" -o "$out/render" "$build/cli/rosyhatch" render scenes/bunny.yaml -o "$out/bunny.png" --quiet >/dev/null
  echo "$(cat "$out/floor") $(cat "$out/render")"
done | python3 -c '
import statistics, sys
rows = [tuple(map(float, l.split())) for l in sys.stdin if l.strip()]
floor, render = statistics.median(r[0] for r in rows), statistics.median(r[1] for r in rows)
print(f"floor {floor:.3f} s, render {render:.3f} s: {render / floor:.2f}x the floor")'
echo "== remesher, bunny00 at L = 1 % (x_field: a multiple of the field stage measured in the same process) =="
"$build/bench/remesh_bench" "${agg[@]}" 2>/dev/null | grep -E '_median|^Benchmark|^---'
echo "== whole process: rosyhatch remesh data/meshes/bunny00.off, $reps runs: wall s, peak KiB, total / field stage of the same run =="
for _ in $(seq "$reps"); do
  /usr/bin/time -f "%e %M" -o "$out/time" "$build/cli/rosyhatch" remesh data/meshes/bunny00.off -o "$out/b.obj" --report "$out/b.json" --quiet
  python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["timings_ms"]; w, m = open(sys.argv[2]).read().split(); print(w, m, t["total"] / (t["frames"] + t["field"] + t["singularities"]))' "$out/b.json" "$out/time"
done | sort -n | awk '{w[NR]=$1; m=$2; r[NR]=$3} END {printf "median wall %.2f s (min %.2f, max %.2f), peak %.0f MiB, %.1fx the field stage (median run)\n", w[int((NR+1)/2)], w[1], w[NR], m/1024, r[int((NR+1)/2)]}'
