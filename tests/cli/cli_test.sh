#!/usr/bin/env bash
# End-to-end tests of the isoforge command. Usage: cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0

# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"

# ---- info on every real file: type and counts ----
expect_ok info_fran "points: 2205" "$bin" info "$data/fran_cut.vtk"
expect_ok info_fran_cells "cells: 4224 \(4224 triangle\)" "$bin" info "$data/fran_cut.vtk"
expect_ok info_hello "cells: 15 \(15 line\)" "$bin" info "$data/hello.vtk"
expect_ok info_torso "cells: 12448 \(1134 triangle, 11314 quad\)" "$bin" info "$data/Torso.vtp"
expect_ok info_bunny "points: 35947" "$bin" info "$data/bunny.ply"
expect_ok info_bunny_arrays "'confidence'" "$bin" info "$data/bunny.ply"
expect_ok info_iron "dimensions: 68 x 68 x 68" "$bin" info "$data/ironProt.vtk"
expect_ok info_office "type: structured grid" "$bin" info "$data/office.binary.vtk"
expect_ok info_post "cells: 8750 \(8750 tetra\)" "$bin" info "$data/post.vtk"
expect_ok info_blow "cells: 1057 \(928 triangle, 129 quad\)" "$bin" info "$data/blow.vtk"
expect_ok info_headsq "dimensions: 64 x 64 x 93" "$bin" info "$data/headsq/quarter.nhdr"
expect_ok info_headmr "dimensions: 48 x 62 x 42" "$bin" info "$data/HeadMRVolume.mhd"
expect_ok info_comb "dimensions: 57 x 33 x 25" "$bin" info "$data/combxyz.bin" --q "$data/combq.bin"
expect_ok info_comb_density "'Density'.*\[0\.19" "$bin" info "$data/combxyz.bin" --q "$data/combq.bin"

# info costs O(header) on structured data: a header claiming 10^15 points without data is
# described at once (the cell histogram visited every cell: it never returned), and a header
# whose data the file cannot hold is rejected as the reader rejects it. (timeout: a hang guard.)
printf '# vtk DataFile Version 3.0\nhuge\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 100000 100000 100000\n' > "$tmp/huge.vtk"
expect_ok info_huge_header "cells: 999970000299999 \(999970000299999 voxel\)" timeout 120 "$bin" info "$tmp/huge.vtk"
printf '<VTKFile type="ImageData" version="1.0"><ImageData WholeExtent="0 99999 0 99999 0 99999" Origin="0 0 0" Spacing="1 1 1"><Piece Extent="0 99999 0 99999 0 99999"></Piece></ImageData></VTKFile>\n' > "$tmp/huge.vti"
expect_ok info_huge_vti "points: 1000000000000000" timeout 120 "$bin" info "$tmp/huge.vti"
printf '# vtk DataFile Version 3.0\nhuge\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 100000 100000 100000\nPOINT_DATA 1000000000000000\nSCALARS s float\nLOOKUP_TABLE default\n1 2 3\n' > "$tmp/huge_data.vtk"
expect_error info_huge_data "huge_data.vtk:8: .*exceeds what the remaining 7 bytes of the file can hold" timeout 120 "$bin" info "$tmp/huge_data.vtk"

# ---- convert: every target format, then read back with info ----
expect_ok conv_vtp "wrote .*fran.vtp" "$bin" convert "$data/fran_cut.vtk" "$tmp/fran.vtp"
expect_ok conv_vtp_back "points: 2205" "$bin" info "$tmp/fran.vtp"
expect_ok conv_xml_auto "wrote .*post.vtu" "$bin" convert "$data/post.vtk" "$tmp/post" --vtk-xml
expect_ok conv_vtu_back "cells: 8750" "$bin" info "$tmp/post.vtu"
expect_ok conv_vts "wrote" "$bin" convert "$data/combxyz.bin" --q "$data/combq.bin" "$tmp/comb.vts"
expect_ok conv_vts_back "'Momentum'" "$bin" info "$tmp/comb.vts"
expect_ok conv_legacy51 "wrote" "$bin" convert "$data/bunny.ply" "$tmp/bunny.vtk" --ascii --legacy-version 5.1
expect_ok conv_legacy51_back "cells: 69451" "$bin" info "$tmp/bunny.vtk"
expect_ok conv_ply "wrote" "$bin" convert "$data/Torso.vtp" "$tmp/torso.ply"
expect_ok conv_ply_back "points: 12015" "$bin" info "$tmp/torso.ply"
expect_ok conv_off "wrote" "$bin" convert "$data/fran_cut.vtk" "$tmp/fran.off"
expect_ok conv_off_back "cells: 4224" "$bin" info "$tmp/fran.off"
expect_ok conv_obj "wrote" "$bin" convert "$data/fran_cut.vtk" "$tmp/fran.obj"
expect_ok conv_vdb "wrote" "$bin" convert "$data/HeadMRVolume.mhd" "$tmp/head.vdb"
expect_ok conv_vdb_info "grids: 1" "$bin" info "$tmp/head.vdb"
expect_ok conv_vdb_back "wrote" "$bin" convert "$tmp/head.vdb" "$tmp/head_back.vti"
expect_ok quiet_is_silent "^$" "$bin" --quiet convert "$data/hello.vtk" "$tmp/hello.vtp"

# ---- errors: one line, non-zero exit, names the file and the problem ----
expect_error missing_file "nosuch.vtk" "$bin" info "$tmp/nosuch.vtk"
expect_usage unknown_ext "unknown file extension '.xyzw'" "$bin" info "$data/../README.md.xyzw"
expect_error wrong_target "holds polygonal data only" "$bin" convert "$data/post.vtk" "$tmp/post.ply"
expect_error unwritable "cannot create a file in" "$bin" convert "$data/hello.vtk" "$tmp/no/such/dir/h.vtp"
printf '# vtk DataFile Version 3.0\ntruncated\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n0 0 0\n' > "$tmp/trunc.vtk"
expect_error truncated "trunc.vtk" "$bin" info "$tmp/trunc.vtk"

# Messages say what is wrong: file content is quoted whole with unprintable bytes escaped (a NUL
# cut the message short), a PLY without x says so (not "face 0 has 0 vertices").
printf 'NRRD0004\ntype: fl\0oat\ndimension: 1\nsizes: 1\nencoding: raw\n\nx' > "$tmp/nul.nrrd"
expect_error nul_in_header "nul.nrrd:2: unknown type 'fl\\\\x00oat'" "$bin" info "$tmp/nul.nrrd"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' > "$tmp/nox.ply"
expect_error ply_without_x "nox.ply:3: the vertex element lacks the 'x' property \\(it has y, z\\)" "$bin" info "$tmp/nox.ply"

# A failed conversion must not clobber an existing good output file.
cp "$tmp/fran.vtp" "$tmp/keep.vtp"
"$bin" convert "$tmp/trunc.vtk" "$tmp/keep.vtp" >/dev/null 2>&1 && fail "convert of a truncated file succeeded"
cmp -s "$tmp/fran.vtp" "$tmp/keep.vtp" || fail "a failed convert changed the existing output file"
ls -A "$tmp" | grep -q '\.tmp\.' && fail "temporary files left behind: $(ls -A "$tmp")"

# ---- killed while writing: SIGINT/SIGTERM leave neither a temporary file nor an output, and the
# exit status is the signal's (the temporary .NAME.tmp.* stayed behind) ----
# interrupted SIGNAL NUMBER: a big dense sample is signalled once its output is being written.
interrupted() {
  local sig=$1 num=$2 dir="$tmp/killed_$1"
  mkdir -p "$dir"
  set -m  # job control: the background job is not made to ignore SIGINT
  "$bin" --quiet sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 400 -o "$dir/out.vti" &
  local pid=$!
  set +m
  local writing=0
  for _ in $(seq 12000); do  # wait (up to 2 min) until the temporary file exists
    if ls -A "$dir" | grep -q '\.tmp\.'; then writing=1; break; fi
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.01
  done
  if [ $writing -eq 0 ]; then fail "killed_$sig: the temporary file never appeared"; wait "$pid"; return; fi
  kill "-$sig" "$pid"
  wait "$pid"
  local rc=$?
  [ $rc -eq $((128 + num)) ] || fail "killed_$sig: exit status $rc, expected $((128 + num))"
  [ -z "$(ls -A "$dir")" ] || fail "killed_$sig: left behind: $(ls -A "$dir")"
}
interrupted INT 2
interrupted TERM 15

