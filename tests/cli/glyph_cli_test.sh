#!/usr/bin/env bash
# End-to-end tests of isoforge glyph, normals and tube: exact counts of real files' outputs,
# the options' effects, and every bad option refused as a usage error naming it.
# Usage: glyph_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"

# ---- normals ----
# fran_cut: one open surface of 2205 points and 4224 triangles; the file's triangles face into
# the head, so --flip reverses all of them; splitting at 30 degrees adds 277 points.
expect_ok normals_fran "2482 points \(277 added by splitting\), 4224 polygons" "$bin" normals "$data/fran_cut.vtk" --flip -o "$tmp/fran.vtp"
expect_ok normals_fran_stats "1 surfaces \(0 closed\), 4224 polygons reversed, 0 non-manifold edges, 0 inconsistent" "$bin" normals "$data/fran_cut.vtk" --flip -o "$tmp/fran.vtp"
expect_ok normals_fran_back "'Normals' +Float32 x3 \[normals\]" "$bin" info "$tmp/fran.vtp"
expect_ok normals_nosplit "2205 points \(0 added" "$bin" normals "$data/fran_cut.vtk" --no-split -o "$tmp/fran_smooth.vtp"
# The bunny is open (holes at the bottom) and already consistent: nothing reversed.
expect_ok normals_bunny "0 polygons reversed" "$bin" normals "$data/bunny.ply" --no-split -o "$tmp/bunny.ply"
expect_ok normals_cellonly "wrote" "$bin" normals "$data/Torso.vtp" --no-point-normals -o "$tmp/torso.vtp"
expect_ok normals_cellonly_back "cell data \(1 array\)" "$bin" info "$tmp/torso.vtp"
expect_usage normals_split_angle "--feature-angle: means nothing with --no-split" "$bin" normals "$data/fran_cut.vtk" --no-split -a 40 -o "$tmp/x.vtp"
expect_usage normals_angle "--feature-angle: must be a finite number in \[0, 180\]" "$bin" normals "$data/fran_cut.vtk" -a 190 -o "$tmp/x.vtp"
expect_usage normals_angle_nan "--feature-angle: must be a finite number" "$bin" normals "$data/fran_cut.vtk" -a nan -o "$tmp/x.vtp"
expect_usage normals_orient "--no-auto-orient: means nothing with --no-consistency" "$bin" normals "$data/fran_cut.vtk" --no-consistency --no-auto-orient -o "$tmp/x.vtp"
expect_usage normals_none "leave no normals" "$bin" normals "$data/fran_cut.vtk" --no-cell-normals --no-point-normals -o "$tmp/x.vtp"
expect_error normals_image "ironProt.vtk is image data; only polygonal data" "$bin" normals "$data/ironProt.vtk" -o "$tmp/x.vtp"
expect_error normals_plot3d "combxyz.bin is structured grid" "$bin" normals "$data/combxyz.bin" --q "$data/combq.bin" -o "$tmp/x.vtp"

