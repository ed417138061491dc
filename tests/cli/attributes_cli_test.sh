#!/usr/bin/env bash
# End-to-end tests of isoforge elevation, warp and gradient: the arrays and points of the files
# they write, and every option's validation.
# Usage: attributes_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"

# ---- elevation ----
# office.binary.vtk: a structured grid, z from 0.01 to 2.5; with the default segment (the bounds'
# lowest to highest z) the elevation ranges exactly 0 .. 1, and with --range 10 20 10 .. 20.
expect_ok elev_default "point scalar 'Elevation' from 0 at .* to 1 at" "$bin" elevation "$data/office.binary.vtk" -o "$tmp/office.vts"
expect_ok elev_range_file "'Elevation' +Float32 x1 \[scalars\] +\[0, 1\]" "$bin" info "$tmp/office.vts"
expect_ok elev_given "from 10 at \(0, 0, 0.01\) to 20 at \(0, 0, 4.99\)" "$bin" elevation "$data/office.binary.vtk" --low 0 0 0.01 --high 0 0 4.99 --range 10 20 --name h -o "$tmp/h.vts"
expect_ok elev_given_file "'h' +Float32 x1 \[scalars\] +\[10, 1[45](\.[0-9]+)?\]" "$bin" info "$tmp/h.vts"
# Without clamping, a segment shorter than the data extrapolates beyond the range.
"$bin" -q elevation "$data/office.binary.vtk" --low 0 0 0.01 --high 0 0 1.255 --no-clamp -o "$tmp/x.vts" || fail "elev_noclamp: failed"
expect_ok elev_noclamp_file "'Elevation' +Float32 x1 \[scalars\] +\[[-0-9.e]+, 2\]" "$bin" info "$tmp/x.vts"
expect_usage elev_same "--low and --high must be different points" "$bin" elevation "$data/bunny.ply" --low 1 1 1 --high 1 1 1 -o "$tmp/b.vtp"
expect_usage elev_nan "--range: must be a finite number" "$bin" elevation "$data/bunny.ply" --range 0 nan -o "$tmp/b.vtp"
expect_usage elev_name "--name: an empty value is not allowed" "$bin" elevation "$data/bunny.ply" --name "" -o "$tmp/b.vtp"
# A new array never replaces one of the input's (the commands keep every input array).
expect_error elev_name_taken "office.binary.vtk already has an array 'scalars', which the new array would replace: give --name another name" "$bin" elevation "$data/office.binary.vtk" --name scalars -o "$tmp/b.vts"
expect_usage elev_flat "hello.vtk is flat in z: give --low and --high" "$bin" elevation "$data/hello.vtk" -o "$tmp/b.vtp"
expect_usage elev_format_obj "writes \.vtk \.vti \.vts \.vtp \.vtu, or \.ply for surfaces, not OBJ" "$bin" elevation "$data/bunny.ply" -o "$tmp/b.obj"
expect_usage elev_format "unknown file extension '.stl'" "$bin" elevation "$data/bunny.ply" -o "$tmp/b.stl"

# ---- warp ----
# blow.vtk moved by displacement5 (|v| up to 6.15): same cells, bounds grown along x and z.
expect_ok warp_blow "unstructured grid \(687 points\) moved by the vectors x 1" "$bin" warp "$data/blow.vtk" -a displacement5 -o "$tmp/blow.vtu"
expect_ok warp_blow_cells "cells: 1057 \(928 triangle, 129 quad\)" "$bin" info "$tmp/blow.vtu"
# Scale 0 leaves every point where it was: the converted and the warped files hold the same bounds.
"$bin" -q warp "$data/office.binary.vtk" --scale 0 -o "$tmp/same.vts" || fail "warp_zero: failed"
[ "$("$bin" info "$tmp/same.vts" | grep '^bounds')" = "$("$bin" info "$data/office.binary.vtk" | grep '^bounds')" ] ||
  fail "warp_zero: scale 0 moved the points"
