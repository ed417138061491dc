#!/usr/bin/env bash
# End-to-end tests of the isoforge command. Usage: cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_ok NAME REGEX CMD...: exit 0 and stdout+stderr matching REGEX (extended grep).
expect_ok() {
  local name=$1 regex=$2; shift 2
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ $rc -ne 0 ]; then fail "$name: exit $rc: $out"; return; fi
  if ! grep -Eq -- "$regex" <<<"$out"; then fail "$name: output does not match /$regex/:"$'\n'"$out"; fi
}

# expect_error NAME REGEX CMD...: non-zero exit, a one-line "isoforge: error:" message matching REGEX.
expect_error() {
  local name=$1 regex=$2; shift 2
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ $rc -eq 0 ]; then fail "$name: expected failure, got exit 0: $out"; return; fi
  if [ "$(wc -l <<<"$out")" -ne 1 ]; then fail "$name: error is not one line:"$'\n'"$out"; fi
  if ! grep -Eq -- "^isoforge: error: .*$regex" <<<"$out"; then fail "$name: message does not match /$regex/: $out"; fi
}

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
expect_error unknown_ext "unknown file extension '.xyzw'" "$bin" info "$data/../README.md.xyzw"
expect_error wrong_target "holds polygonal data only" "$bin" convert "$data/post.vtk" "$tmp/post.ply"
expect_error unwritable "cannot create" "$bin" convert "$data/hello.vtk" "$tmp/no/such/dir/h.vtp"
printf '# vtk DataFile Version 3.0\ntruncated\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n0 0 0\n' > "$tmp/trunc.vtk"
expect_error truncated "trunc.vtk" "$bin" info "$tmp/trunc.vtk"

# A failed conversion must not clobber an existing good output file.
cp "$tmp/fran.vtp" "$tmp/keep.vtp"
"$bin" convert "$tmp/trunc.vtk" "$tmp/keep.vtp" >/dev/null 2>&1 && fail "convert of a truncated file succeeded"
cmp -s "$tmp/fran.vtp" "$tmp/keep.vtp" || fail "a failed convert changed the existing output file"
ls -A "$tmp" | grep -q '\.tmp\.' && fail "temporary files left behind: $(ls -A "$tmp")"

# ---- help: every subcommand has examples ----
for sub in info convert; do
  expect_ok "help_$sub" "Examples:" "$bin" "$sub" --help
done
out=$("$bin" 2>&1); [ $? -ne 0 ] || fail "no subcommand should be an error"

if [ $failures -ne 0 ]; then echo "$failures CLI test(s) failed"; exit 1; fi
echo "all CLI tests passed"