# ---- glyph ----
# Fig. 1.30: 220 cones (13 points, 10 triangles each) along the normals of the face.
expect_ok glyph_fig130 "220 glyphs \(220 of 2482 points; cone, 13 points and 10 cells each\), 2860 points, 2200 cells" "$bin" glyph "$tmp/fran.vtp" --orient normals -f 0.01 --mask-random 220 --seed 1 -o "$tmp/spikes.vtp"
expect_ok glyph_fig130_back "cells: 2200 \(2200 triangle\)" "$bin" info "$tmp/spikes.vtp"
expect_ok glyph_fig130_ids "'InputPointIds' +Int64" "$bin" info "$tmp/spikes.vtp"
# The same seed gives the same file; another seed another one.
"$bin" glyph "$tmp/fran.vtp" --orient normals -f 0.01 --mask-random 220 --seed 1 -o "$tmp/spikes2.vtp" -q
cmp -s "$tmp/spikes.vtp" "$tmp/spikes2.vtp" || fail "glyph: --seed 1 twice gave different files"
"$bin" glyph "$tmp/fran.vtp" --orient normals -f 0.01 --mask-random 220 --seed 2 -o "$tmp/spikes3.vtp" -q
cmp -s "$tmp/spikes.vtp" "$tmp/spikes3.vtp" && fail "glyph: --seed 1 and --seed 2 gave the same file"
# One thread or two: the same bytes.
"$bin" --threads 1 glyph "$tmp/fran.vtp" --orient normals -f 0.01 --mask-random 220 --seed 1 -o "$tmp/spikes1t.vtp" -q
cmp -s "$tmp/spikes.vtp" "$tmp/spikes1t.vtp" || fail "glyph: 1 thread and 2 threads differ"
# PLOT3D with --q: Momentum is the active vector; every 20th of 47025 points is 2352 arrows of
# 37 points and 34 triangles (6 sides).
expect_ok glyph_arrows "2352 glyphs \(2352 of 47025 points; arrow, 37 points and 34 cells each\), 87024 points, 79968 cells" "$bin" glyph "$data/combxyz.bin" --q "$data/combq.bin" -s arrow --scale-by vector -f 0.004 --mask-every 20 -o "$tmp/arrows.vtp"
expect_ok glyph_arrows_orient "oriented by 'Momentum', sized by 'Momentum'" "$bin" glyph "$data/combxyz.bin" --q "$data/combq.bin" -s arrow --scale-by vector -f 0.004 --mask-every 20 -o "$tmp/arrows.vtp"
# The hedgehog: one line of 2 points per point.
expect_ok glyph_hedgehog "47025 glyphs .* 94050 points, 47025 cells" "$bin" glyph "$data/combxyz.bin" --q "$data/combq.bin" -s line --scale-by vector -f 0.002 -o "$tmp/hedgehog.vtp"
expect_ok glyph_hedgehog_back "cells: 47025 \(47025 line\)" "$bin" info "$tmp/hedgehog.vtp"
# --mask-max caps any mask; --resolution changes the shape.
expect_ok glyph_max "100 glyphs \(100 of 47025 points; cone, 17 points and 14 cells each\)" "$bin" glyph "$data/combxyz.bin" --q "$data/combq.bin" --mask-every 3 --mask-max 100 --resolution 8 -o "$tmp/max.vtp"
expect_ok glyph_cube "22 glyphs \(22 of 22 points; cube, 24 points and 12 cells each\), 528 points, 264 cells" "$bin" glyph "$data/hello.vtk" -s cube -f 0.2 -o "$tmp/cubes.ply"
expect_ok glyph_color "22 glyphs" "$bin" glyph "$data/hello.vtk" -s cube -f 0.2 --glyph-color index -o "$tmp/cubes.vtp"
expect_ok glyph_color_back "'GlyphColor' +Float32 x1 \[scalars\] +\[0, 21\]" "$bin" info "$tmp/cubes.vtp"
# A polydata file as the shape.
expect_ok glyph_file "22 glyphs \(22 of 22 points; .*fran_cut.vtk, 2205 points and 4224 cells each\), 48510 points, 92928 cells" "$bin" glyph "$data/hello.vtk" -s "$data/fran_cut.vtk" --orient none -o "$tmp/faces.vtp"
# Voxel mask on the bunny, clamped scalar sizes in [0, 0.004].
expect_ok glyph_voxel "sized by 'intensity' \(sizes 0 .. 0.004\)" "$bin" glyph "$data/bunny.ply" -s sphere --scalars intensity --scale-by scalar --clamp -f 0.004 --mask-voxel 0.01 -o "$tmp/dots.ply"
expect_usage glyph_masks "--mask-every and --mask-random exclude each other" "$bin" glyph "$data/fran_cut.vtk" --mask-every 2 --mask-random 3 -o "$tmp/x.vtp"
expect_usage glyph_masks2 "--mask-random and --mask-voxel exclude each other" "$bin" glyph "$data/fran_cut.vtk" --mask-random 2 --mask-voxel 3 -o "$tmp/x.vtp"
expect_usage glyph_seed "--seed: applies to --mask-random only" "$bin" glyph "$data/fran_cut.vtk" --seed 3 -o "$tmp/x.vtp"
expect_usage glyph_seed_neg "--seed: must be an integer >= 0" "$bin" glyph "$data/fran_cut.vtk" --mask-random 3 --seed -1 -o "$tmp/x.vtp"
expect_usage glyph_factor "--factor: must be a finite number, got 'nan'" "$bin" glyph "$data/fran_cut.vtk" -f nan -o "$tmp/x.vtp"
expect_usage glyph_factor_inf "--factor: must be a finite number, got 'inf'" "$bin" glyph "$data/fran_cut.vtk" -f inf -o "$tmp/x.vtp"
expect_usage glyph_every0 "--mask-every: must be an integer >= 1" "$bin" glyph "$data/fran_cut.vtk" --mask-every 0 -o "$tmp/x.vtp"
expect_usage glyph_random0 "--mask-random: must be an integer >= 1" "$bin" glyph "$data/fran_cut.vtk" --mask-random 0 -o "$tmp/x.vtp"
expect_usage glyph_voxel_neg "--mask-voxel: must be a finite number > 0" "$bin" glyph "$data/fran_cut.vtk" --mask-voxel -1 -o "$tmp/x.vtp"
expect_usage glyph_source "--source: 'nothing' is neither" "$bin" glyph "$data/fran_cut.vtk" -s nothing -o "$tmp/x.vtp"
expect_usage glyph_res "--resolution: must be an integer in \[3, 1024\]" "$bin" glyph "$data/fran_cut.vtk" --resolution 2 -o "$tmp/x.vtp"
expect_usage glyph_res_cube "--resolution: applies to the cone, arrow and sphere only" "$bin" glyph "$data/fran_cut.vtk" -s cube --resolution 8 -o "$tmp/x.vtp"
expect_usage glyph_range "--range: applies with --clamp only" "$bin" glyph "$data/fran_cut.vtk" --range 0 1 -o "$tmp/x.vtp"
expect_usage glyph_range_order "--range: MIN must be below MAX" "$bin" glyph "$data/bunny.ply" --scale-by scalar --clamp --range 1 0 -o "$tmp/x.vtp"
expect_usage glyph_clamp "--clamp: clamps the scale value" "$bin" glyph "$data/fran_cut.vtk" --clamp -o "$tmp/x.vtp"
expect_usage glyph_q "--q: a PLOT3D solution goes with a PLOT3D grid" "$bin" glyph "$data/fran_cut.vtk" --q "$data/combq.bin" -o "$tmp/x.vtp"
expect_usage glyph_format "writes .vtp .vtk .ply .obj .off" "$bin" glyph "$data/fran_cut.vtk" -o "$tmp/x.vti"
expect_error glyph_no_normals "orient by normals: the input has no active normals \(point arrays: 'textureCoords'\)" "$bin" glyph "$data/fran_cut.vtk" --orient normals -o "$tmp/x.vtp"
expect_error glyph_no_array "no point array 'nope'" "$bin" glyph "$data/bunny.ply" --scalars nope --scale-by scalar -o "$tmp/x.vtp"
expect_error glyph_source_image "ironProt.vtk is image data; the --source file must hold polygonal data" "$bin" glyph "$data/fran_cut.vtk" -s "$data/ironProt.vtk" -o "$tmp/x.vtp"
[ -e "$tmp/x.vtp" ] && fail "a refused command wrote its output"

