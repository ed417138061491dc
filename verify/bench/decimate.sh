#!/usr/bin/env bash
# The decimation benchmark: isoforge and its peers decimate the same inputs to the same triangle
# counts in one run; every output is then measured by one implementation (isoforge-verify
# distance --check: Hausdorff and RMS distance to the input relative to the input's bounding-box
# diagonal, exact self-intersecting pairs, manifoldness) and decimate_report.py prints a Markdown
# table with ratios. Run by hand (about 10 minutes on 2 cores), or by run.sh's decimate section;
# not part of ctest. See docs/verification.md, "Decimation".
#
# Usage: decimate.sh BUILD OUT [CASE...]
#   BUILD: a build with -DISOFORGE_BUILD_BENCH=ON (isoforge, isoforge-verify, meshopt_decimate);
#   OUT: a directory for inputs, outputs and OUT/decimate.md.
#   CASE: big bunny headsq noisy-sphere (default: all).
# Environment: DECIMATE_TIMEOUT (seconds per command, default 300).
set -euo pipefail
build=$(cd "$1" && pwd) out=$2; shift 2
cases=${*:-big bunny headsq noisy-sphere}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
timeout_s=${DECIMATE_TIMEOUT:-300}
mkdir -p "$out/inputs" "$out/outputs"
out=$(cd "$out" && pwd)
iso=$build/src/isoforge
verify=$build/verify/isoforge-verify
meshopt=$build/verify/bench/meshopt_decimate
python=/usr/bin/python3
runs=$out/runs.jsonl metrics=$out/metrics.jsonl
: > "$runs"
: > "$metrics"

# (grep reads the whole help: with pipefail, grep -q stopping early fails the pipeline by SIGPIPE)
have_cli=0; "$iso" --help | grep "^  decimate " > /dev/null && have_cli=1
have_vtk=0; $python -c "import vtk" 2> /dev/null && have_vtk=1
[ $have_cli = 1 ] || echo "isoforge decimate is not in this build: its rows are left out"
[ $have_vtk = 1 ] || echo "python3-vtk9 is missing: the VTK rows are left out"

# run CASE PEER OUTPUT TARGET COMMAND...: one record in runs.jsonl (decimate_run.py).
run() {
  local case=$1 peer=$2 output=$3 target=$4; shift 4
  local err=$out/outputs/$peer-$case-$target.err
  $python "$here/decimate_run.py" "$case" "$peer" "$output" "$target" "$timeout_s" "$err" -- "$@" \
    | tee -a "$runs" | grep '"status": 0' > /dev/null || echo "  $peer: failed (see $err)"
}

# The inputs (made by isoforge itself where possible).
input_of() {
  local c=$1 f
  case $c in
    big)
      f=$out/inputs/big.ply
      if [ ! -f "$f" ]; then
        # A torus, a sphere and a rounded cube in one closed genus-1 surface with creases where
        # they meet: sampled into a 550^3 narrow band and contoured, 1 052 680 triangles.
        "$iso" sample -f 'union(torus(R=0.6, r=0.2), sphere(center=[0.5,0.5,0.3], r=0.4), superquadric(center=[-0.5,-0.4,0], radii=[0.35,0.35,0.35], n=0.3, e=0.3))' \
          -b -1.2 1.2 -1.2 1.2 -1.2 1.2 -d 550 -o "$out/inputs/big.vdb" > /dev/null
        "$iso" contour "$out/inputs/big.vdb" -v 0 -o "$f" > /dev/null
      fi ;;
    bunny) f=$root/data/bunny.ply ;;
    headsq)
      f=$out/inputs/headsq.ply
      # The skin of the CT head: 78 510 triangles, open where it leaves the volume.
      [ -f "$f" ] || "$iso" contour "$root/data/headsq/quarter.nhdr" -v 1150 --flip -o "$f" > /dev/null ;;
    noisy-sphere)
      f=$out/inputs/noisy-sphere.ply
      [ -f "$f" ] || "$verify" make-mesh noisy-sphere "$f" > /dev/null ;;
    *) echo "unknown case $c" >&2; exit 2 ;;
  esac
  echo "$f"
}

triangles_of() {
  "$iso" info "$1" | sed -n 's/^cells: \([0-9]*\).*/\1/p'
}

# step PEER COMMAND...: one decimation of the current case ($c, $target) into $o-PEER.ply, added to
# the outputs to measure when the command wrote it.
step() {
  local peer=$1; shift
  echo "  $peer"
  rm -f "$o-$peer.ply"
  run "$c" "$peer" "$o-$peer.ply" "$target" "$@"
  if [ -f "$o-$peer.ply" ]; then outputs+=("$o-$peer.ply"); fi
}

for c in $cases; do
  in=$(input_of "$c")
  n=$(triangles_of "$in")
  percents="10 2"; [ "$c" = big ] && percents=10
  for p in $percents; do
    target=$(( (n * p + 50) / 100 ))
    echo "== $c: $n triangles -> $p % = $target"
    o=$out/outputs/$c-$p
    outputs=()
    if [ $have_cli = 1 ]; then
      for t in 1 2; do
        # --no-measure: the command would otherwise also measure its distance to the input.
        step "isoforge-t$t" "$iso" --threads "$t" decimate "$in" -o "$o-isoforge-t$t.ply" \
          --target-triangles "$target" --no-measure
        step "isoforge-refine-t$t" "$iso" --threads "$t" decimate "$in" \
          -o "$o-isoforge-refine-t$t.ply" --target-triangles "$target" --refine --no-measure
      done
    fi
    step meshopt "$meshopt" "$in" "$o-meshopt.ply" "$target"
    step meshopt-lockborder "$meshopt" "$in" "$o-meshopt-lockborder.ply" "$target" --lock-border
    step cgal-gh "$verify" decimate "$in" -o "$o-cgal-gh.ply" --target "$target" --policy gh
    step cgal-lt "$verify" decimate "$in" -o "$o-cgal-lt.ply" --target "$target" --policy lt
    if [ $have_vtk = 1 ]; then
      for m in quadric pro pro-topology; do
        step "vtk-$m" $python "$here/peers/vtk_decimate.py" "$m" "$in" "$o-vtk-$m.ply" "$target"
      done
    fi
    echo "  measuring ${#outputs[@]} outputs"
    "$verify" distance "$in" "${outputs[@]}" --check | while read -r line; do
      printf '%s\n' "$line" | $python -c '
import json, sys
rec = json.loads(sys.stdin.read())
rec["case"], rec["percent"] = sys.argv[1], int(sys.argv[2])
print(json.dumps(rec))' "$c" "$p" >> "$metrics"
    done
  done
done
$python "$here/decimate_report.py" "$out" | tee "$out/decimate.md"