# ---- outputs: replacing keeps the file's mode; a symbolic link is written through ----
"$bin" -q convert "$data/hello.vtk" "$tmp/private.vtp" && chmod 600 "$tmp/private.vtp"
"$bin" -q convert "$data/hello.vtk" "$tmp/private.vtp"
[ "$(stat -c %a "$tmp/private.vtp")" = 600 ] || fail "replacing a 0600 file changed its mode to $(stat -c %a "$tmp/private.vtp")"
mkdir -p "$tmp/real" && ln -sf real/linked.vtp "$tmp/link.vtp"
expect_ok write_through_link "wrote" "$bin" convert "$data/hello.vtk" "$tmp/link.vtp"
[ -L "$tmp/link.vtp" ] || fail "writing to a symbolic link replaced the link by a file"
expect_ok write_through_link_info "cells: 15" "$bin" info "$tmp/real/linked.vtp"
expect_error unwritable_before_work "cannot create a file in" "$bin" sample -f 'sphere()' -b 0 1 0 1 0 1 -d 100000 -o "$tmp/no/such/dir/x.vti"

# ---- sample, select, contour ----
expect_ok sample_vti "wrote .*16 x 16 x 16 samples" "$bin" sample -f 'sphere(r=0.8)' -b -1 1 -1 1 -1 1 -d 16 -o "$tmp/sphere.vti"
expect_ok sample_vti_info "dimensions: 16 x 16 x 16" "$bin" info "$tmp/sphere.vti"
expect_ok sample_vdb "active" "$bin" sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 128 -o "$tmp/ice.vdb"
expect_ok sample_vdb_info "class level set" "$bin" info "$tmp/ice.vdb"
expect_ok contour_dense "wrote .*sphere.vtp" "$bin" contour "$tmp/sphere.vti" -v 0 --normals gradient -o "$tmp/sphere.vtp"
expect_ok contour_dense_info "'Normals'" "$bin" info "$tmp/sphere.vtp"
expect_ok contour_sparse "wrote .*ice.ply" "$bin" contour "$tmp/ice.vdb" -v 0 -o "$tmp/ice.ply"
# OpenVDB and Ceres are loaded by the commands that need them only (a shared build loads
# libisoforge_vdb, the commands' module and libisoforge_fit on demand; a static build links them,
# so there is nothing to check).
if LD_TRACE_LOADED_OBJECTS=1 "$bin" 2>&1 | grep -q "libisoforge\.so"; then
  LD_TRACE_LOADED_OBJECTS=1 "$bin" 2>&1 | grep -Eq "libopenvdb|libglog|libcholmod" &&
    fail "the isoforge program links libopenvdb or Ceres' libraries"
  # loads PATTERN CMD...: how many distinct libraries matching PATTERN CMD loads.
  loads() {
    local pattern=$1; shift
    LD_DEBUG=files "$@" 2>&1 | grep "generating link map" | grep -oE "$pattern" | sort -u | wc -l
  }
  vdb_loads() { loads "(libopenvdb|libisoforge_vdb|isoforge-vdb-commands)" "$@"; }
  n=$(vdb_loads "$bin" contour "$tmp/sphere.vti" -v 0 -o "$tmp/lazy.vtp")
  [ "$n" = 0 ] || fail "contour of a .vti loaded $n OpenVDB libraries"
  n=$(vdb_loads "$bin" info "$tmp/sphere.vti")
  [ "$n" = 0 ] || fail "info of a .vti loaded $n OpenVDB libraries"
  n=$(vdb_loads "$bin" contour "$tmp/ice.vdb" -v 0 -o "$tmp/lazy.vtp")
  [ "$n" = 3 ] || fail "contour of a .vdb loaded $n of libopenvdb, libisoforge_vdb and the module"
  n=$(vdb_loads "$bin" convert "$tmp/ice.vdb" "$tmp/lazy.vti")
  [ "$n" = 2 ] || fail "convert of a .vdb loaded $n of libopenvdb and libisoforge_vdb"
fi
expect_ok contour_range "IsovalueIndex.*\[0, 2\]" bash -c "'$bin' contour '$tmp/sphere.vti' --range -0.2 0.2 3 -o '$tmp/shells.vtp' && '$bin' info '$tmp/shells.vtp'"
"$bin" sample -f 'union(sphere(center=[-0.5,0,0], r=0.3), sphere(center=[0.5,0,0], r=0.2))' -b -1 1 -1 1 -1 1 -d 32 -o "$tmp/two.vti" >/dev/null 2>&1
expect_ok contour_largest "kept from 2 connected pieces" "$bin" contour "$tmp/two.vti" -v 0 --largest -o "$tmp/one.vtp"
expect_ok select_cells "wrote .*of 3375 cells" "$bin" select "$tmp/sphere.vti" -f 'sphere(r=0.5)' -o "$tmp/inside.vtu"
expect_ok select_ids "'OriginalCellIds'" "$bin" info "$tmp/inside.vtu"
expect_ok select_shrink "wrote" "$bin" select "$tmp/sphere.vti" -f 'sphere(r=0.5)' --shrink 0.5 -o "$tmp/shrunk.vtu"
expect_usage bad_function "column 11: expected '\)'" "$bin" sample -f 'sphere(r=1' -b 0 1 0 1 0 1 -o "$tmp/x.vti"
expect_usage bad_parameter "'r' \(radius\) is negative" "$bin" sample -f 'sphere(r=-1)' -b 0 1 0 1 0 1 -o "$tmp/x.vti"
expect_usage no_values "at least one value" "$bin" contour "$tmp/sphere.vti" -o "$tmp/x.vtp"
expect_error missing_array "no point array named 'nope'" "$bin" contour "$tmp/sphere.vti" -v 0 -a nope -o "$tmp/x.vtp"
expect_usage contour_to_vti "holds|not" "$bin" contour "$tmp/sphere.vti" -v 0 -o "$tmp/x.vti"
expect_error contour_lines_triangle_normals "contour: normals from triangles need a surface" "$bin" contour "$data/bunny.ply" -a intensity -v 0.5 --normals triangles -o "$tmp/x.vtp"
# An empty value (an unset shell variable) is never "not given".
expect_usage empty_array "--array: an empty value is not allowed" "$bin" contour "$tmp/sphere.vti" -v 0 -a '' -o "$tmp/x.vtp"
expect_usage empty_q "--q: an empty value is not allowed" "$bin" info "$data/combxyz.bin" --q ''
expect_usage empty_file "file: an empty value is not allowed" "$bin" info ''
# A flag given both ways, and options the other options make unused, are errors.
expect_usage flag_both_ways "--cap: given both ways \(--cap, --no-cap\)" "$bin" tube "$data/hello.vtk" -r 0.1 --cap --no-cap -o "$tmp/x.vtp"
expect_usage decimate_free_preserve "given both ways" "$bin" decimate "$data/bunny.ply" -r 0.5 --free-boundary --preserve-boundary -o "$tmp/x.ply"
expect_usage decimate_volume_method "--preserve-volume: applies to --method quadric only" "$bin" decimate "$data/bunny.ply" -r 0.5 -m cell-collapse --free-volume -o "$tmp/x.ply"
expect_usage decimate_volume_both "given both ways" "$bin" decimate "$data/bunny.ply" -r 0.5 --free-volume --preserve-volume -o "$tmp/x.ply"
expect_usage decimate_attr_weight "--attribute-weight: applies to --method quadric only" "$bin" decimate "$data/bunny.ply" -r 0.5 -m vertex-removal --attribute-weight 1 -o "$tmp/x.ply"
expect_usage decimate_boundary_weight "--boundary-weight: .*--feature-angle" "$bin" decimate "$data/bunny.ply" -r 0.5 --free-boundary --boundary-weight 5 -o "$tmp/x.ply"
expect_usage glyph_unused_vectors "--vectors: unused" "$bin" glyph "$data/bunny.ply" --orient none --vectors v -o "$tmp/x.vtp"
expect_error overflowing_result "not written: point 0 of the result is \(.*inf\): .*an option.s value overflows" "$bin" tube "$data/hello.vtk" -r 1e308 -o "$tmp/x.vtp"
expect_usage range_too_wide "--range: -1e\+308 .. 1e\+308 is too wide" "$bin" contour "$tmp/sphere.vti" --range -1e308 1e308 3 -o "$tmp/x.vtp"
expect_usage color_range_too_wide "--range: .* is too wide" "$bin" colormap "$data/bunny.ply" -a intensity --range -1e308 1e308 -o "$tmp/x.vtp"
expect_usage cut_range_same "--range: FIRST equals LAST" "$bin" cut "$tmp/sphere.vti" --plane 0 0 0 0 0 1 --range 0 0 3 -o "$tmp/x.vtp"
expect_usage bounds_too_wide "--bounds: x -1e\+308 .. 1e\+308 is too wide" "$bin" sample -f 'sphere()' -b -1e308 1e308 -1 1 -1 1 -o "$tmp/x.vti"
expect_error normals_of_lines "has no polygons or strips" "$bin" normals "$data/hello.vtk" -o "$tmp/x.vtp"
expect_usage glyph_unused_normals "--normals: unused" "$bin" glyph "$data/bunny.ply" --orient vectors --normals n -o "$tmp/x.vtp"

