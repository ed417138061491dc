#!/usr/bin/env bash
# End-to-end tests of isoforge probe and isoforge subsample: outputs read back with info, exit
# codes and one-line messages naming the option for every bad argument.
# Usage: probe_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"
comb=("$data/combxyz.bin" --q "$data/combq.bin")

# ---- probe: the four kinds of probe, outputs read back ----
# A 50 x 50 plane inside the combustor (Fig. 1.35): every point found, 49 x 49 quads.
expect_ok plane "2500 points\), 2500 found" "$bin" probe "${comb[@]}" \
  --plane 3.7 -2.5 25.87 3.7 2.5 25.87 3.7 -2.5 30.87 50 50 -o "$tmp/plane.vtp"
expect_ok plane_back "cells: 2401 \(2401 quad\)" "$bin" info "$tmp/plane.vtp"
expect_ok plane_arrays "'Density' .*\[0\.[0-9]+, 0\.[0-9]+\]" "$bin" info "$tmp/plane.vtp"
expect_ok plane_mask "'vtkValidPointMask' +UInt8 +x1 +\[1, 1\]" "$bin" info "$tmp/plane.vtp"
# A line from outside to outside: some points outside get NaN and mask 0.
expect_ok line "200 points\), [0-9]+ found" "$bin" probe "${comb[@]}" --line -5 0 30 20 0 30 200 -o "$tmp/line.vtp"
expect_ok line_mask "'vtkValidPointMask' +UInt8 +x1 +\[0, 1\]" "$bin" info "$tmp/line.vtp"
# A volume over the input's bounds is image data of the given dims; --nil and --mask-name.
expect_ok volume "image data \(1000 points\)" "$bin" probe "${comb[@]}" --volume 10 --nil -1 --mask-name inside -o "$tmp/vol.vti"
expect_ok volume_back "dimensions: 10 x 10 x 10" "$bin" info "$tmp/vol.vti"
expect_ok volume_nil "'Density' +Float32 x1 \[scalars\] +\[-1, 0\.[0-9]+\]" "$bin" info "$tmp/vol.vti"
expect_ok volume_mask "'inside' +UInt8" "$bin" info "$tmp/vol.vti"
# --with keeps the probe's type: the grid at its own points is found everywhere.
expect_ok with "structured grid \(47025 points\), 47025 found" "$bin" probe "${comb[@]}" --with "$data/combxyz.bin" -o "$tmp/self.vts"
# An unstructured tetra mesh (post.vtk) probed by a plane.
expect_ok tets "6400 points\), [0-9]+ found" "$bin" probe "$data/post.vtk" --plane -2.8 -2.8 0.5 2.8 -2.8 0.5 -2.8 2.8 0.5 80 80 -o "$tmp/post.vtk"
expect_ok tets_back "'Pressure'" "$bin" info "$tmp/post.vtk"

# ---- probe: usage errors name the option ----
expect_usage no_probe "one of --with, --line, --plane, --volume" "$bin" probe "${comb[@]}" -o "$tmp/x.vtp"
expect_usage two_probes "exclude each other" "$bin" probe "${comb[@]}" --volume 4 --line 0 0 0 1 1 1 3 -o "$tmp/x.vtp"
expect_usage line_n0 "--line: N must be an integer >= 1, got '0'" "$bin" probe "${comb[@]}" --line 0 0 0 1 1 1 0 -o "$tmp/x.vtp"
expect_usage line_zero_length "--line: P0 equals P1" "$bin" probe "${comb[@]}" --line 1 1 1 1 1 1 5 -o "$tmp/x.vtp"
expect_usage line_nan "--line: P1 must be a finite number, got 'nan'" "$bin" probe "${comb[@]}" --line 0 0 0 nan 1 1 5 -o "$tmp/x.vtp"
expect_usage line_inf "--line: P0 must be a finite number, got 'inf'" "$bin" probe "${comb[@]}" --line inf 0 0 1 1 1 5 -o "$tmp/x.vtp"
expect_usage line_count "--line" "$bin" probe "${comb[@]}" --line 0 0 0 1 1 1 -o "$tmp/x.vtp"
expect_usage plane_degenerate "--plane: degenerate plane" "$bin" probe "${comb[@]}" --plane 0 0 0 1 0 0 2 0 0 5 5 -o "$tmp/x.vtp"
expect_usage plane_nu "--plane: NU must be an integer >= 2, got '1'" "$bin" probe "${comb[@]}" --plane 0 0 0 1 0 0 0 1 0 1 5 -o "$tmp/x.vtp"
expect_usage volume_0 "--volume: must be an integer >= 1" "$bin" probe "${comb[@]}" --volume 0 -o "$tmp/x.vti"
expect_usage volume_vtp "-o: a volume probe is image data" "$bin" probe "${comb[@]}" --volume 4 -o "$tmp/x.vtp"
expect_usage plane_vti "-o: a line or plane probe is polygonal data" "$bin" probe "${comb[@]}" --line 0 0 0 1 1 1 4 -o "$tmp/x.vti"
expect_usage with_type "-o: the probe .* is structured grid" "$bin" probe "${comb[@]}" --with "$data/combxyz.bin" -o "$tmp/x.vtu"
expect_usage tolerance "--tolerance: must be a finite number >= 0" "$bin" probe "${comb[@]}" --volume 4 --tolerance -1 -o "$tmp/x.vti"
expect_usage nil "--nil: must be a finite number" "$bin" probe "${comb[@]}" --volume 4 --nil inf -o "$tmp/x.vti"
expect_usage mask "--mask-name: an empty value is not allowed" "$bin" probe "${comb[@]}" --volume 4 --mask-name "" -o "$tmp/x.vti"
expect_usage q_not_plot3d "--q" "$bin" probe "$data/post.vtk" --q "$data/combq.bin" --volume 4 -o "$tmp/x.vti"
expect_error missing_with "nothing.vtk" "$bin" probe "${comb[@]}" --with "$tmp/nothing.vtk" -o "$tmp/x.vtk"
[ -e "$tmp/x.vtp" ] || [ -e "$tmp/x.vti" ] && fail "a failed probe wrote an output"