# ---- tube ----
# hello.vtk: 15 two-point lines; 12 sides: 2 rings + 2 cap rings of 12 points, 24 + 2 x 10
# triangles each.
expect_ok tube_hello "15 tubes \(0 lines skipped.*\), 720 points, 660 triangles" "$bin" tube "$data/hello.vtk" -r 0.1 -o "$tmp/hello_tubes.vtp"
expect_ok tube_hello_back "'Normals' +Float32 x3 \[normals\]" "$bin" info "$tmp/hello_tubes.vtp"
expect_ok tube_nocap "90 points, 90 triangles" "$bin" tube "$data/hello.vtk" -r 0.05 -n 3 --no-cap -o "$tmp/prisms.ply"
# Isolines of the bunny's intensity as tubes whose radius follows it.
expect_ok tube_iso_lines "wrote" "$bin" contour "$data/bunny.ply" -a intensity --range 0.05 0.45 9 -o "$tmp/isolines.vtp"
expect_ok tube_iso "4060 tubes .* radius 0.0005 .. 0.002" "$bin" tube "$tmp/isolines.vtp" -r 0.0005 -n 8 --radius-by intensity --max-radius 0.002 -o "$tmp/isotubes.vtp"
expect_ok tube_iso_back "'intensity' +Float32 x1 +\[0.05, 0.45" "$bin" info "$tmp/isotubes.vtp"
expect_usage tube_radius0 "--radius: must be a finite number > 0, got '0'" "$bin" tube "$data/hello.vtk" -r 0 -o "$tmp/x.vtp"
expect_usage tube_radius_inf "--radius: must be a finite number > 0, got 'inf'" "$bin" tube "$data/hello.vtk" -r inf -o "$tmp/x.vtp"
expect_usage tube_radius_nan "--radius: must be a finite number > 0, got 'nan'" "$bin" tube "$data/hello.vtk" -r nan -o "$tmp/x.vtp"
expect_usage tube_radius_missing "--radius is required" "$bin" tube "$data/hello.vtk" -o "$tmp/x.vtp"
expect_usage tube_sides "--sides: must be an integer in \[3, 4096\], got 2" "$bin" tube "$data/hello.vtk" -r 1 -n 2 -o "$tmp/x.vtp"
expect_usage tube_max "--max-radius: applies with --radius-by only" "$bin" tube "$data/hello.vtk" -r 1 --max-radius 3 -o "$tmp/x.vtp"
expect_usage tube_range "--range: MIN must be below MAX" "$bin" tube "$data/hello.vtk" -r 1 --radius-by x --range 2 1 -o "$tmp/x.vtp"
expect_usage tube_q "--q: a PLOT3D solution goes with a PLOT3D grid" "$bin" tube "$data/hello.vtk" -r 1 --q "$data/combq.bin" -o "$tmp/x.vtp"
expect_error tube_nolines "fran_cut.vtk has no lines" "$bin" tube "$data/fran_cut.vtk" -r 1 -o "$tmp/x.vtp"
expect_error tube_array "radius by 'nope': no such point array" "$bin" tube "$data/hello.vtk" -r 1 --radius-by nope -o "$tmp/x.vtp"
expect_error tube_grid "combxyz.bin is structured grid; tubes go around the lines" "$bin" tube "$data/combxyz.bin" --q "$data/combq.bin" -r 1 -o "$tmp/x.vtp"
[ -e "$tmp/x.vtp" ] && fail "a refused command wrote its output"