# ---- every option value checked: counts (never wrapped), numbers, meaning, contradictions ----
v=(-f 'sphere()' -b -1 1 -1 1 -1 1)  # a valid sample
# counts: negative, zero where meaningless, non-integer (CLI11 would wrap -5 into 2^64-5)
expect_usage steps_negative "--steps: must be an integer in \[1, 4294967295\], got -5" "$bin" attractor --steps -5 -o "$tmp/x.vtp"
expect_usage steps_zero "--steps: must be an integer in \[1, 4294967295\], got 0" "$bin" attractor --steps 0 -o "$tmp/x.vtp"
expect_usage steps_uint32 "--steps: must be an integer in \[1, 4294967295\], got 4294967296" "$bin" attractor --steps 4294967296 -o "$tmp/x.vtp"
expect_usage steps_fraction "--steps: must be an integer in \[1, 4294967295\], got '1.5'" "$bin" attractor --steps 1.5 -o "$tmp/x.vtp"
expect_usage transient_negative "--transient: must be an integer >= 0" "$bin" attractor --transient -1 -o "$tmp/x.vtp"
expect_usage attractor_dims_1 "--dims: must be an integer >= 2, got 1" "$bin" attractor --dims 1 -o "$tmp/x.vtp"
expect_usage largest_n_negative "--largest-n: must be an integer >= 1, got -1" "$bin" contour "$tmp/sphere.vti" -v 0 --largest-n -1 -o "$tmp/x.vtp"
expect_usage largest_n_zero "--largest-n: must be an integer >= 1, got 0" "$bin" contour "$tmp/sphere.vti" -v 0 --largest-n 0 -o "$tmp/x.vtp"
expect_usage range_n_negative "--range: must be an integer in \[1, 1000000\], got -3" "$bin" contour "$tmp/sphere.vti" --range 0 1 -3 -o "$tmp/x.vtp"
expect_usage range_n_fraction "--range: must be an integer .*got '2.5'" "$bin" contour "$tmp/sphere.vti" --range 0 1 2.5 -o "$tmp/x.vtp"
expect_usage range_n_huge "--range: must be an integer in \[1, 1000000\], got 1000000000" "$bin" contour "$tmp/sphere.vti" --range 0 1 1000000000 -o "$tmp/x.vtp"
expect_usage range_repeated "--range: FIRST equals LAST, so N must be 1" "$bin" contour "$tmp/sphere.vti" --range 0 0 5 -o "$tmp/x.vtp"
expect_usage sample_dims_negative "--dims: must be an integer >= 1, got -5" "$bin" sample "${v[@]}" -d -5 -o "$tmp/x.vti"
expect_usage sample_dims_zero "--dims: must be an integer >= 1, got 0" "$bin" sample "${v[@]}" -d 4 0 4 -o "$tmp/x.vti"
expect_usage distance_dims_1 "--dims: must be an integer >= 2" "$bin" distance "$data/hello.vtk" -d 1 -o "$tmp/x.vti"
expect_usage offset_dims_negative "--dims: must be an integer >= 2" "$bin" offset "$data/hello.vtk" -d 0.2 --dims -64 -o "$tmp/x.vtp"
# Values beyond what the box (double) or the Float32 field can hold name their option.
expect_usage distance_max_huge "--max-distance: 1e\+308 grows the box of .*hello.vtk beyond the range of a double" "$bin" distance "$data/hello.vtk" -m 1e308 -o "$tmp/x.vti"
expect_usage distance_max_float "--max-distance: 1e\+300 does not fit the Float32 distances" "$bin" distance "$data/hello.vtk" -m 1e300 --bounds 0 1 0 1 0 1 -o "$tmp/x.vti"
expect_usage distance_cap_float "--cap-value: -1e\+39 does not fit the Float32 distances" "$bin" distance "$data/hello.vtk" --cap --cap-value -1e39 -o "$tmp/x.vti"
expect_usage offset_max_float "--max-distance: 1e\+308 does not fit the Float32 distance field" "$bin" offset "$data/hello.vtk" -d 0.2 -m 1e308 -o "$tmp/x.vtp"
expect_ok dims_decimal "10 x 10 x 10 samples" "$bin" sample "${v[@]}" -d 010 -o "$tmp/x.vti"  # not octal 8
# numbers: non-finite, zero or negative where a positive value is needed, out of range
expect_usage shrink_nan "--shrink: must be a finite number in \[0, 1\], got 'nan'" "$bin" select "$tmp/sphere.vti" -f 'sphere()' --shrink nan -o "$tmp/x.vtu"
expect_usage shrink_range "--shrink: must be a finite number in \[0, 1\], got '1.5'" "$bin" select "$tmp/sphere.vti" -f 'sphere()' --shrink 1.5 -o "$tmp/x.vtu"
expect_usage bounds_nan "--bounds: must be a finite number, got 'nan'" "$bin" sample -f 'sphere()' -b 0 nan 0 1 0 1 -o "$tmp/x.vti"
expect_usage bounds_inf "--bounds: must be a finite number, got 'inf'" "$bin" sample -f 'sphere()' -b 0 inf 0 1 0 1 -o "$tmp/x.vti"
expect_usage bounds_order "--bounds: y 1 .. 0: min must not exceed max" "$bin" sample -f 'sphere()' -b 0 1 1 0 0 1 -o "$tmp/x.vti"
expect_usage bounds_flat "--bounds/--dims: .*zero extent" "$bin" sample -f 'sphere()' -b 0 1 0 0 0 1 -o "$tmp/x.vti"
expect_usage value_nan "--value: must be a finite number, got 'nan'" "$bin" contour "$tmp/sphere.vti" -v nan -o "$tmp/x.vtp"
expect_usage voxel_size_zero "--voxel-size: must be a finite number > 0, got '0'" "$bin" sample "${v[@]}" --voxel-size 0 -o "$tmp/x.vdb"
expect_usage max_distance_zero "--max-distance: must be a finite number > 0, got '0'" "$bin" distance "$data/hello.vtk" -m 0 -o "$tmp/x.vti"
expect_usage max_distance_inf "--max-distance: must be a finite number > 0, got 'inf'" "$bin" distance "$data/hello.vtk" -m inf -o "$tmp/x.vti"
expect_usage half_width_negative "--half-width: must be a finite number > 0" "$bin" sample "${v[@]}" --half-width -3 -o "$tmp/x.vdb"
expect_usage step_zero "--step: must be a finite number > 0" "$bin" attractor --step 0 -o "$tmp/x.vtp"
expect_usage visits_negative "--value: must be a finite number > 0" "$bin" attractor --value -5 -o "$tmp/x.vtp"
expect_usage tolerance_negative "--vdb-tolerance: must be a finite number in \[0, 3.40282[0-9]*e\+38\], got .-1." "$bin" convert "$tmp/sphere.vti" "$tmp/x.vdb" --vdb-tolerance -1
expect_usage tolerance_beyond_float "--vdb-tolerance: must be a finite number in \[0, 3.40282[0-9]*e\+38\], got .1e308." "$bin" convert "$tmp/sphere.vti" "$tmp/x.vdb" --vdb-tolerance 1e308
expect_usage offset_a_nan "--offset-a: must be a finite number" "$bin" csg union "$tmp/sphere.vti" "$tmp/sphere.vti" --offset-a nan -o "$tmp/x.vti"
expect_error offset_a_float32 "offset: the distance 1e\+308 is beyond the range of the Float32 scalars" "$bin" csg union "$tmp/sphere.vti" "$tmp/sphere.vti" --offset-a 1e308 -o "$tmp/x.vti"
# options that do nothing for these inputs/outputs
expect_usage normals_sparse "--normals: applies to dense output" "$bin" sample "${v[@]}" --normals -o "$tmp/x.vdb"
expect_usage half_width_dense "--half-width: applies to sparse output" "$bin" sample "${v[@]}" --half-width 2 -o "$tmp/x.vti"
expect_usage ascii_vdb "--ascii: applies to VTK and PLY output" "$bin" convert "$tmp/sphere.vti" "$tmp/x.vdb" --ascii
expect_usage legacy_xml "--legacy-version: applies to VTK legacy output" "$bin" convert "$data/hello.vtk" "$tmp/x.vtp" --legacy-version 5.1
expect_usage no_compress_legacy "--no-compress: applies to VTK XML output only" "$bin" convert "$data/hello.vtk" "$tmp/x.vtk" --no-compress
expect_usage tolerance_vti "--vdb-tolerance: applies to OpenVDB output only" "$bin" convert "$tmp/sphere.vti" "$tmp/x.vti" --vdb-tolerance 0.1
expect_usage q_not_plot3d "--q: a PLOT3D solution goes with a PLOT3D grid input" "$bin" info "$data/hello.vtk" --q "$data/combq.bin"
expect_usage grid_not_vdb "--grid: names a grid of an OpenVDB input" "$bin" contour "$tmp/sphere.vti" -v 0 --grid F -o "$tmp/x.vtp"
expect_usage cap_sparse "--cap: applies to dense output" "$bin" distance "$data/hello.vtk" --cap -o "$tmp/x.vdb"
expect_usage float64_sparse "--float64: applies to dense output" "$bin" distance "$data/hello.vtk" --float64 -o "$tmp/x.vdb"
expect_usage voxel_size_dense "--voxel-size: applies to sparse output" "$bin" distance "$data/hello.vtk" --voxel-size 0.1 -o "$tmp/x.vti"
expect_usage allow_open_unsigned "--allow-open: applies with --signed only" "$bin" distance "$data/hello.vtk" --allow-open -o "$tmp/x.vti"
expect_usage cap_value_no_cap "--cap-value: applies with --cap only" "$bin" distance "$data/hello.vtk" --cap-value 1 -o "$tmp/x.vti"
expect_usage offset_field_dims "--dims: applies when the input is polygonal data" "$bin" offset "$tmp/sphere.vti" -d 0 --dims 32 -o "$tmp/x.vtp"
expect_usage offset_unsigned_negative "--distance: -0.1: an unsigned distance field" "$bin" offset "$data/hello.vtk" -d -0.1 -o "$tmp/x.vtp"
expect_usage offset_band_short "--max-distance: 0.1 must exceed the largest \|distance\| 0.2" "$bin" offset "$data/hello.vtk" -d 0.2 -m 0.1 -o "$tmp/x.vtp"
expect_usage attractor_volume_twice "--volume: the counts are the output already" "$bin" attractor --volume "$tmp/v.vti" -o "$tmp/x.vti"
expect_usage attractor_value_counts "--value: applies to a surface output" "$bin" attractor -v 20 -o "$tmp/x.vti"
# contradictions and outputs that cannot hold the result
expect_usage largest_closest "--largest and --closest exclude each other" "$bin" contour "$tmp/sphere.vti" -v 0 --largest --closest 0 0 0 -o "$tmp/x.vtp"
expect_usage dims_voxel_size "--dims and --voxel-size exclude each other" "$bin" sample "${v[@]}" -d 32 --voxel-size 0.1 -o "$tmp/x.vdb"
expect_usage no_cap_sparse "--no-cap and --voxel-size exclude each other" "$bin" offset "$data/hello.vtk" -d 0.2 --no-cap --voxel-size 0.05 -o "$tmp/x.vtp"
expect_usage ascii_no_compress "--ascii and --no-compress exclude each other" "$bin" convert "$data/hello.vtk" "$tmp/x.vtp" --ascii --no-compress
expect_usage sample_to_vtp "x.vtp: this subcommand writes .vti .vtk" "$bin" sample "${v[@]}" -o "$tmp/x.vtp"
expect_usage select_to_vtp "x.vtp: this subcommand writes .vtu .vtk" "$bin" select "$tmp/sphere.vti" -f 'sphere()' -o "$tmp/x.vtp"
expect_usage convert_to_nrrd "writing NRRD is not supported" "$bin" convert "$tmp/sphere.vti" "$tmp/x.nrrd"
expect_usage csg_sparse_to_vti "this subcommand writes .vdb \(the field\)" "$bin" csg union "$tmp/ice.vdb" "$tmp/ice.vdb" -o "$tmp/x.vti"

