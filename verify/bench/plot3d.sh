#!/usr/bin/env bash
# PLOT3D reading as a user runs it, isoforge against VTK 9.1 (python3-vtk9) in the same run on
# the same files: an N^3 big-endian float32 grid and its solution (plot3d_make), read with the
# derived velocity and pressure.
#   info:    `isoforge info GRID --q Q` (streams the files) against VTK reading them and taking
#            every point array's range (peers/vtk_plot3d.py info);
#   convert: `isoforge convert GRID --q Q OUT.vts --compressor none` against VTK reading them and
#            writing the same uncompressed .vts.
# Each a whole process; best of REPEAT runs of the wall time, and the least peak resident memory
# (/usr/bin/time %M). Not part of ctest.
# Usage: plot3d.sh BUILD [N=256] [REPEAT=3] [WORK_DIR=/tmp/isoforge_plot3d]
#   (BUILD configured with -DISOFORGE_BUILD_BENCH=ON; WORK_DIR needs about 2.2 GB at N=256)
set -euo pipefail
build=$(cd "$1" && pwd) n=${2:-256} repeat=${3:-3} work=${4:-/tmp/isoforge_plot3d}
here=$(cd "$(dirname "$0")" && pwd)
py=${PYTHON:-/usr/bin/python3}
iso=$build/src/isoforge
mkdir -p "$work"
xyz=$work/grid_$n.xyz q=$work/grid_$n.q
[ -f "$xyz" ] && [ -f "$q" ] || "$build/verify/bench/plot3d_make" "$n" "$xyz" "$q"

# best CMD...: "WALL RSS_MB" (minimum wall seconds and minimum peak RSS over $repeat runs); the
# output files of a run are removed before the next.
best() {
  local w="" m="" out t
  for _ in $(seq "$repeat"); do
    rm -f "$work"/out_*.vts
    /usr/bin/time -o "$work/time.txt" -f '%e %M' "$@" > /dev/null 2>&1
    out=$(tail -n 1 "$work/time.txt")
    t=${out% *}
    if [ -z "$w" ] || [ "$(echo "$t < $w" | bc -l)" = 1 ]; then w=$t; fi
    if [ -z "$m" ] || [ "${out#* }" -lt "$m" ]; then m=${out#* }; fi
  done
  rm -f "$work"/out_*.vts
  echo "$w $((m / 1024))"
}

mb=$(( ($(stat -c %s "$xyz") + $(stat -c %s "$q")) / 1000000 ))
echo "| $n³ PLOT3D ($mb MB of files) | isoforge s | isoforge MB | VTK s | VTK MB | ratio |"
echo "|---|---|---|---|---|---|"
row() {  # row NAME "ISOFORGE CMD" "VTK CMD"
  local a b
  read -r ta ma <<< "$(best $2)"
  read -r tb mb_ <<< "$(best $3)"
  echo "| $1 | $ta | $ma | $tb | $mb_ | $(echo "scale=1; $tb / $ta" | bc -l)× |"
}
row info "$iso -q info $xyz --q $q" "$py $here/peers/vtk_plot3d.py info $xyz $q"
row "convert to .vts" "$iso -q convert $xyz --q $q $work/out_iso.vts --compressor none" \
    "$py $here/peers/vtk_plot3d.py convert $xyz $q $work/out_vtk.vts"
echo
echo "Peak RSS includes each process's start-up (python3 + import vtk: about 130 MB; isoforge: about 42 MB)."
echo "Load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)."