# ---- subsample ----
expect_ok sub "29 x 17 x 13 points \(6409\) of 57 x 33 x 25" "$bin" subsample "${comb[@]}" --rate 2 2 2 -o "$tmp/half.vts"
expect_ok sub_back "dimensions: 29 x 17 x 13" "$bin" info "$tmp/half.vts"
expect_ok sub_arrays "'Density' +Float32 x1 \[scalars\]" "$bin" info "$tmp/half.vts"
expect_ok sub_voi "15 x 33 x 1 points" "$bin" subsample "${comb[@]}" --rate 4 1 1 --voi 0 56 0 32 12 12 --include-boundary -o "$tmp/k12.vts"
expect_ok sub_image "23 x 23 x 23 points" "$bin" subsample "$data/ironProt.vtk" --rate 3 -o "$tmp/iron.vti"
expect_ok sub_image_back "spacing: 3 3 3" "$bin" info "$tmp/iron.vti"
expect_usage sub_rate0 "--rate: must be an integer >= 1" "$bin" subsample "${comb[@]}" --rate 0 1 1 -o "$tmp/y.vts"
expect_usage sub_voi_inverted "--voi: j0 5 > j1 2: the range is inverted" "$bin" subsample "${comb[@]}" --rate 1 --voi 0 1 5 2 0 1 -o "$tmp/y.vts"
expect_usage sub_voi_range "--voi: k1 25 is out of range" "$bin" subsample "${comb[@]}" --rate 1 --voi 0 1 0 1 0 25 -o "$tmp/y.vts"
expect_usage sub_voi_negative "--voi: must be an integer >= 0" "$bin" subsample "${comb[@]}" --rate 1 --voi -1 1 0 1 0 2 -o "$tmp/y.vts"
expect_usage sub_voi_count "--voi" "$bin" subsample "${comb[@]}" --rate 1 --voi 0 1 0 1 -o "$tmp/y.vts"
expect_usage sub_boundary_image "--include-boundary: applies to structured grids only" "$bin" subsample "$data/ironProt.vtk" --rate 3 --include-boundary -o "$tmp/y.vti"
expect_usage sub_format "-o: .* write .vts or .vtk" "$bin" subsample "${comb[@]}" --rate 2 -o "$tmp/y.vti"
expect_usage sub_vtp "-o: subsample writes" "$bin" subsample "${comb[@]}" --rate 2 -o "$tmp/y.vtp"
expect_error sub_unstructured "only image data and structured grids" "$bin" subsample "$data/post.vtk" --rate 2 -o "$tmp/y.vtk"
[ -e "$tmp/y.vts" ] || [ -e "$tmp/y.vtk" ] && fail "a failed subsample wrote an output"

if [ "$failures" -ne 0 ]; then echo "$failures failure(s)"; exit 1; fi
echo "all probe/subsample CLI tests passed"