# ---- huge requests: refused at once with the size they need (they ended in std::bad_alloc after
# growing to gigabytes); no machine has the petabytes these need, so nothing is allocated ----
expect_error huge_sample "sample: a 100000³ Float32 volume needs 4 PB; this machine has" "$bin" sample "${v[@]}" -d 100000 -o "$tmp/refused.vti"
expect_error huge_sample_normals "sample: a 100000³ Float32 volume needs 16 PB" "$bin" sample "${v[@]}" -d 100000 --normals -o "$tmp/refused.vti"
expect_error huge_distance "distance: a 100000³ Float32 volume needs 4 PB" "$bin" distance "$data/hello.vtk" -d 100000 -o "$tmp/refused.vti"
expect_error huge_offset "distance: a 100000³ Float32 volume needs 4 PB" "$bin" offset "$data/hello.vtk" -d 0.2 --dims 100000 -o "$tmp/refused.vtp"
expect_error huge_attractor "trajectory density: a 100000³ UInt32 volume needs 4 PB" "$bin" attractor --dims 100000 -o "$tmp/refused.vtp"
expect_error huge_band "sparse sample: a narrow band \(half width 3\) of about .* leaves \(8³ voxels\) in a 100000³ grid needs .* TB; this machine has" "$bin" sample -f 'sphere(r=0.8)' -b -1 1 -1 1 -1 1 -d 100000 -o "$tmp/refused.vdb"
expect_error huge_distance_band "distance: a narrow band of about .* voxels \(within 0.003 of the input, voxel size 1e-05\) in a 16171 x 16035 x 12669 grid needs .* TB" "$bin" distance "$data/bunny.ply" -m 0.003 --voxel-size 0.00001 -o "$tmp/refused.vdb"
expect_error huge_offset_band "offset: a narrow band of about .* voxels .* needs .* TB" "$bin" offset "$data/bunny.ply" -d 0.001 --voxel-size 0.000005 -o "$tmp/refused.ply"
expect_ok tiny_band_in_huge_grid "active" "$bin" sample -f 'sphere(r=0.0002)' -b -1 1 -1 1 -1 1 -d 100000 -o "$tmp/tiny.vdb"
ls "$tmp"/refused.* >/dev/null 2>&1 && fail "a refused request left an output"

# ---- implicit modeling ----
expect_ok offset_hello "5 connected surfaces" "$bin" offset "$data/hello.vtk" -d 0.25 --dims 110 40 20 --bounds -1 10 -1 3 -1 1 -o "$tmp/hello.vtp"
expect_ok offset_hello_info "cells: [0-9]+ \\([0-9]+ triangle\\)" "$bin" info "$tmp/hello.vtp"
expect_error distance_open "open" "$bin" distance "$data/bunny.ply" --signed -m 0.01 -d 16 -o "$tmp/b.vti"
expect_ok attractor "discarded" "$bin" attractor --steps 100000 --dims 50 -o "$tmp/l.vtp"

# ---- --threads N: every subcommand honours it, results do not depend on it ----
expect_ok threads_1 "wrote" "$bin" --threads 1 sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 40 -o "$tmp/t1.vti"
expect_ok threads_2 "wrote" "$bin" sample -f 'icecream()' -b -0.1 2 -0.7 0.7 -0.7 0.7 -d 40 -o "$tmp/t2.vti" --threads 2
cmp -s "$tmp/t1.vti" "$tmp/t2.vti" || fail "threads: sample with --threads 1 and 2 differ"
# (dense: a .vdb file holds a random UUID, so two runs never give the same bytes)
expect_ok threads_d1 "wrote" "$bin" --threads 1 distance "$data/bunny.ply" -m 0.01 -d 40 -o "$tmp/t1d.vti"
expect_ok threads_d2 "wrote" "$bin" --threads 2 distance "$data/bunny.ply" -m 0.01 -d 40 -o "$tmp/t2d.vti"
cmp -s "$tmp/t1d.vti" "$tmp/t2d.vti" || fail "threads: distance with --threads 1 and 2 differ"
expect_usage threads_0 "--threads: must be an integer in \[1, 4096\], got 0" "$bin" --threads 0 info "$data/hello.vtk"
expect_usage threads_negative "--threads: must be an integer" "$bin" --threads -2 info "$data/hello.vtk"
expect_usage threads_fraction "--threads: must be an integer" "$bin" --threads 1.5 info "$data/hello.vtk"

