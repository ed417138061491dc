#!/usr/bin/env bash
# Runs every fuzz target for a bounded time. The readers' seed corpora are made from data/ (plus
# small files the CLI writes); the function expression and VTK XML block decoder targets start
# from the seeds committed in tests/fuzz/corpus/<target>/ (read-only: new inputs go to the
# build's corpus). Usage: run.sh FUZZ_BUILD_DIR SECONDS; FUZZ_TARGETS="function ..." runs some.
set -euo pipefail
build=$1 seconds=${2:-20}
root=$(cd "$(dirname "$0")/../.." && pwd)
data=$root/data
corpus=$build/corpus
bin=$build/tests/fuzz

seed() {  # seed NAME FILE...: copy the first 64 KiB of each file into the corpus of NAME
  local name=$1; shift
  mkdir -p "$corpus/$name"
  for f in "$@"; do head -c 65536 "$f" > "$corpus/$name/$(basename "$f")"; done
}
seed vtk_legacy "$data"/hello.vtk "$data"/fran_cut.vtk "$data"/post.vtk "$data"/office.binary.vtk "$data"/blow.vtk "$data"/ironProt.vtk
seed vtk_xml "$data"/Torso.vtp
seed ply "$data"/bunny.ply
seed plot3d "$data"/combxyz.bin "$data"/combq.bin
seed nrrd "$data"/headsq/quarter.nhdr
seed metaimage "$data"/HeadMRVolume.mhd
mkdir -p "$corpus/off" "$corpus/vdb" "$corpus/drc" "$corpus/glb"
printf 'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n' > "$corpus/off/quad.off"
# Generated seeds: small XML, PLY, VDB, Draco and glTF files written by isoforge itself (Draco: a
# mesh with arrays by Edgebreaker and sequentially, a point cloud; glTF: each codec).
cli=$build/src/isoforge
if [ -x "$cli" ]; then
  "$cli" -q convert "$data/hello.vtk" "$corpus/vtk_xml/hello.vtp" || true
  "$cli" -q convert "$data/post.vtk" "$corpus/vtk_xml/post.vtu" --no-compress || true
  "$cli" -q convert "$data/hello.vtk" "$corpus/vtk_xml/hello_ascii.vtp" --ascii || true
  "$cli" -q convert "$data/hello.vtk" "$corpus/vtk_xml/hello_lz4.vtp" --compressor lz4 || true
  "$cli" -q convert "$data/post.vtk" "$corpus/vtk_xml/post_lz4.vtu" --compressor lz4 --level 9 || true
  "$cli" -q convert "$data/fran_cut.vtk" "$corpus/ply/fran.ply" || true
  "$cli" -q convert "$data/bunny.ply" "$corpus/ply/bunny_ascii.ply" --ascii && head -c 65536 "$corpus/ply/bunny_ascii.ply" > "$corpus/ply/bunny_ascii_head.ply" && rm "$corpus/ply/bunny_ascii.ply" || true
  # Ascii, mixed faces, a list among the vertex properties, an element skipped, a face property.
  printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty list uchar int tags\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement edge 1\nproperty int a\nproperty int b\nelement face 2\nproperty list uchar int vertex_indices\nproperty short material\nend_header\n0 0 0 0 1 2 3\n1 0 0 2 5 6 4 5 6\n0 1 0 1 7 8 9 10\n1 1 0 0 11 12 13\n0 0 1 0 14 15 16\n0 1\n3 0 1 2 -1\n4 1 3 2 4 7\n' > "$corpus/ply/mixed_ascii.ply"
  printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float q\nelement face 2\nproperty list uchar float texcoord\nproperty list uchar int vertex_indices\nproperty int texnumber\nend_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n6 0 0 1 0 1 1 3 0 1 2 0\n6 0 0 0.5 0.5 0 1 3 0 2 3 1\n' > "$corpus/ply/corner_texcoord.ply"
  "$cli" -q convert "$data/HeadMRVolume.mhd" "$corpus/vdb/head.vdb" || true
  "$cli" -q convert "$data/fran_cut.vtk" "$corpus/drc/fran.drc" --bits 12 || true
  "$cli" -q convert "$data/fran_cut.vtk" "$corpus/drc/fran_seq.drc" --sequential || true
  printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float s\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n' > "$corpus/drc/cloud.ply"
  "$cli" -q convert "$corpus/drc/cloud.ply" "$corpus/drc/cloud.drc" || true
  rm -f "$corpus/drc/cloud.ply"
  "$cli" -q convert "$data/hello.vtk" "$corpus/glb/hello.glb" --codec none || true
  "$cli" -q convert "$data/fran_cut.vtk" "$corpus/glb/fran_meshopt.glb" --codec meshopt || true
  "$cli" -q convert "$data/fran_cut.vtk" "$corpus/glb/fran_draco.glb" --codec draco || true
fi

status=0
targets=${FUZZ_TARGETS:-vtk_legacy vtk_xml ply off plot3d nrrd metaimage vdb drc glb function vtk_xml_block}
for target in $targets; do
  echo "== fuzz_$target for ${seconds}s"
  mkdir -p "$build/crashes/$target" "$corpus/$target"
  extra=(-max_len=65536)
  timeout=10
  if [ "$target" = function ]; then
    extra=(-max_len=4096 -dict="$root/tests/fuzz/function.dict")
  fi
  # Draco 1.5.5's texture-coordinate prediction decoder loops over a 32-bit count read from the
  # stream before it can fail: up to 2^31 cheap iterations (~10 s, 256 MB), no crash. Such a
  # slow input is Draco's, not isoforge's (docs/formats.md, "Draco").
  if [ "$target" = drc ] || [ "$target" = glb ]; then timeout=40; fi
  seeds=()
  if [ -d "$root/tests/fuzz/corpus/$target" ]; then seeds=("$root/tests/fuzz/corpus/$target"); fi
  if ! "$bin/fuzz_$target" -max_total_time="$seconds" -timeout=$timeout -rss_limit_mb=2048 \
      "${extra[@]}" -print_final_stats=1 -artifact_prefix="$build/crashes/$target/" \
      "$corpus/$target" "${seeds[@]}" 2>"$build/fuzz_$target.log"; then
    echo "fuzz_$target FAILED; log tail:"; tail -40 "$build/fuzz_$target.log"; status=1
  else
    grep -E "stat::number_of_executed_units|cov:" "$build/fuzz_$target.log" | tail -2
  fi
done
exit $status
