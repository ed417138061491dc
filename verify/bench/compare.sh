#!/usr/bin/env bash
# Before/after: runs the same benchmarks of two bench builds (e.g. the last release and a
# refactoring) alternately, ROUNDS times each, and prints the median times and their ratio, so a
# change that should not change speed can show it did not. Both builds must have the benchmark
# programs (cmake -DISOFORGE_BUILD_BENCH=ON; make bench builds them).
# Usage: compare.sh BEFORE_BUILD AFTER_BUILD OUT_DIR [ROUNDS] [FILTER]
#   FILTER is a Google Benchmark regex over "program:benchmark" names (default: the contouring,
#   sampling and distance-field cases).
set -euo pipefail
before=$1 after=$2 out=$3 rounds=${4:-5}
filter=${5:-'^(bench_contour:contour_dense|bench_contour_sparse:contour_vdb_cone/[0-9]+/[01]/0|bench_implicit:|bench_model:(modeller|crossover/(1000|100000)/|attractor))'}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
[ -d "$out/fields" ] || /usr/bin/python3 "$here/peers/make_fields.py" "$out/fields" 256 512
export ISOFORGE_BENCH_FIELDS="$out/fields"

# The cases: every benchmark of the four programs whose "program:name" matches FILTER.
cases=()
for prog in bench_contour bench_contour_sparse bench_implicit bench_model; do
  while read -r name; do
    [[ "$prog:$name" =~ $filter ]] && cases+=("$prog:$name")
  done < <("$after/verify/bench/$prog" --benchmark_list_tests)
done
echo "${#cases[@]} cases, $rounds rounds each, before and after alternating"

: > "$out/times.tsv"
for ((r = 1; r <= rounds; ++r)); do
  for c in "${cases[@]}"; do
    prog=${c%%:*} name=${c#*:}
    for side in before after; do
      dir=$before; [ $side = after ] && dir=$after
      # One run of the case (its own process: no warm caches from the other build).
      t=$("$dir/verify/bench/$prog" --benchmark_filter="^${name}\$" --benchmark_format=json \
            2>/dev/null | /usr/bin/python3 -c '
import json, sys
b = [x for x in json.load(sys.stdin)["benchmarks"] if x.get("run_type") == "iteration"]
unit = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b[0]["time_unit"]]
print(b[0]["real_time"] * unit)')
      printf '%s\t%s\t%s\n' "$c" "$side" "$t" >> "$out/times.tsv"
    done
  done
done

/usr/bin/python3 - "$out/times.tsv" <<'EOF' | tee "$out/compare.md"
import collections, statistics, sys
t = collections.defaultdict(lambda: {"before": [], "after": []})
for line in open(sys.argv[1]):
    case, side, ms = line.rstrip("\n").split("\t")
    t[case][side].append(float(ms))
print("| case | before ms (median) | after ms (median) | after / before |")
print("|---|---:|---:|---:|")
for case, v in t.items():
    b, a = statistics.median(v["before"]), statistics.median(v["after"])
    print(f"| {case} | {b:.3g} | {a:.3g} | {a / b:.3f} |")
EOF