# ---- an empty result is written (exit 0) with a warning naming the value and the data's range ----
expect_ok empty_contour "^isoforge: warning: contour: no surface at value 5000: 'Scalars' ranges 0 \.\. 3926$" "$bin" contour "$data/headsq/quarter.nhdr" -v 5000 -o "$tmp/empty.vtp"
expect_ok empty_contour_info "points: 0" "$bin" info "$tmp/empty.vtp"
expect_ok empty_contour_values "no surface at values 5, 6: 'F' ranges -0\.[0-9]+ \.\. 0\.[0-9]+" "$bin" contour "$tmp/sphere.vti" -v 5 -v 6 -o "$tmp/empty.vtp"
expect_ok empty_contour_vdb "no surface at value 5: 'F' ranges .* over [0-9]+ active voxels \(background" "$bin" contour "$tmp/ice.vdb" -v 5 -o "$tmp/empty.vtp"
expect_ok empty_offset "warning: offset: no surface at distance 7: 'F' ranges" "$bin" offset "$tmp/sphere.vti" -d 7 -o "$tmp/empty.vtp"
expect_ok empty_select "warning: select: no cell lies inside 'sphere\(center=\[5,5,5\], r=0.1\)' .*: 'F' ranges [0-9.]+ \.\. [0-9.]+ over the points of" "$bin" select "$tmp/sphere.vti" -f 'sphere(center=[5,5,5], r=0.1)' -o "$tmp/empty.vtu"
expect_ok empty_csg "warning: csg: the intersection is empty \(no value <= 0\): 'F' ranges" "$bin" csg intersection "$tmp/sphere.vti" "$tmp/sphere.vti" --offset-a -5 -o "$tmp/empty.vtp"
expect_ok empty_attractor "warning: attractor: no surface at 1000 visits: the counts range 0 \.\. [0-9]+" "$bin" attractor --steps 1000 --dims 20 -v 1000 -o "$tmp/empty.vtp"
expect_ok empty_distance "warning: distance: no sample lies within 0.9 of .*hello.vtk" "$bin" distance "$data/hello.vtk" -b 20 21 20 21 20 21 -d 8 -o "$tmp/empty.vti"
expect_ok empty_band "warning: sample: the band is empty" "$bin" sample -f 'sphere(r=0.5)' -b 2 3 2 3 2 3 -d 32 -o "$tmp/empty.vdb"
out=$("$bin" contour "$tmp/sphere.vti" -v 0 -o "$tmp/full.vtp" 2>&1)
grep -q warning <<<"$out" && fail "a non-empty contour warned: $out"

# ---- fit: parameters, statistics, the function as an expression that sample reads back ----
"$bin" --quiet sample -f 'sphere(center=[1,2,3], r=2)' -b -2 4 -1 5 0 6 -d 32 -o "$tmp/ball.vti" >/dev/null
"$bin" --quiet contour "$tmp/ball.vti" -v 0 -o "$tmp/ball.vtp" >/dev/null
# The contour's points lie within a voxel's linear-interpolation error of the sphere.
expect_ok fit_sphere "center: 1(\.0*[0-9]*)? 2(\.0*[0-9]*)? 3(\.0*[0-9]*)?" "$bin" fit "$tmp/ball.vtp" --primitive sphere
expect_ok fit_sphere_radius "radius: 1\.99[0-9]*" "$bin" fit "$tmp/ball.vtp" -p sphere --loss none
expect_ok fit_sphere_function "^function: sphere\(center=\[" "$bin" fit "$tmp/ball.vtp" -p sphere --loss cauchy
expect_ok fit_sphere_file "wrote .*ball.txt" "$bin" fit "$tmp/ball.vtp" -p sphere -o "$tmp/ball.txt"
# Ceres (libisoforge_fit, which links Ceres in, and Ceres' glog and cholmod) is loaded by fitting
# only (shared builds; see the OpenVDB check above).
if LD_TRACE_LOADED_OBJECTS=1 "$bin" 2>&1 | grep -q "libisoforge\.so"; then
  fit_loads() { loads "(libglog|libcholmod|libisoforge_fit)" "$@"; }
  n=$(fit_loads "$bin" decimate "$tmp/ball.vtp" -r 0.5 -o "$tmp/lazy.ply")
  [ "$n" = 0 ] || fail "decimate without --refine loaded $n of libisoforge_fit, libglog, libcholmod"
  n=$(fit_loads "$bin" decimate "$tmp/ball.vtp" -r 0.5 --refine -o "$tmp/lazy.ply")
  [ "$n" = 3 ] || fail "decimate --refine loaded $n of libisoforge_fit, libglog, libcholmod"
  n=$(fit_loads "$bin" fit "$tmp/ball.vtp" -p sphere)
  [ "$n" = 3 ] || fail "fit loaded $n of libisoforge_fit, libglog, libcholmod"
fi
grep -Eq '^sphere\(center=\[.*\], r=1\.99[0-9]*\)$' "$tmp/ball.txt" || fail "fit -o: unexpected file: $(cat "$tmp/ball.txt")"
[ "$(grep '^function: ' <<<"$("$bin" fit "$tmp/ball.vtp" -p sphere)" | cut -c11-)" = "$(cat "$tmp/ball.txt")" ] ||
  fail "fit -o: the file differs from the printed function"
expect_ok fit_file_samples "wrote .*refit.vti" "$bin" sample -f "$(cat "$tmp/ball.txt")" -b -2 4 -1 5 0 6 -d 8 -o "$tmp/refit.vti"
expect_ok fit_quadric "^residuals \(first-order distance\)" "$bin" fit "$tmp/ball.vtp" -p quadric
expect_ok fit_plane_hello "normal: -?0 -?0 1$" "$bin" fit "$data/hello.vtk" -p plane --loss none
expect_ok fit_inliers "inliers 1992 of 1992" "$bin" fit "$tmp/ball.vtp" -p sphere
expect_ok fit_image "fitted to 512 points" "$bin" fit "$tmp/refit.vti" -p plane --max-iterations 5
expect_usage fit_kind "--primitive: torus not in" "$bin" fit "$tmp/ball.vtp" -p torus
expect_usage fit_no_kind "--primitive is required" "$bin" fit "$tmp/ball.vtp"
expect_usage fit_loss "--loss: bogus not in" "$bin" fit "$tmp/ball.vtp" -p sphere --loss bogus
expect_usage fit_scale_nan "--loss-scale: must be a finite number > 0, got 'nan'" "$bin" fit "$tmp/ball.vtp" -p sphere --loss-scale nan
expect_usage fit_scale_zero "--loss-scale: must be a finite number > 0, got '0'" "$bin" fit "$tmp/ball.vtp" -p sphere --loss-scale 0
expect_usage fit_scale_none "--loss-scale: applies to a robust loss" "$bin" fit "$tmp/ball.vtp" -p sphere --loss none --loss-scale 1
expect_usage fit_iterations_zero "--max-iterations: must be an integer in \[1, 100000\], got 0" "$bin" fit "$tmp/ball.vtp" -p sphere --max-iterations 0
expect_usage fit_iterations_fraction "--max-iterations: must be an integer .*got '2.5'" "$bin" fit "$tmp/ball.vtp" -p sphere --max-iterations 2.5
expect_error fit_degenerate "quadric: the points do not determine a quadric" "$bin" fit "$data/hello.vtk" -p quadric
expect_error fit_missing "nosuch.vtp" "$bin" fit "$tmp/nosuch.vtp" -p plane
expect_error fit_out_dir "nodir" "$bin" fit "$tmp/ball.vtp" -p sphere -o "$tmp/nodir/f.txt"
# A failed fit leaves an existing output file as it was.
echo "keep" > "$tmp/keep.txt"
"$bin" fit "$data/hello.vtk" -p quadric -o "$tmp/keep.txt" >/dev/null 2>&1
[ "$(cat "$tmp/keep.txt")" = "keep" ] || fail "a failed fit replaced its output file"