# ---- tensor-glyph ----
# The office's velocity gradient (9 components) as a tensor: 8400 points, every 7th: 1200
# ellipsoids of 12 slices (120 triangles each).
"$bin" -q gradient "$data/office.binary.vtk" -a vectors --name strain -o "$tmp/grad.vts" || fail "tensor: gradient failed"
expect_ok tensor_every "wrote .*: 1200 ellipsoids \([0-9]+ flat or collapsed\), 144000 triangles" "$bin" tensor-glyph "$tmp/grad.vts" -a strain -s 0.2 --mask-every 7 -o "$tmp/ell.vtp"
expect_ok tensor_file "'TensorColor' +Float32 x1 \[scalars\]" "$bin" info "$tmp/ell.vtp"
expect_ok tensor_ids "'InputPointIds' +Int64 +x1 +\[0, 8393\]" "$bin" info "$tmp/ell.vtp"
expect_ok tensor_aniso "wrote .*: 10 ellipsoids .*, 80 triangles" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --mask-max 10 -r 4 --color-by anisotropy -o "$tmp/ell2.vtp"
expect_ok tensor_aniso_range "'TensorColor' +Float32 x1 .*\[0(\.[0-9]+)?, (0\.[0-9]+|1)\]" "$bin" info "$tmp/ell2.vtp"
expect_error tensor_none "tensor glyph: the input has no active point tensors" "$bin" tensor-glyph "$data/office.binary.vtk" -o "$tmp/x.vtp"
expect_error tensor_vectors "point array 'vectors' has 3 components: a tensor has 9" "$bin" tensor-glyph "$data/office.binary.vtk" -a vectors -o "$tmp/x.vtp"
expect_usage tensor_scale "--scale: .*" "$bin" tensor-glyph "$tmp/grad.vts" -a strain -s 0 -o "$tmp/x.vtp"
expect_usage tensor_res "--resolution: .*" "$bin" tensor-glyph "$tmp/grad.vts" -a strain -r 2 -o "$tmp/x.vtp"
expect_usage tensor_color "--color-by: .*not in" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --color-by red -o "$tmp/x.vtp"
expect_usage tensor_every "--mask-every: .*" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --mask-every 0 -o "$tmp/x.vtp"
# Superquadrics: the same counts as ellipsoids; --gamma only with them.
expect_ok tensor_sq "wrote .*: 10 superquadrics .*, 80 triangles" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --mask-max 10 -r 4 --shape superquadric --gamma 2 -o "$tmp/sq.vtp"
expect_usage tensor_gamma_shape "--gamma: applies to --shape superquadric" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --gamma 2 -o "$tmp/x.vtp"
expect_usage tensor_gamma "--gamma: .*" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --shape superquadric --gamma 0 -o "$tmp/x.vtp"
expect_usage tensor_gamma_nan "--gamma: .*" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --shape superquadric --gamma nan -o "$tmp/x.vtp"
expect_usage tensor_shape "--shape: .*not in" "$bin" tensor-glyph "$tmp/grad.vts" -a strain --shape cube -o "$tmp/x.vtp"
[ -e "$tmp/x.vtp" ] && fail "a refused tensor-glyph wrote its output"

