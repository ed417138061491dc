#!/usr/bin/env bash
# VTK XML reading and writing, isoforge against VTK 9.1 (python3-vtk9) in the same run, each
# operation a whole process as a user runs it (peers/vtk_xml_io.py is VTK's side):
#   - a 256^3 float32 volume (.vti, 64 MiB of values): a torus and a sphere sampled with
#     `isoforge sample` (a distance field, as `sample` and `distance` write);
#   - a 1M-triangle isosurface (.vtp: points, normals, connectivity): six spheres contoured;
# each with no compression, zlib and LZ4. Reading: `isoforge info FILE` against VTK's reader of
# the same file. Writing: `isoforge convert RAW OUT --compressor C` against VTK reading RAW and
# writing OUT (both read the same uncompressed RAW first); each side writes cell ids its default
# way (isoforge Int32 when they fit, VTK Int64), the surface's LZ4 also with both on Int64 and
# both on Int32. Best of REPEATS runs (wall and CPU
# seconds, bash's `time`); "VTK call": VTK's Update()/Write() alone, without Python's start-up
# and `import vtk`; MB/s of uncompressed array bytes; ratio = VTK time / isoforge time (whole
# processes). isoforge's read is `info`, which also computes every array's range.
# Usage: xml_io.sh ISOFORGE [THREADS=2] [REPEATS=3] [WORK_DIR=/tmp/isoforge_xml_io]
set -eu
bin=$(realpath "$1") threads=${2:-2} repeats=${3:-3} work=${4:-/tmp/isoforge_xml_io}
here=$(cd "$(dirname "$0")" && pwd)
peer="$here/peers/vtk_xml_io.py"
py=${PYTHON:-/usr/bin/python3}  # the python3 with the vtk module (python3-vtk9)
mkdir -p "$work"
export OMP_NUM_THREADS=$threads TBB_NUM_THREADS=$threads
iso() { "$bin" -q --threads "$threads" "$@"; }

# ---- inputs (kept between runs) ----
vol="$work/vol_raw.vti" surf="$work/surf_raw.vtp"
if [ ! -f "$vol" ]; then
  iso sample -f 'union(torus(R=0.6, r=0.2), sphere(center=[0.3,0.2,0.1], r=0.5))' \
      -b -1 1 -1 1 -1 1 -d 256 --compressor none -o "$vol"
fi
if [ ! -f "$surf" ]; then
  # Six concentric spheres of a 256^3 distance field: about a million triangles with normals.
  iso sample -f 'sphere(r=0)' -b -1 1 -1 1 -1 1 -d 256 --compressor none -o "$work/radial.vti"
  iso contour "$work/radial.vti" -v 0.2 0.35 0.5 0.65 0.8 0.95 --compressor none -o "$surf"
fi

# best WALL CPU CALL of REPEATS runs of a command: "wall cpu call" (seconds; CALL: the least
# number the command printed, the peer's time of the read/write call alone, else 0). With
# FRESH=FILE in the environment, FILE is removed before each run: a writer replacing the file of
# the run before would also pay for the kernel freeing that file's page cache.
best() {
  local bw=1e9 bc=1e9 bk=1e9 w u s k
  for _ in $(seq "$repeats"); do
    if [ -n "${FRESH:-}" ]; then rm -f "$FRESH"; fi
    # bash's own `time`: wall and CPU in milliseconds of the process it starts, nothing else
    # (/usr/bin/time counts hundredths, and timing it from `date` adds two processes' start).
    local TIMEFORMAT="%3R %3U %3S"
    if ! { time "$@" >"$work/out.txt" 2>"$work/err.txt"; } 2>"$work/time.txt"; then
      cat "$work/err.txt" >&2
      exit 1
    fi
    read -r w u s < "$work/time.txt"
    k=$(awk 'NR == 1 && $1 ~ /^[0-9.]+$/ { print $1 }' "$work/out.txt"); k=${k:-0}
    read -r bw bc bk < <(awk -v w="$w" -v c="$(awk -v u="$u" -v s="$s" 'BEGIN { print u + s }')" \
      -v k="$k" -v bw="$bw" -v bc="$bc" -v bk="$bk" \
      'BEGIN { print (w < bw ? w : bw), (c < bc ? c : bc), (k < bk ? k : bk) }')
  done
  echo "$bw $bc $bk"
}