# ---- decimate: exact counts, measured errors, validated options ----
expect_ok decimate_count "wrote .*bunny10.ply: [0-9]+ points, 6945 triangles \(from 69451; quadric, target reached\)" "$bin" decimate "$data/bunny.ply" -r 0.9 -o "$tmp/bunny10.ply"
expect_ok decimate_distance "distance to the input: Hausdorff [0-9.e-]+ \([0-9.]+e-0[34] of the diagonal\), RMS" "$bin" decimate "$data/bunny.ply" -t 5000 -o "$tmp/bunny5k.vtp"
expect_ok decimate_free_volume "wrote .*: [0-9]+ points, 6945 triangles \(from 69451; quadric, target reached\)" "$bin" decimate "$data/bunny.ply" -r 0.9 --free-volume -o "$tmp/bunny10_gh.ply"
expect_ok decimate_target "wrote .*: [0-9]+ points, 5000 triangles" "$bin" decimate "$data/bunny.ply" -t 5000 -m vertex-removal -o "$tmp/bunny5k_vr.vtp"
expect_ok decimate_cells "wrote .*: [0-9]+ points, (499[7-9]|5000) triangles .*cell-collapse" "$bin" decimate "$data/bunny.ply" -t 5000 -m cell-collapse -o "$tmp/bunny5k_cc.vtp"
expect_ok decimate_refine "refined in [0-9.]+ s: RMS" "$bin" decimate "$data/bunny.ply" -t 3000 --refine -o "$tmp/bunny3k.vtp"
expect_ok decimate_error "maximum error reached" "$bin" decimate "$data/bunny.ply" -e 0.001 --relative --no-measure -o "$tmp/bunny_err.vtp"
"$bin" --quiet info "$tmp/bunny10.ply" | grep -q "cells: 6945 (6945 triangle)" || fail "decimate: the output file does not hold 6945 triangles"
expect_usage decimate_no_stop "give a stop" "$bin" decimate "$data/bunny.ply" -o "$tmp/x.vtp"
expect_usage decimate_two_stops "exclude each other" "$bin" decimate "$data/bunny.ply" -t 10 -r 0.5 -o "$tmp/x.vtp"
expect_usage decimate_reduction_big "--reduction: must be a finite number in \(0, 1\]" "$bin" decimate "$data/bunny.ply" -r 1.5 -o "$tmp/x.vtp"
expect_usage decimate_reduction_one "--reduction: must be below 1" "$bin" decimate "$data/bunny.ply" -r 1 -o "$tmp/x.vtp"
expect_usage decimate_reduction_nan "--reduction: .*got 'nan'" "$bin" decimate "$data/bunny.ply" -r nan -o "$tmp/x.vtp"
expect_usage decimate_target_zero "--target-triangles: must be an integer >= 1, got 0" "$bin" decimate "$data/bunny.ply" -t 0 -o "$tmp/x.vtp"
expect_usage decimate_target_negative "--target-triangles: must be an integer >= 1, got '?-5'?" "$bin" decimate "$data/bunny.ply" -t -5 -o "$tmp/x.vtp"
expect_usage decimate_error_negative "--max-error: must be a finite number > 0" "$bin" decimate "$data/bunny.ply" -e -1 -o "$tmp/x.vtp"
expect_usage decimate_relative_alone "--relative: applies to --max-error only" "$bin" decimate "$data/bunny.ply" -t 100 --relative -o "$tmp/x.vtp"
expect_usage decimate_method "--method: bogus not in" "$bin" decimate "$data/bunny.ply" -t 100 -m bogus -o "$tmp/x.vtp"
expect_usage decimate_angle "--feature-angle: must be a finite number in \(0, 180\]" "$bin" decimate "$data/bunny.ply" -t 100 --feature-angle 200 -o "$tmp/x.vtp"
expect_usage decimate_extension "x.vti" "$bin" decimate "$data/bunny.ply" -t 100 -o "$tmp/x.vti"
expect_error decimate_volume "decimate: .*ironProt.vtk is image data; only polygonal data can be decimated" "$bin" decimate "$data/ironProt.vtk" -t 100 -o "$tmp/x.vtp"
expect_error decimate_lock_missing "lock array 'Nope'" "$bin" decimate "$data/bunny.ply" -t 100 --lock Nope -o "$tmp/x.vtp"
expect_error decimate_no_triangles "no triangle" "$bin" decimate "$data/hello.vtk" -t 10 -o "$tmp/x.vtp"

# ---- convert to Draco (.drc): measured errors within the budget, options validated ----
expect_ok drc_budget "Points: [0-9]+ bits, step [0-9.e-]+, measured max error [0-9.e-]+ \(budget 2\.5e-05\)" "$bin" convert "$data/bunny.ply" "$tmp/bunny.drc" --max-error-rel 1e-4
expect_ok drc_bits "Points: 16 bits" "$bin" convert "$data/bunny.ply" "$tmp/bunny16.drc" --bits 16 --level 10
expect_ok drc_sequential "decoded: 35947 points, 69451 triangles; lost triangles: 0" "$bin" convert "$data/bunny.ply" "$tmp/bunny_seq.drc" --sequential --max-error 1e-5 --array-error confidence=0.001
expect_ok drc_array_budget "confidence: [0-9]+ bits, .*\(budget 0\.001\)" "$bin" convert "$data/bunny.ply" "$tmp/bunny_seq.drc" --sequential --max-error 1e-5 --array-error confidence=0.001
expect_ok drc_back "points: 35947" "$bin" info "$tmp/bunny_seq.drc"
expect_ok drc_back_arrays "'confidence' +Float32" "$bin" info "$tmp/bunny_seq.drc"
expect_ok drc_to_vtp "wrote .*b.vtp \(34834 points, 69451 cells\)" "$bin" convert "$tmp/bunny.drc" "$tmp/b.vtp"
# The measured error printed never exceeds the budget (parsed from the output).
out=$("$bin" convert "$data/fran_cut.vtk" "$tmp/fran.drc" --max-error 0.0005 2>&1)
awk '/Points:/ { for (i = 1; i <= NF; ++i) if ($i == "error") e = $(i + 1) } END { exit !(e + 0 <= 0.0005 && e + 0 > 0) }' <<<"$out" || fail "drc_fran: measured error above the budget: $out"
expect_error drc_lines "Draco has no lines" "$bin" convert "$data/hello.vtk" "$tmp/x.drc"
expect_error drc_volume "Draco holds polygonal data only" "$bin" convert "$data/ironProt.vtk" "$tmp/x.drc"
head -c 100 "$tmp/bunny.drc" > "$tmp/trunc.drc"
expect_error drc_truncated "trunc.drc: .*(corrupt|truncated)" "$bin" info "$tmp/trunc.drc"
printf 'not draco at all' > "$tmp/junk.drc"
expect_error drc_junk "junk.drc: not a Draco file" "$bin" convert "$tmp/junk.drc" "$tmp/x.vtp"
expect_usage drc_bits_zero "--bits: must be an integer in \[1, 30\], got 0" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --bits 0
expect_usage drc_bits_big "--bits: must be an integer in \[1, 30\], got 31" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --bits 31
expect_usage drc_normal_bits "--normal-bits: must be an integer in \[1, 30\]" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --normal-bits -1
expect_usage drc_level "--level: must be an integer in \[0, 10\], got 11" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --level 11
expect_usage drc_error_nan "--max-error: must be a finite number > 0, got 'nan'" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --max-error nan
expect_usage drc_error_negative "--max-error-rel: must be a finite number > 0" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --max-error-rel -1
expect_usage drc_error_zero "--max-error: must be a finite number > 0" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --max-error 0
expect_usage drc_two_budgets "--max-error and --max-error-rel exclude each other" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --max-error 1 --max-error-rel 0.1
expect_usage drc_bits_budget "--bits and --max-error-rel exclude each other" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --bits 12 --max-error-rel 0.1
expect_usage drc_array_malformed "--array-error: must be NAME=E with a finite E > 0, got 'confidence=-1'" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --array-error confidence=-1
expect_usage drc_array_twice "--array-error: array 'confidence' given twice" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --array-error confidence=1 --array-error confidence=2
expect_error drc_array_missing "error budget for 'nope', which is not a point array" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --array-error nope=1
for opt in "--bits 12" "--sequential" "--max-error 1" "--max-error-rel 0.1" "--array-error a=1" "--generic-bits 9"; do
  # shellcheck disable=SC2086
  expect_usage "drc_meaningless_${opt%% *}" "${opt%% *}: applies to Draco output \(.drc, or .glb with the draco codec\) only" "$bin" convert "$data/bunny.ply" "$tmp/x.vtp" $opt
