#!/usr/bin/env bash
# End-to-end tests of isoforge cut and isoforge clip: real files in, exit codes, messages and
# outputs (read back with info) checked.
# Usage: cut_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"

comb=("$data/combxyz.bin" --q "$data/combq.bin")
plane=(--plane 8.255 0 29.763 -0.287 0 0.9579)

# ---- cut ----
# Fig. 1.31: the combustor's density carried to the polygons of the plane through its centre.
expect_ok cut_fig131 "wrote .*comb.vtp: [0-9]+ polygons, 0 lines, 0 vertices" "$bin" cut "${comb[@]}" "${plane[@]}" -o "$tmp/comb.vtp"
expect_ok cut_fig131_back "'Density' +Float32 x1 \[scalars\]" "$bin" info "$tmp/comb.vtp"
# The same plane as an expression: the same cut (the general path); --triangulate: triangles only.
expect_ok cut_f "wrote" "$bin" cut "${comb[@]}" -f 'plane(origin=[8.255,0,29.763], normal=[-0.287,0,0.9579])' --triangulate -o "$tmp/comb_tri.vtk"
expect_ok cut_f_back "\([0-9]+ triangle\)" "$bin" info "$tmp/comb_tri.vtk"
# Fig. 1.33: contour lines on the skin, 46 planes y = 1.5 ... 136.5.
expect_ok cut_fig133 "0 polygons, [0-9]+ lines" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 --range 1.5 136.5 46 -o "$tmp/torso.vtp"
expect_ok cut_fig133_back "'CutValueIndex' +Int32 +x1 +\[0, 4[0-5]\]" "$bin" info "$tmp/torso.vtp"
# Several values with -v; lines of a surface; points of lines.
expect_ok cut_values "wrote" "$bin" cut "$data/ironProt.vtk" -f 'sphere(center=[34,34,34], r=20)' -v 0 -v 5 -o "$tmp/shells.ply"
expect_ok cut_lines_points "0 polygons, 0 lines, [1-9][0-9]* vertices" "$bin" cut "$tmp/torso.vtp" --plane 0 0 0 1 0 0 -o "$tmp/dots.vtp"
# Nothing there: a warning naming the range, still written.
expect_ok cut_empty "warning: cut: nothing at value 1000: 'F' ranges" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 -v 1000 -o "$tmp/none.vtp"
[ -f "$tmp/none.vtp" ] || fail "cut_empty: no output written"
# Usage errors: every option validated.
expect_usage cut_no_function "give the cut function" "$bin" cut "$data/Torso.vtp" -o "$tmp/x.vtp"
expect_usage cut_both "exclude each other" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 -f 'sphere()' -o "$tmp/x.vtp"
expect_usage cut_zero_normal "normal .* must not be zero" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 0 0 -o "$tmp/x.vtp"
expect_usage cut_nan_plane "--plane" "$bin" cut "$data/Torso.vtp" --plane 0 0 nan 0 0 1 -o "$tmp/x.vtp"
expect_usage cut_short_plane "--plane" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 1 -o "$tmp/x.vtp"
expect_usage cut_inf_value "--value" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 -v inf -o "$tmp/x.vtp"
expect_usage cut_v_and_range "exclude each other" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 -v 1 --range 0 1 3 -o "$tmp/x.vtp"
expect_usage cut_range_zero "--range" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 --range 0 1 0 -o "$tmp/x.vtp"
expect_usage cut_range_reversed "--range: .*first value is above the last" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 --range 5 1 3 -o "$tmp/x.vtp"
expect_usage cut_range_one "--range: .*one value needs" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 --range 1 2 1 -o "$tmp/x.vtp"
expect_usage cut_bad_function "--function" "$bin" cut "$data/Torso.vtp" -f 'sphere(r=-1)' -o "$tmp/x.vtp"
expect_usage cut_q_not_plot3d "--q" "$bin" cut "$data/Torso.vtp" --q "$data/combq.bin" --plane 0 0 0 0 1 0 -o "$tmp/x.vtp"
expect_usage cut_bad_output "x.vtu" "$bin" cut "$data/Torso.vtp" --plane 0 0 0 0 1 0 -o "$tmp/x.vtu"
expect_error cut_missing_input "nothing.vtk" "$bin" cut "$tmp/nothing.vtk" --plane 0 0 0 0 1 0 -o "$tmp/x.vtp"

# ---- clip ----
expect_ok clip_ball "wrote .*ball.vtu: [0-9]+ cells \([0-9]+ of 300763 input cells kept whole, [0-9]+ split\)" "$bin" clip "$data/ironProt.vtk" -f 'sphere(center=[34,34,34], r=20)' --inside-out -o "$tmp/ball.vtu"
expect_ok clip_ball_back "type: unstructured grid" "$bin" info "$tmp/ball.vtu"
expect_ok clip_comb "wrote" "$bin" clip "${comb[@]}" -f 'plane(origin=[8.255,0,29.763], normal=[-0.287,0,0.9579])' -v 0.5 -o "$tmp/half.vtk"
expect_ok clip_comb_back "'Density'" "$bin" info "$tmp/half.vtk"
expect_ok clip_poly "wrote .*top.ply" "$bin" clip "$data/bunny.ply" -f 'plane(origin=[0,0.1,0], normal=[0,1,0])' -o "$tmp/top.ply"
expect_ok clip_poly_back "type: polygonal data" "$bin" info "$tmp/top.ply"
expect_ok clip_empty "warning: clip: nothing" "$bin" clip "$data/bunny.ply" -f 'plane(origin=[0,10,0], normal=[0,1,0])' -o "$tmp/none.vtp"
expect_usage clip_no_function "function" "$bin" clip "$data/bunny.ply" -o "$tmp/x.vtp"
expect_usage clip_nan_value "--value" "$bin" clip "$data/bunny.ply" -f 'sphere()' -v nan -o "$tmp/x.vtp"
expect_usage clip_grid_to_vtp "x.vtp" "$bin" clip "$data/ironProt.vtk" -f 'sphere()' -o "$tmp/x.vtp"
expect_usage clip_bad_function "--function" "$bin" clip "$data/bunny.ply" -f 'plane(normal=[0,0,0])' -o "$tmp/x.vtp"
expect_usage clip_q_not_plot3d "--q" "$bin" clip "$data/bunny.ply" --q "$data/combq.bin" -f 'sphere()' -o "$tmp/x.vtp"

if [ $failures -ne 0 ]; then echo "$failures cut/clip CLI test(s) failed"; exit 1; fi
echo "all cut/clip CLI tests passed"