# An image becomes a structured grid; by a scalar along +z the top rises by max(scalar) * scale.
"$bin" -q sample -f 'plane(normal=[0,0,1])' -b 0 1 0 1 0 1 -d 3 -o "$tmp/z.vti" || fail "warp_image: sample failed"
expect_ok warp_image "structured grid \(27 points\) moved along the direction x 2" "$bin" warp "$tmp/z.vti" --by scalar --direction 0 0 5 --scale 2 -o "$tmp/z.vts"
expect_ok warp_huge_direction "structured grid \(27 points\) moved along the direction x 2" "$bin" warp "$tmp/z.vti" --by scalar --direction 0 0 1e308 --scale 2 -o "$tmp/z_huge.vts"
diff <("$bin" info "$tmp/z.vts" | grep -v "^file") <("$bin" info "$tmp/z_huge.vts" | grep -v "^file") > /dev/null \
  || fail "warp_huge_direction: --direction 0 0 1e308 moved the points otherwise than 0 0 5"
expect_ok warp_image_bounds "bounds: x \[0, 1\]  y \[0, 1\]  z \[0, 3\]" "$bin" info "$tmp/z.vts"
expect_fail 1 warp_image_vti "structured grid is written as \.vts, not '\.vti'" "$bin" warp "$tmp/z.vti" --by scalar --direction 0 0 1 -o "$tmp/w.vti"
expect_usage warp_dir_vector "--direction: applies to --by scalar only" "$bin" warp "$data/blow.vtk" --direction 0 0 1 -o "$tmp/w.vtu"
expect_usage warp_disp_scalar "--displacement: applies to --by vector only" "$bin" warp "$tmp/z.vti" --by scalar --displacement -o "$tmp/w.vts"
expect_usage warp_dir_normals "exclude each other" "$bin" warp "$tmp/z.vti" --by scalar --direction 0 0 1 --normals N -o "$tmp/w.vts"
expect_usage warp_by "--by: .*not in" "$bin" warp "$data/blow.vtk" --by tensor -o "$tmp/w.vtu"
expect_usage warp_scale "--scale: must be a finite number" "$bin" warp "$data/blow.vtk" --scale inf -o "$tmp/w.vtu"
expect_fail 1 warp_no_array "warp: no point array 'nope' \(point arrays: 'displacement0'" "$bin" warp "$data/blow.vtk" -a nope -o "$tmp/w.vtu"
expect_fail 1 warp_no_normals "warp: the input has no active point normals" "$bin" warp "$tmp/z.vti" --by scalar -o "$tmp/w.vts"
expect_fail 1 warp_zero_dir "direction must be finite and not zero" "$bin" warp "$tmp/z.vti" --by scalar --direction 0 0 0 -o "$tmp/w.vts"
expect_fail 1 warp_disp_no_normals "displacement: the input has no active point normals" "$bin" warp "$data/blow.vtk" --displacement -o "$tmp/w.vtu"

# ---- gradient ----
# The gradient of F = z on a sampled image is (0, 0, 1) everywhere; a vector's gradient has 9
# components, and the curl and divergence come with it.
expect_ok grad_image "added point arrays 'Gradient'" "$bin" gradient "$tmp/z.vti" -o "$tmp/g.vti"
expect_ok grad_image_file "'Gradient' +Float64 x3 +\[0, 0\], \[0, 0\], \[1, 1\]" "$bin" info "$tmp/g.vti"
expect_error grad_name_taken "already has an array 'vectors', which the new array would replace" "$bin" gradient "$data/office.binary.vtk" -a scalars --name vectors -o "$tmp/o.vts"
expect_ok grad_office "added point arrays 'Gradient', 'Divergence', 'Vorticity'" "$bin" gradient "$data/office.binary.vtk" -a vectors --divergence --vorticity -o "$tmp/o.vts"
expect_ok grad_office_file "'Gradient' +Float64 x9" "$bin" info "$tmp/o.vts"
expect_ok grad_only_curl "added point arrays 'Vorticity'$" "$bin" gradient "$data/combxyz.bin" --q "$data/combq.bin" -a Velocity --vorticity --no-gradient -o "$tmp/c.vts"
expect_ok grad_post "added point arrays 'dP'" "$bin" gradient "$data/post.vtk" -a Pressure --name dP -o "$tmp/p.vtu"
expect_usage grad_nothing "--no-gradient: nothing left to compute" "$bin" gradient "$data/post.vtk" -a Pressure --no-gradient -o "$tmp/p.vtu"
expect_usage grad_name_no_grad "--name: the gradient is left out" "$bin" gradient "$data/office.binary.vtk" -a vectors --vorticity --no-gradient --name G -o "$tmp/p.vts"
expect_fail 1 grad_div_scalar "divergence needs a 3-component point array; 'Pressure' has 1" "$bin" gradient "$data/post.vtk" -a Pressure --divergence -o "$tmp/p.vtu"
expect_fail 1 grad_no_scalars "gradient: the input has no active point scalars" "$bin" gradient "$data/post.vtk" -o "$tmp/p.vtu"

