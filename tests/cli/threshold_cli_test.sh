#!/usr/bin/env bash
# End-to-end tests of isoforge threshold and isoforge surface, and of --q (a PLOT3D solution) on
# every subcommand that reads any dataset: exit codes, messages and the properties of the files.
# Usage: threshold_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"

cells_of() { "$bin" info "$1" | sed -n 's/^cells: \([0-9]*\).*/\1/p'; }
points_of() { "$bin" info "$1" | sed -n 's/^points: \([0-9]*\).*/\1/p'; }

# ---- threshold ----
# A range covering every value keeps every cell (post.vtk: 8750 tetrahedra, Pressure 0.355..1.641).
expect_ok thr_all "wrote .*: 8750 of 8750 cells, 2288 points \(point array 'Pressure'\)" "$bin" threshold "$data/post.vtk" -a Pressure --above 0 -o "$tmp/all.vtu"
[ "$(cells_of "$tmp/all.vtu")" = 8750 ] || fail "thr_all: the file does not hold 8750 cells"
# all points <= overlap, any point <= overlap, all < any.
n_all=$("$bin" threshold "$data/post.vtk" -a Pressure --between 0.8 1.0 -o "$tmp/a.vtu" 2>&1 | sed -n 's/.*: \([0-9]*\) of.*/\1/p')
n_any=$("$bin" threshold "$data/post.vtk" -a Pressure --between 0.8 1.0 --any-point -o "$tmp/b.vtu" 2>&1 | sed -n 's/.*: \([0-9]*\) of.*/\1/p')
n_ovl=$("$bin" threshold "$data/post.vtk" -a Pressure --between 0.8 1.0 --overlap -o "$tmp/c.vtu" 2>&1 | sed -n 's/.*: \([0-9]*\) of.*/\1/p')
{ [ "$n_all" -gt 0 ] && [ "$n_all" -lt "$n_any" ] && [ "$n_any" -le "$n_ovl" ]; } ||
  fail "thr_modes: expected 0 < all < any <= overlap, got $n_all $n_any $n_ovl"
[ "$(cells_of "$tmp/b.vtu")" = "$n_any" ] || fail "thr_modes: b.vtu does not hold $n_any cells"
# --all-points is the default.
expect_ok thr_all_points "wrote .*: $n_all of 8750" "$bin" threshold "$data/post.vtk" -a Pressure --between 0.8 1.0 --all-points -o "$tmp/a2.vtu"
# Complementary ranges of a cell array partition the cells (OriginalCellIds of a surface are integers).
expect_ok surf_post "wrote .*post.vtp: 1980 boundary faces of 3D cells, 0 other cells passed, 992 points" "$bin" surface "$data/post.vtk" -o "$tmp/post.vtp"
lo=$("$bin" threshold "$tmp/post.vtp" -a OriginalCellIds --below 4374.5 -o "$tmp/lo.vtu" 2>&1 | sed -n 's/.*: \([0-9]*\) of 1980 cells.*cell array.*/\1/p')
hi=$("$bin" threshold "$tmp/post.vtp" -a OriginalCellIds --above 4374.5 --ids -o "$tmp/hi.vtk" 2>&1 | sed -n 's/.*: \([0-9]*\) of 1980 cells.*cell array.*/\1/p')
{ [ -n "$lo" ] && [ -n "$hi" ] && [ "$lo" -gt 0 ] && [ "$hi" -gt 0 ] && [ $((lo + hi)) = 1980 ]; } ||
  fail "thr_partition: $lo + $hi cells, expected 1980 in two non-empty parts"