done
# ---- colormap: exact colours on a tiny input (info prints each component's range), every
# dataset type's point or cell data, --color-by on the commands that write meshes ----
printf '# vtk DataFile Version 3.0\nramp\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0 1 0 0 2 0 0 3 0 0\nVERTICES 4 8\n1 0\n1 1\n1 2\n1 3\nPOINT_DATA 4\nSCALARS s float\nLOOKUP_TABLE default\n0 10 nan 20\n' > "$tmp/ramp.vtk"
# Rainbow over 0 .. 10: red, blue, grey (NaN), blue (20 is above, clamped to the last colour).
expect_ok colormap_stats "range 0 .. 10 \(given\); 1 NaN, 0 below and 1 above the range" "$bin" colormap "$tmp/ramp.vtk" -a s --colormap rainbow --range 0 10 -o "$tmp/ramp_rainbow.vtp"
expect_ok colormap_rainbow_colours "'Colors' +UInt8 +x3 .*\[0, 255\], \[0, 128\], \[0, 255\]" "$bin" info "$tmp/ramp_rainbow.vtp"
# The data's range (0 .. 20, NaN ignored) with viridis: 0, 10, 20 take 68 1 84, 33 144 140 and
# 253 231 37, NaN the given 0 0 0; RGBA with opacity 0.5 -> alpha 128 (the NaN colour keeps 255).
expect_error colormap_name_taken "ramp.vtk already has an array 's', which the new array would replace: give --name another name" "$bin" colormap "$tmp/ramp.vtk" -a s --name s -o "$tmp/ramp_x.vtp"
expect_ok colormap_auto "range 0 .. 20 \(of the data\); 1 NaN" "$bin" colormap "$tmp/ramp.vtk" -a s --nan-color 0,0,0 --rgba --opacity 0.5 -o "$tmp/ramp_viridis.vtp"
expect_ok colormap_viridis_colours "'Colors' +UInt8 +x4 .*\[0, 253\], \[0, 231\], \[0, 140\], \[128, 255\]" "$bin" info "$tmp/ramp_viridis.vtp"
expect_ok colormap_above_color "1 above" "$bin" colormap "$tmp/ramp.vtk" -a s --colormap grayscale --range 0 10 --above-color 0,255,0 --nan-color 9,9,9 -o "$tmp/ramp_above.vtp"
expect_ok colormap_above_colours "'Colors' +UInt8 +x3 .*\[0, 255\], \[0, 255\], \[0, 255\]" "$bin" info "$tmp/ramp_above.vtp"
expect_ok colormap_ply "wrote .*'Colors' \(RGB, 35947 point colours\) from 'intensity' by plasma" "$bin" colormap "$data/bunny.ply" -a intensity --colormap plasma -o "$tmp/bunny_plasma.ply"
expect_ok colormap_ply_back "'Colors' +UInt8 +x3" "$bin" info "$tmp/bunny_plasma.ply"
expect_ok colormap_cells "'Colors' \(RGB, [0-9]+ cell colours\) from 'OriginalCellIds'" "$bin" colormap "$tmp/inside.vtu" -a OriginalCellIds --bands 4 -o "$tmp/inside_colors.vtu"
"$bin" info "$tmp/inside_colors.vtu" | awk '/^cell data/ { c = 1 } c && /Colors/' | grep -q UInt8 || fail "colormap: no cell array 'Colors' in inside_colors.vtu"
expect_ok colormap_grid "47025 point colours" "$bin" colormap "$data/combxyz.bin" --q "$data/combq.bin" -a Velocity --magnitude --log --range 1 2000 -o "$tmp/speed.vts"
expect_ok colormap_quiet "^$" "$bin" --quiet colormap "$tmp/ramp.vtk" -a s -o "$tmp/ramp_q.vtp"
expect_error colormap_unknown_array "no array 'nosuch' \(point arrays: 'confidence', 'intensity'; cell arrays: none\)" "$bin" colormap "$data/bunny.ply" -a nosuch -o "$tmp/x.vtp"
expect_error colormap_component_range "'intensity': component 3 is out of range \(the array has 1 component\)" "$bin" colormap "$data/bunny.ply" -a intensity --component 3 -o "$tmp/x.vtp"
expect_error colormap_log_data "'intensity': log scale needs positive values, but they range \[0, 0.5\]" "$bin" colormap "$data/bunny.ply" -a intensity --log -o "$tmp/x.vtp"
expect_usage colormap_range_order "--range: MIN must be below MAX, got 5 1" "$bin" colormap "$data/bunny.ply" -a intensity --range 5 1 -o "$tmp/x.vtp"
expect_usage colormap_range_nan "--range: .*nan" "$bin" colormap "$data/bunny.ply" -a intensity --range 0 nan -o "$tmp/x.vtp"
expect_usage colormap_range_log "--range: --log needs a positive range, got 0 1" "$bin" colormap "$data/bunny.ply" -a intensity --log --range 0 1 -o "$tmp/x.vtp"
expect_usage colormap_two_sources "exclude each other" "$bin" colormap "$data/bunny.ply" -a intensity --component 0 --magnitude -o "$tmp/x.vtp"
expect_usage colormap_unknown_map "--colormap: jet not in" "$bin" colormap "$data/bunny.ply" -a intensity --colormap jet -o "$tmp/x.vtp"
expect_usage colormap_short_color "--nan-color: expected R,G,B or R,G,B,A with integers 0..255, got '1,2'" "$bin" colormap "$data/bunny.ply" -a intensity --nan-color 1,2 -o "$tmp/x.vtp"
expect_usage colormap_big_color "--below-color: expected .*got '300,0,0'" "$bin" colormap "$data/bunny.ply" -a intensity --below-color 300,0,0 -o "$tmp/x.vtp"
expect_usage colormap_opacity_rgb "--opacity: applies to --rgba output only" "$bin" colormap "$data/bunny.ply" -a intensity --opacity 0.5 -o "$tmp/x.vtp"
expect_usage colormap_bands_zero "--bands: must be an integer in \[1, " "$bin" colormap "$data/bunny.ply" -a intensity --bands 0 -o "$tmp/x.vtp"
expect_usage colormap_component_negative "--component: must be an integer in \[0, 2147483647\], got -1" "$bin" colormap "$data/bunny.ply" -a intensity --component -1 -o "$tmp/x.vtp"
expect_usage colormap_empty_name "--name: an empty value is not allowed" "$bin" colormap "$data/bunny.ply" -a intensity --name '' -o "$tmp/x.vtp"
expect_ok contour_color_by "coloured by 'Velocity' \(cool-warm, range" "$bin" contour "$data/combxyz.bin" --q "$data/combq.bin" -a Density -v 0.3 --color-by Velocity --colormap cool-warm -o "$tmp/density.vtp"
expect_ok contour_color_by_back "'Colors' +UInt8 +x3" "$bin" info "$tmp/density.vtp"
expect_ok contour_color_by_cells "coloured by 'OriginalCellIds' \(rainbow, range" "$bin" contour "$tmp/inside.vtu" -v -0.5 --color-by OriginalCellIds --colormap rainbow -o "$tmp/inside_contour.vtp"
expect_ok contour_color_by_empty "warning: contour: no surface at value 0" "$bin" contour "$tmp/inside.vtu" -v 0 --color-by OriginalCellIds -o "$tmp/inside_empty.vtp"
expect_ok decimate_color_by "coloured by 'intensity' \(viridis, range 0 .. 0.5\)" "$bin" decimate "$data/bunny.ply" -r 0.9 --no-measure --color-by intensity -o "$tmp/bunny10_colors.ply"
expect_ok decimate_color_by_back "'Colors' +UInt8 +x3" "$bin" info "$tmp/bunny10_colors.ply"
expect_ok convert_color_by "coloured by 'Pressure' \(black-body, range 1 .. 1.5\)" "$bin" convert "$data/post.vtk" "$tmp/post_colors.vtu" --color-by Pressure --colormap black-body --color-range 1 1.5
expect_ok convert_color_by_back "'Colors' +UInt8 +x3" "$bin" info "$tmp/post_colors.vtu"
expect_usage color_by_map_alone "--colormap: applies with --color-by only" "$bin" contour "$tmp/sphere.vti" -v 0 --colormap plasma -o "$tmp/x.vtp"
expect_usage color_by_range_alone "--color-range: applies with --color-by only" "$bin" convert "$data/post.vtk" "$tmp/x.vtu" --color-range 0 1
expect_usage color_by_range_order "--color-range: MIN must be below MAX, got 1 1" "$bin" convert "$data/post.vtk" "$tmp/x.vtu" --color-by Pressure --color-range 1 1
expect_usage color_by_vdb "--color-by: OpenVDB files do not store colours" "$bin" convert "$data/HeadMRVolume.mhd" "$tmp/x.vdb" --color-by MetaImage
expect_usage color_by_obj "--color-by: OBJ files do not store colours" "$bin" decimate "$data/bunny.ply" -r 0.5 --color-by intensity -o "$tmp/x.obj"
expect_usage colormap_obj "x.off: this subcommand writes .vtk .vti .vts .vtp .vtu .ply, not OFF" "$bin" colormap "$data/bunny.ply" -a intensity -o "$tmp/x.off"
expect_usage colormap_component_huge "--component: must be an integer in \[0, 2147483647\], got 4294967296" "$bin" colormap "$data/bunny.ply" -a intensity --component 4294967296 -o "$tmp/x.vtp"
expect_error color_by_unknown "--color-by: no point array 'nosuch' \(point arrays: 'confidence', 'intensity'\)" "$bin" decimate "$data/bunny.ply" -r 0.5 --color-by nosuch -o "$tmp/x.vtp"
expect_error color_by_unknown_convert "--color-by: no array 'nosuch' \(point arrays: 'Pressure'; cell arrays: none\)" "$bin" convert "$data/post.vtk" "$tmp/x.vtu" --color-by nosuch

