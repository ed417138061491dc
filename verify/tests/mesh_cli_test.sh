#!/usr/bin/env bash
# isoforge-verify mesh FILE on tiny meshes: self-intersection counts and the exit status of
# --require; the decimation benchmark's subcommands (make-mesh, decimate, distance).
# Usage: mesh_cli_test.sh ISOFORGE_VERIFY SCRATCH_DIR
set -u
bin=$1 tmp=$2
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect NAME STATUS REGEX ARGS...: exit status STATUS and stdout+stderr matching REGEX.
expect() {
  local name=$1 status=$2 regex=$3; shift 3
  local out rc
  out=$("$bin" "$@" 2>&1); rc=$?
  if [ "$rc" -ne "$status" ]; then fail "$name: exit $rc, expected $status:"$'\n'"$out"; return; fi
  if ! grep -Eq -- "$regex" <<<"$out"; then fail "$name: output does not match /$regex/:"$'\n'"$out"; fi
}

# A closed, outward tetrahedron.
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$tmp/tetra.off"
# Three triangles on one edge (non-manifold): they meet only along the edge.
printf 'OFF\n5 3 0\n0 0 0\n1 0 0\n0.5 1 0\n0.5 -1 0\n0.5 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n' > "$tmp/book.off"
# Two triangles crossing each other.
printf 'OFF\n6 2 0\n0 0 0\n2 0 0\n1 2 0\n1 1 -1\n1 1 1\n1 3 0.5\n3 0 1 2\n3 3 4 5\n' > "$tmp/cross.off"

expect tetra_report 0 "self-intersecting face pairs \(exact\): 0" mesh "$tmp/tetra.off"
expect tetra_all 0 "required checks passed: closed, manifold, oriented, no-self-intersections" \
  mesh "$tmp/tetra.off" --require closed,manifold,oriented,no-self-intersections
expect book_pairs 0 "self-intersecting face pairs \(exact\): 0" mesh "$tmp/book.off"
expect book_no_si 0 "required checks passed: no-self-intersections" \
  mesh "$tmp/book.off" --require no-self-intersections
expect book_manifold 1 "book.off: required checks failed: closed \(6 border edges\), manifold \(1 non-manifold edges, 2 non-manifold vertices\)$" \
  mesh "$tmp/book.off" --require closed,manifold,no-self-intersections
expect cross_pairs 0 "self-intersecting face pairs \(exact\): 1" mesh "$tmp/cross.off"
expect cross_no_si 1 "required checks failed: no-self-intersections \(1 intersecting face pairs\)$" \
  mesh "$tmp/cross.off" --require no-self-intersections
expect cross_repeated 1 "required checks failed: closed .*no-self-intersections" \
  mesh "$tmp/cross.off" --require closed --require no-self-intersections
# Usage errors: exit status 2.
expect unknown_name 2 "watertight" mesh "$tmp/tetra.off" --require closed,watertight
expect skipped_si 2 "contradicts" mesh "$tmp/tetra.off" --require no-self-intersections \
  --no-self-intersections
# The decimation benchmark's subcommands. An icosphere of 5 subdivisions has 20 * 4^5 faces; two
# of them glued on an edge share its 2 points.
expect make_glued 0 "wrote .*glued.off: 20482 points, 40960 triangles" \
  make-mesh glued-spheres "$tmp/glued.off"
# CGAL's collapses of a closed mesh remove two faces each: from 40 960 to exactly 1000 (the
# spheres are first split at their shared edge, which the JSON line reports).
expect cgal_gh 0 '"peer": "cgal-gh", .*"output_triangles": 1000,' \
  decimate "$tmp/glued.off" -o "$tmp/gh.off" --target 1000 --policy gh
expect cgal_split 0 '"split_non_manifold": true' \
  decimate "$tmp/glued.off" -o "$tmp/lt.off" --target 1000 --policy lt
expect cgal_policy 2 "policy" decimate "$tmp/glued.off" -o "$tmp/x.off" --target 10 --policy qem
# distance --check: one line per mesh, the checks of each.
expect distance_check 0 '"mesh": ".*cross.off".*"self_intersections": 1, "manifold": true' \
  distance "$tmp/tetra.off" "$tmp/tetra.off" "$tmp/cross.off" --check
expect distance_self 0 '"mesh": ".*tetra.off", .*"hausdorff": [0-9.e-]+, "rms": [0-9.e-]+, .*"relative_hausdorff": ([0-9]\.[0-9]+e-1[0-9]|0),' \
  distance "$tmp/tetra.off" "$tmp/tetra.off"
expect version 0 "^[0-9]+\.[0-9]+\.[0-9]+$" --version

if [ $failures -ne 0 ]; then echo "$failures failure(s)"; exit 1; fi
echo "all isoforge-verify mesh tests passed"