# The surface's cells run in increasing owner id, so the upper part is its last $hi cells, and
# --ids replaces the input's OriginalCellIds with the ids of those cells in post.vtp.
expect_ok thr_ids "'OriginalCellIds' +Int64 +x1 +\[$lo, 1979\]" "$bin" info "$tmp/hi.vtk"
# A vector: magnitude or a component; a PLOT3D grid with its solution.
expect_ok thr_magnitude "wrote .*: 288 of 7220 cells" "$bin" threshold "$data/office.binary.vtk" -a vectors --magnitude --above 0.1 -o "$tmp/fast.vtu"
expect_ok thr_component "wrote .* of 7220 cells" "$bin" threshold "$data/office.binary.vtk" -a vectors --component 2 --below 0 -o "$tmp/down.vtu"
expect_ok thr_q "wrote .* of 43008 cells.*point array 'Density'" "$bin" threshold "$data/combxyz.bin" --q "$data/combq.bin" -a Density --above 0.5 --any-point -o "$tmp/dense.vtu"
# The cells of an image stay voxels.
expect_ok thr_image "wrote" "$bin" threshold "$data/ironProt.vtk" -a scalars --between 200 255 --overlap -o "$tmp/high.vtu"
expect_ok thr_image_voxels "cells: [0-9]+ \([0-9]+ voxel\)" "$bin" info "$tmp/high.vtu"
# An empty result is written, with a warning naming the range of the data.
expect_ok thr_empty "warning: threshold: no cell has its point values in \[100, inf\]: 'Pressure' ranges 0.355.* \.\. 1.64" "$bin" threshold "$data/post.vtk" -a Pressure --above 100 -o "$tmp/empty.vtu"
[ "$(cells_of "$tmp/empty.vtu")" = 0 ] || fail "thr_empty: the file is not empty"

# ---- threshold: every option validated ----
expect_usage thr_no_range "a range is required: --between LO HI, --above LO or --below HI" "$bin" threshold "$data/post.vtk" -a Pressure -o "$tmp/x.vtu"
expect_usage thr_two_ranges "--above and --below exclude each other" "$bin" threshold "$data/post.vtk" -a Pressure --above 1 --below 2 -o "$tmp/x.vtu"
expect_usage thr_between_order "--between: LO 2 is above HI 1" "$bin" threshold "$data/post.vtk" -a Pressure --between 2 1 -o "$tmp/x.vtu"
expect_usage thr_between_nan "--between: .*nan" "$bin" threshold "$data/post.vtk" -a Pressure --between nan 1 -o "$tmp/x.vtu"
expect_usage thr_above_inf "--above: .*inf" "$bin" threshold "$data/post.vtk" -a Pressure --above inf -o "$tmp/x.vtu"
expect_usage thr_between_arity "--between" "$bin" threshold "$data/post.vtk" -a Pressure --between 1 -o "$tmp/x.vtu"
expect_usage thr_modes_exclusive "--all-points and --any-point exclude each other" "$bin" threshold "$data/post.vtk" -a Pressure --above 1 --all-points --any-point -o "$tmp/x.vtu"
expect_usage thr_component_negative "--component: must be an integer in \[0, 2147483647\], got -1" "$bin" threshold "$data/office.binary.vtk" -a vectors --component -1 --above 0 -o "$tmp/x.vtu"
expect_usage thr_component_magnitude "--component and --magnitude exclude each other" "$bin" threshold "$data/office.binary.vtk" -a vectors --component 1 --magnitude --above 0 -o "$tmp/x.vtu"
expect_usage thr_mode_cell_array "--any-point: applies to a point array; 'OriginalCellIds' is cell data" "$bin" threshold "$tmp/post.vtp" -a OriginalCellIds --above 1 --any-point -o "$tmp/x.vtu"
expect_usage thr_output "x.vtp: this subcommand writes .vtu .vtk" "$bin" threshold "$data/post.vtk" -a Pressure --above 1 -o "$tmp/x.vtp"
expect_usage thr_no_array "--array is required" "$bin" threshold "$data/post.vtk" --above 1 -o "$tmp/x.vtu"
expect_usage thr_empty_array "--array: an empty value is not allowed" "$bin" threshold "$data/post.vtk" -a '' --above 1 -o "$tmp/x.vtu"
expect_error thr_unknown_array "threshold: no array 'nosuch' \(point arrays: 'Pressure'; cell arrays: none\)" "$bin" threshold "$data/post.vtk" -a nosuch --above 1 -o "$tmp/x.vtu"
expect_error thr_component_range "threshold: component 3 of 'vectors', which has 3 components" "$bin" threshold "$data/office.binary.vtk" -a vectors --component 3 --above 0 -o "$tmp/x.vtu"
expect_error thr_bad_input "nosuch.vtk" "$bin" threshold "$tmp/nosuch.vtk" -a s --above 0 -o "$tmp/x.vtu"