# ---- point-load ----
# 5^3 samples of [-1, 1]^3: the load point (0, 0, 1) is one of them (its glyph collapses, as
# do the 24 others on the free surface, where the stress is plane).
expect_ok load_grid "wrote .*: 125 points .*effective stress up to .*the load point itself is a sample" "$bin" point-load --dims 5 -o "$tmp/load.vti"
expect_ok load_arrays "'stress' +Float32 x9 \[tensors\]" "$bin" info "$tmp/load.vti"
expect_ok load_mask "'vtkValidPointMask' +UInt8 +x1 +\[0, 1\]" "$bin" info "$tmp/load.vti"
expect_ok load_box "wrote .*: 336 points in [0-9.]+ s$" "$bin" point-load --dims 6 7 8 --bounds -10 10 -10 10 -20 0 --load 100 --poisson 0.5 --no-effective-stress -o "$tmp/load2.vtk"
expect_ok load_box_dims "dimensions: 6 x 7 x 8" "$bin" info "$tmp/load2.vtk"
expect_ok load_box_arrays "point data \(2 arrays\)" "$bin" info "$tmp/load2.vtk"
expect_ok load_glyphs "wrote .*: 125 ellipsoids \(25 flat or collapsed\)" "$bin" tensor-glyph "$tmp/load.vti" -s 0.2 --max-size 0.3 -r 4 -o "$tmp/load_ell.vtp"
expect_usage load_poisson "--poisson: .*" "$bin" point-load --poisson 0.6 -o "$tmp/x.vti"
expect_usage load_negative "--load: .*" "$bin" point-load --load -1 -o "$tmp/x.vti"
expect_usage load_inf "--load: .*" "$bin" point-load --load inf -o "$tmp/x.vti"
expect_error load_float32 "stress at sample \(0, 0, 0\) = \(-1, -1, -1\) exceeds the Float32 range.*lower the load \(1e\+308\)" "$bin" point-load --dims 5 --load 1e308 -o "$tmp/x.vti"
expect_usage load_dims "--dims: .*" "$bin" point-load --dims 1 -o "$tmp/x.vti"
expect_usage load_flat "--bounds: z 0 .. 0: the box must have a positive extent" "$bin" point-load --bounds -1 1 -1 1 0 0 -o "$tmp/x.vti"
expect_usage load_format "vtp" "$bin" point-load -o "$tmp/x.vtp"
[ -e "$tmp/x.vti" ] && fail "a refused point-load wrote its output"

if [ $failures -ne 0 ]; then echo "$failures failure(s)"; exit 1; fi
echo "all glyph/normals/tube CLI tests passed"