# ---- calc ----
# speed = |vectors| has the same range as the vectors' magnitude in `info`.
expect_ok calc_speed "added point arrays 'speed' \(1 component\)" "$bin" calc "$data/office.binary.vtk" -e 'speed = mag(vectors)' -o "$tmp/speed.vts"
mag=$("$bin" info "$data/office.binary.vtk" | sed -n "s/.*'vectors'.*|v| \[\([^]]*\)\].*/\1/p")
expect_ok calc_speed_file "'speed' +Float64 x1 +\[$mag\]" "$bin" info "$tmp/speed.vts"
# Later expressions use earlier results; a vector minus itself is zero; Float32 on request.
expect_ok calc_chain "added point arrays 'd' \(3 components\), 'n' \(1 component\)" "$bin" calc "$data/blow.vtk" -e 'd = displacement5 - displacement5' -e 'n = mag(d) + 1' --float -o "$tmp/d.vtu"
expect_ok calc_chain_file "'n' +Float32 x1 +\[1, 1\]" "$bin" info "$tmp/d.vtu"
# Coordinates: z of office points is within [0.01, 2.5]... exactly its bounds.
expect_ok calc_coords "added point arrays 'z'" "$bin" calc "$data/office.binary.vtk" -e 'z=coordsZ' -o "$tmp/z.vts"
zb=$("$bin" info "$data/office.binary.vtk" | sed -n 's/.*z \[\([^]]*\)\].*/\1/p')
expect_ok calc_coords_file "'z' +Float64 x1 +\[$zb\]" "$bin" info "$tmp/z.vts"
# Over cells: post.vtk has no cell arrays; a constant works.
expect_ok calc_cells "added cell arrays 'one'" "$bin" calc "$data/post.vtk" --cells -e 'one = 1' -o "$tmp/c.vtu"
expect_ok calc_cells_file "'one' +Float64 x1 +\[1, 1\]" "$bin" info "$tmp/c.vtu"
expect_usage calc_no_eq "-e: 'speed': write NAME = EXPRESSION" "$bin" calc "$data/office.binary.vtk" -e speed -o "$tmp/cx.vts"
expect_usage calc_no_name "-e: '= 1': the result needs a name" "$bin" calc "$data/office.binary.vtk" -e '= 1' -o "$tmp/cx.vts"
expect_usage calc_empty "-e: 's = ': the expression is empty" "$bin" calc "$data/office.binary.vtk" -e 's = ' -o "$tmp/cx.vts"
expect_usage calc_no_e "--expression is required" "$bin" calc "$data/office.binary.vtk" -o "$tmp/cx.vts"
expect_fail 1 calc_unknown "calc: s = 'mag\(vector\)': calculator: column 5: no point array 'vector' \(point arrays: 'scalars', 'vectors'\)" "$bin" calc "$data/office.binary.vtk" -e 's = mag(vector)' -o "$tmp/cx.vts"
expect_fail 1 calc_kind "column 9: cannot add a scalar and a vector" "$bin" calc "$data/office.binary.vtk" -e 's = scalars + vectors' -o "$tmp/cx.vts"
expect_fail 1 calc_coords_cells "coords are point coordinates: not available over cells" "$bin" calc "$data/post.vtk" --cells -e 'x = coordsX' -o "$tmp/cx.vtu"
[ ! -e "$tmp/cx.vts" ] && [ ! -e "$tmp/cx.vtu" ] || fail "calc: a failed run left its output behind"

for sub in elevation warp gradient calc; do expect_ok "help_$sub" "Examples:" "$bin" "$sub" --help; done

if [ $failures -ne 0 ]; then echo "$failures elevation/warp/gradient/calc CLI test(s) failed"; exit 1; fi
echo "all elevation/warp/gradient/calc CLI tests passed"