# ---- surface ----
# post.vtk's boundary is a closed triangle mesh of genus 0: F = 2 V - 4 (Euler).
f=$(cells_of "$tmp/post.vtp") v=$(points_of "$tmp/post.vtp")
[ "$f" = $((2 * v - 4)) ] || fail "surf_post: $f triangles on $v points is not a closed genus-0 surface"
expect_ok surf_post_arrays "'Pressure'" "$bin" info "$tmp/post.vtp"
# The combustor (57 x 33 x 25 points): 2 (56*32 + 56*24 + 32*24) outer quads.
expect_ok surf_q "wrote .*: $((2 * (56 * 32 + 56 * 24 + 32 * 24))) boundary faces of 3D cells, 0 other cells passed, $((57 * 33 * 25 - 55 * 31 * 23)) points" "$bin" surface "$data/combxyz.bin" --q "$data/combq.bin" --point-ids -o "$tmp/comb.vtp"
expect_ok surf_q_arrays "'OriginalPointIds' +Int64" "$bin" info "$tmp/comb.vtp"
expect_ok surf_q_density "'Density'" "$bin" info "$tmp/comb.vtp"
# Shells pass through (blow.vtk: 928 triangles + 129 quads), written as PLY.
expect_ok surf_blow "0 boundary faces of 3D cells, 1057 other cells passed" "$bin" surface "$data/blow.vtk" -o "$tmp/blow.ply"
expect_ok surf_blow_back "cells: 1057 \(928 triangle, 129 quad\)" "$bin" info "$tmp/blow.ply"
# An image: 6 x 67^2 faces.
expect_ok surf_image "wrote .*: $((6 * 67 * 67)) boundary faces" "$bin" surface "$data/ironProt.vtk" --no-ids -o "$tmp/box.obj"
expect_usage surf_output "x.vtu: this subcommand writes .vtp .vtk .ply .obj .off" "$bin" surface "$data/post.vtk" -o "$tmp/x.vtu"
expect_error surf_bad_input "nosuch.vtk" "$bin" surface "$tmp/nosuch.vtk" -o "$tmp/x.vtp"

# ---- --q on every subcommand that reads any dataset ----
expect_usage q_not_plot3d_threshold "--q: a PLOT3D solution goes with a PLOT3D grid input" "$bin" threshold "$data/post.vtk" --q "$data/combq.bin" -a Pressure --above 0 -o "$tmp/x.vtu"
expect_usage q_not_plot3d_surface "--q: a PLOT3D solution goes with a PLOT3D grid input" "$bin" surface "$data/post.vtk" --q "$data/combq.bin" -o "$tmp/x.vtp"
expect_usage q_not_plot3d_fit "--q: a PLOT3D solution goes with a PLOT3D grid input" "$bin" fit "$data/bunny.ply" --q "$data/combq.bin" --primitive plane
expect_ok fit_q "plane" "$bin" fit "$data/combxyz.bin" --q "$data/combq.bin" --primitive plane --loss none
expect_error fit_q_missing "nosuch.bin" "$bin" fit "$data/combxyz.bin" --q "$tmp/nosuch.bin" --primitive plane

for sub in threshold surface; do expect_ok "help_$sub" "Examples:" "$bin" "$sub" --help; done

if [ $failures -ne 0 ]; then echo "$failures threshold/surface CLI test(s) failed"; exit 1; fi
echo "all threshold/surface CLI tests passed"