# ---- help: every subcommand has examples ----
for sub in info convert sample select contour distance offset csg attractor fit decimate colormap view; do
  expect_ok "help_$sub" "Examples:" "$bin" "$sub" --help
done

# ---- VTK XML compression: --compressor and --level on every subcommand that writes XML ----
expect_ok xml_lz4 "wrote" "$bin" convert "$data/ironProt.vtk" "$tmp/iron_lz4.vti" --compressor lz4
grep -q 'compressor="vtkLZ4DataCompressor"' "$tmp/iron_lz4.vti" || fail "xml_lz4: no LZ4 compressor attribute"
expect_ok xml_none "wrote" "$bin" convert "$data/ironProt.vtk" "$tmp/iron_none.vti" --compressor none
grep -q 'compressor=' "$tmp/iron_none.vti" && fail "xml_none: compressed anyway"
expect_ok xml_z1 "wrote" "$bin" convert "$data/ironProt.vtk" "$tmp/iron_z1.vti" --level 1
expect_ok xml_z12 "wrote" "$bin" convert "$data/ironProt.vtk" "$tmp/iron_z12.vti" --compressor zlib --level 12
# The same data whatever the compressor (info prints the ranges); level 12 is smaller than 1.
for f in iron_lz4 iron_none iron_z12; do
  [ "$("$bin" info "$tmp/$f.vti" 2>&1 | grep -v "$f")" = "$("$bin" info "$tmp/iron_z1.vti" 2>&1 | grep -v iron_z1)" ] || fail "xml_same_$f: info differs from iron_z1.vti"
done
[ "$(stat -c %s "$tmp/iron_z12.vti")" -lt "$(stat -c %s "$tmp/iron_z1.vti")" ] || fail "xml_levels: level 12 is not smaller than level 1"
expect_ok xml_contour_lz4 "" "$bin" contour "$tmp/iron_lz4.vti" -v 20 --compressor lz4 --level 9 -o "$tmp/iron_iso.vtp"
grep -q 'compressor="vtkLZ4DataCompressor"' "$tmp/iron_iso.vtp" || fail "xml_contour_lz4: no LZ4 compressor attribute"
expect_ok xml_sample_none "" "$bin" sample -f 'sphere()' -b -1 1 -1 1 -1 1 -d 8 --compressor none -o "$tmp/s_none.vti"
expect_usage xml_level_range "--level: must be an integer in \[1, 12\], got 13" "$bin" sample -f 'sphere()' -b -1 1 -1 1 -1 1 -d 8 --level 13 -o "$tmp/x.vti"
expect_usage xml_level_none "--level: there is no level without compression" "$bin" sample -f 'sphere()' -b -1 1 -1 1 -1 1 -d 8 --compressor none --level 3 -o "$tmp/x.vti"
expect_usage xml_compressor_bogus "--compressor: bogus not in" "$bin" sample -f 'sphere()' -b -1 1 -1 1 -1 1 -d 8 --compressor bogus -o "$tmp/x.vti"
expect_usage xml_compressor_legacy "--compressor: applies to VTK XML output \(.vti .vts .vtp .vtu\) only, not .*x.vtk" "$bin" contour "$tmp/iron_lz4.vti" -v 20 --compressor lz4 -o "$tmp/x.vtk"
expect_usage xml_level_ply "--level: applies to VTK XML output .* only, not .*x.ply" "$bin" decimate "$data/bunny.ply" -t 100 --level 3 -o "$tmp/x.ply"
expect_usage xml_convert_legacy "--level: applies to VTK XML \(.vti .vts .vtp .vtu\) and Draco output only" "$bin" convert "$data/bunny.ply" "$tmp/x.vtk" --level 3
expect_usage xml_convert_drc "--compressor: applies to VTK XML output only, not Draco" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --compressor lz4
expect_usage xml_convert_no_compress "--compressor and --no-compress exclude each other" "$bin" convert "$data/bunny.ply" "$tmp/x.vtp" --compressor lz4 --no-compress
expect_usage xml_convert_ascii "--level and --ascii exclude each other" "$bin" convert "$data/bunny.ply" "$tmp/x.vtp" --level 4 --ascii
expect_ok xml_convert_level "wrote" "$bin" convert "$data/bunny.ply" "$tmp/bunny9.vtp" --level 9
expect_usage xml_fit_none "--compressor" "$bin" fit "$data/bunny.ply" --primitive plane --compressor lz4
# --id-type: Int32 cell ids when they fit (the default) or Int64; the same mesh either way.
expect_ok xml_ids_auto "wrote" "$bin" convert "$data/bunny.ply" "$tmp/bunny_auto.vtp" --compressor none
expect_ok xml_ids_64 "wrote" "$bin" convert "$data/bunny.ply" "$tmp/bunny_64.vtp" --compressor none --id-type int64
expect_ok xml_ids_32 "wrote" "$bin" convert "$data/bunny.ply" "$tmp/bunny_32.vtp" --compressor none --id-type int32
grep -q 'type="Int32" Name="connectivity"' "$tmp/bunny_auto.vtp" || fail "xml_ids_auto: connectivity is not Int32"
grep -q 'type="Int64" Name="offsets"' "$tmp/bunny_64.vtp" || fail "xml_ids_64: offsets are not Int64"
cmp -s "$tmp/bunny_auto.vtp" "$tmp/bunny_32.vtp" || fail "xml_ids_32: differs from auto"
[ "$("$bin" info "$tmp/bunny_64.vtp" 2>&1 | grep -v bunny_64)" = "$("$bin" info "$tmp/bunny_auto.vtp" 2>&1 | grep -v bunny_auto)" ] || fail "xml_ids_same: info differs"
expect_ok xml_ids_roundtrip "wrote" "$bin" convert "$tmp/bunny_64.vtp" "$tmp/bunny_back.vtp" --compressor none
cmp -s "$tmp/bunny_auto.vtp" "$tmp/bunny_back.vtp" || fail "xml_ids_roundtrip: Int64 file converted back differs"
expect_usage xml_ids_bogus "--id-type: int16 not in" "$bin" convert "$data/bunny.ply" "$tmp/x.vtp" --id-type int16
expect_usage xml_ids_ply "--id-type: applies to VTK XML \(.vti .vts .vtp .vtu\) output only, not .*x.ply" "$bin" convert "$data/bunny.ply" "$tmp/x.ply" --id-type int64
expect_usage xml_ids_drc "--id-type: applies to VTK XML output only, not Draco" "$bin" convert "$data/bunny.ply" "$tmp/x.drc" --id-type int64
expect_usage xml_ids_legacy "--id-type: applies to VTK XML output \(.vti .vts .vtp .vtu\) only, not .*x.vtk" "$bin" decimate "$data/bunny.ply" -t 100 --id-type int32 -o "$tmp/x.vtk"

# ---- one form for every error, one exit code per kind (README "Exit status") ----
expect_usage no_subcommand "subcommand is required.*isoforge --help" "$bin"
expect_usage unknown_option "info: .*not expected: --bogus.*isoforge info --help" "$bin" info --bogus "$data/hello.vtk"
expect_usage missing_positional "contour: .*input is required" "$bin" contour -v 0 -o "$tmp/x.vtp"
expect_usage missing_option "sample: .*--output is required" "$bin" sample -f 'sphere()' -b 0 1 0 1 0 1
expect_usage bad_choice "--normals" "$bin" contour "$tmp/sphere.vti" -v 0 --normals bogus -o "$tmp/x.vtp"
expect_usage wrong_arity "--bounds" "$bin" sample -f 'sphere()' -b 0 1 0 1 -o "$tmp/x.vti"
expect_ok help_exit_0 "Exit status: 0 success" "$bin" --help
expect_ok version_exit_0 "^[0-9]+\.[0-9]+\.[0-9]+" "$bin" --version

if [ $failures -ne 0 ]; then echo "$failures CLI test(s) failed"; exit 1; fi
echo "all CLI tests passed"