# Megabytes of a file (the raw inputs: all arrays).
mb_of() { awk -v b="$(stat -c %s "$1")" 'BEGIN { printf "%.2f", b / 1e6 }'; }

# row DATA COMPRESSOR OP OURS_WALL OURS_CPU VTK_WALL VTK_CPU VTK_CALL MB SIZES
row() {
  awk -v d="$1" -v c="$2" -v op="$3" -v iw="$4" -v ic="$5" -v vw="$6" -v vc="$7" -v vk="$8" \
      -v mb="$9" -v sz="${10}" \
    'BEGIN { printf "| %s | %s | %s | %.3f (%.2f) | %.3f (%.2f) | %.2f | %.0f | %.0f | %.1f | %s |\n",
             d, c, op, iw, ic, vw, vc, vk, mb / iw, mb / vw, vw / iw, sz }'
}

printf "| data | compressor | op | isoforge s (cpu) | VTK s (cpu) | VTK call s | isoforge MB/s | VTK MB/s | ratio VTK/isoforge | size isoforge / VTK MB |\n"
printf "|---|---|---|---|---|---|---|---|---|---|\n"
for pair in "volume:$vol:vti" "surface:$surf:vtp"; do
  IFS=: read -r name raw ext <<<"$pair"
  mb=$(mb_of "$raw")
  cases="none zlib zlib10 lz4"
  # The surface's cell ids: isoforge writes Int32 when they fit, VTK Int64 unless told (the rows
  # above are each side's default); then LZ4 with each id type on both sides.
  [ "$name" = surface ] && cases="$cases lz4-ids64 lz4-ids32"
  for c in $cases; do
    ours="$work/${name}_$c.ours.$ext" theirs="$work/${name}_$c.vtk.$ext"
    opts=(--compressor "$c") vopts=("$c")
    [ "$c" = zlib10 ] && opts=(--compressor zlib --level 10) vopts=(zlib)
    [ "$c" = lz4-ids64 ] && opts=(--compressor lz4 --id-type int64) vopts=(lz4)
    [ "$c" = lz4-ids32 ] && opts=(--compressor lz4 --id-type int32) vopts=(lz4 ids32)
    # write (from the raw file; both sides read it first)
    read -r iw ic _ < <(FRESH=$ours best "$bin" -q --threads "$threads" convert "$raw" "$ours" "${opts[@]}")
    read -r vw vc vk < <(FRESH=$theirs best "$py" "$peer" write "$raw" "$theirs" "${vopts[@]}")
    row "$name" "$c" write "$iw" "$ic" "$vw" "$vc" "$vk" "$mb" "$(mb_of "$ours") / $(mb_of "$theirs")"
    "$py" "$peer" read "$ours" >/dev/null  # VTK reads what we wrote
    case $c in zlib10 | lz4-ids*) continue ;; esac
    # read VTK's file, both sides
    read -r rw rc _ < <(best "$bin" -q --threads "$threads" info "$theirs")
    read -r pw pc pk < <(best "$py" "$peer" read "$theirs")
    row "$name" "$c" "read" "$rw" "$rc" "$pw" "$pc" "$pk" "$mb" ""
  done
done
# Process start-up alone (python + import vtk; isoforge --version) for reference.
read -r sw _ _ < <(best "$py" -c "import vtk")
read -r bw _ _ < <(best "$bin" --version)
echo
echo "start-up: python3 + import vtk $sw s; isoforge $bw s. threads=$threads, best of $repeats."
