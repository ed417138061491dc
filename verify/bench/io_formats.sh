#!/usr/bin/env bash
# Reading and writing of every format isoforge writes and VTK reads, and end-to-end pipelines,
# isoforge against VTK 9.1 (python3-vtk9) in the same run, each operation a whole process as a
# user runs it (peers/vtk_formats.py is VTK's side). Issue #16.
#   Inputs (made once with isoforge, kept in WORK_DIR): float32 volumes of SIZES^3 (a torus and
#   a sphere sampled with `isoforge sample`, as xml_io.sh) and the surface of xml_io.sh (six
#   spheres contoured, about 1.46M triangles) with gradient normals; converted with
#   `isoforge convert` to every format: volume .vti (none, zlib, lz4), legacy binary .vtk;
#   surface .vtp (none, zlib, lz4), legacy binary .vtk, binary .ply, .glb (plain, meshopt and
#   Draco; VTK 9.1's vtkGLTFReader reads the plain one, and writes .gltf + .bin, not .glb; the
#   writing row times that). isoforge writes neither
#   NRRD nor MetaImage (the table says so, with its error): the .mhd (+ .raw) read here is
#   VTK's (vtkMetaImageWriter, uncompressed) and the .nrrd is a raw attached NRRD made by this
#   script (a header before the bytes of that .raw).
#   READ: `isoforge info FILE` (which also computes every array's range; in one streaming pass
#   but for Draco and ascii PLY) against VTK's reader.
#   WRITE: `isoforge convert RAW OUT` against VTK reading RAW (the uncompressed .vti/.vtp) and
#   writing OUT with its writer; each output is then read by the other side (VTK reads ours,
#   `isoforge info` reads VTK's): a failure is printed in the row, and so are arrays lost.
#   PIPELINE: end to end with each side's defaults (both write zlib; VTK at level 5 with base64
#   appended data, isoforge level 3 raw appended data).
# Best of REPEATS runs (/usr/bin/time): wall and CPU seconds are each the minimum over the runs;
# "VTK call": the peer's Update()/Write()/pipeline alone, without Python's start-up and
# `import vtk` (the least over the runs); max RSS: the minimum over the runs of the peak
# resident memory (%M) of the whole process, in MB. MB: the uncompressed array bytes (the size of
# the uncompressed .vti/.vtp input); MB/s = MB / wall seconds; ratio = VTK wall / isoforge wall;
# RSS/MB: max RSS over the array bytes. Sizes in MB (1e6 bytes); VTK's .mhd counts its .raw.
# VTK runs with vtkSMPTools at THREADS threads, except the distance pipeline (1 thread: VTK 9.1's
# vtkImplicitPolyDataDistance is not thread-safe under vtkSampleFunction, 2 threads give wrong
# values). The NRRD header, the contour/sample/distance settings: see below and the peer.
# Usage: io_formats.sh ISOFORGE [THREADS=2] [REPEATS=3] [WORK_DIR=/tmp/isoforge_io_formats]
#                      [SIZES="256 512"]
#   e.g. verify/bench/io_formats.sh build/src/isoforge 2 3 > table.md   (11 min on 2 busy cores;
#   WORK_DIR needs about 6 GB for SIZES="256 512"; its inputs are kept for the next run)
set -eu
bin=$(realpath "$1") threads=${2:-2} repeats=${3:-3} work=${4:-/tmp/isoforge_io_formats}
sizes=${5:-256 512}
here=$(cd "$(dirname "$0")" && pwd)
peer="$here/peers/vtk_formats.py"
py=${PYTHON:-/usr/bin/python3}  # the python3 with the vtk module (python3-vtk9)
mkdir -p "$work"
# A copy of isoforge and its library: a rebuild during the run can neither change nor break it.
snap="$work/isoforge_copy" lib=$(ldd "$bin" | awk '$1 ~ /^libisoforge/ { print $3 }')
mkdir -p "$snap" && cp "$bin" "$snap/isoforge" && { [ -z "$lib" ] || cp -L "$lib" "$snap/"; }
built=$(date -r "${lib:-$bin}" '+%F %T')
export LD_LIBRARY_PATH="$snap${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
bin="$snap/isoforge"
"$bin" --version >/dev/null || { echo "the copy of $1 does not run (being rebuilt?)" >&2; exit 1; }
export OMP_NUM_THREADS=$threads TBB_NUM_THREADS=$threads VTK_THREADS=$threads
iso() { "$bin" -q --threads "$threads" "$@"; }
vtkpy() { "$py" "$peer" "$@"; }
function='union(torus(R=0.6, r=0.2), sphere(center=[0.3,0.2,0.1], r=0.5))'
small=${sizes%% *}  # the first size: the pipelines' volume
# Disk: per size, five uncompressed copies of the volume and two compressed kept as inputs, and
# the two outputs of a write (removed after each row); 1 GB for the surface and the rest.
need=$(awk -v s="$sizes" 'BEGIN { split(s, n, " "); for (i in n) t += 9 * 4 * n[i] ^ 3; print int(t / 1e6) + 1000 }')
avail=$(df -Pm "$work" | awk 'NR == 2 { print $4 }')
[ "$avail" -ge "$need" ] || { echo "$work: $avail MB free, about $need MB needed" >&2; exit 1; }
note() { echo "io_formats: $*" >&2; }

# ---- inputs (kept between runs) ----
for n in $sizes; do
  [ -f "$work/vol_$n.vti" ] ||
    iso sample -f "$function" -b -1 1 -1 1 -1 1 -d "$n" --compressor none -o "$work/vol_$n.vti"
done
if [ ! -f "$work/surf.vtp" ]; then
  # Six concentric spheres of a 256^3 distance field: about 1.46M triangles with normals.
  iso sample -f 'sphere(r=0)' -b -1 1 -1 1 -1 1 -d 256 --compressor none -o "$work/radial.vti"
  iso contour "$work/radial.vti" -v 0.2 0.35 0.5 0.65 0.8 0.95 --normals gradient \
      --compressor none -o "$work/surf.vtp"
  rm -f "$work/radial.vti"
fi
# converted(NAME, FILE): FILE made from the raw input by `isoforge convert` (vti/vtp: compressor
# from NAME), VTK (mhd) or this script (nrrd), once.
converted() {
  local raw=$1 out=$2 c
  [ -f "$out" ] && return 0
  case "$out" in
    *_zlib.vti | *_zlib.vtp | *_lz4.vti | *_lz4.vtp)
      c=${out##*_}; iso convert "$raw" "$out" --compressor "${c%%.*}" ;;
    *_meshopt.glb | *_draco.glb) c=${out##*_}; iso convert "$raw" "$out" --codec "${c%.glb}" ;;
    *.glb) iso convert "$raw" "$out" --codec none ;;
    *.mhd) vtkpy write "$raw" "$out" mhd >/dev/null ;;
    *.nrrd)
      converted "$raw" "${out%.nrrd}.mhd"
      # A raw attached NRRD: the header, then the bytes of VTK's .raw (x fastest, little endian).
      awk -v f="$(iso info "$raw")" 'BEGIN {
            n = split(f, l, "\n")
            for (i = 1; i <= n; i++) {
              split(l[i], w, " +")
              if (w[1] == "dimensions:") { d = w[2] " " w[4] " " w[6] }
              if (w[1] == "origin:") { o = w[2] "," w[3] "," w[4] }
              if (w[1] == "spacing:") { sx = w[2]; sy = w[3]; sz = w[4] }
            }
            printf "NRRD0004\n# isoforge io_formats.sh\ntype: float\ndimension: 3\n"
            printf "space dimension: 3\nsizes: %s\n", d
            printf "space directions: (%s,0,0) (0,%s,0) (0,0,%s)\n", sx, sy, sz
            printf "space origin: (%s)\nendian: little\nencoding: raw\n\n", o
          }' >"$out.tmp"
      cat "${out%.nrrd}.raw" >>"$out.tmp" && mv "$out.tmp" "$out" ;;
    *) iso convert "$raw" "$out" ;;
  esac
}

# measure CMD...: REPEATS runs; prints "wall cpu call rss_mb" (each the least over the runs;
# call: the number the command printed first, else 0), or "FAIL message" (the last line the
# command printed on stderr) if a run failed. The last run's stdout stays in $work/out.txt.
measure() {
  : >"$work/runs.txt"
  for _ in $(seq "$repeats"); do
    # A write makes a new file, as a user's does: replacing an existing one would add the
    # kernel's freeing of the old file's pages to the run (0.3-0.5 s for 500 MB here).
    [ -z "${FRESH:-}" ] || rm -f $FRESH
    if ! /usr/bin/time -f "%e %U %S %M" -o "$work/time.txt" "$@" >"$work/out.txt" 2>"$work/err.txt"
    then
      # (the last line without terminal colour codes: VTK's warnings carry them)
      echo "FAIL $(sed 's/\x1b\[[0-9;]*m//g' "$work/err.txt" | grep -v '^ *$' | tail -n 1 | tr '|' '/')"
      return 0
    fi
    echo "$(tail -n 1 "$work/time.txt") $(awk 'NR == 1 { print ($1 ~ /^[0-9.]+$/ ? $1 : 0) }' \
      "$work/out.txt")" >>"$work/runs.txt"
  done
  awk 'NR == 1 { w = $1; c = $2 + $3; m = $4; k = $5 }
       { if ($1 < w) w = $1; if ($2 + $3 < c) c = $2 + $3; if ($4 < m) m = $4; if ($5 < k) k = $5 }
       END { printf "%s %.2f %s %.0f\n", w, c, k == "" ? 0 : k, m * 1024 / 1e6 }' "$work/runs.txt"
}

# Megabytes of files (an .mhd with its .raw, a .gltf with its .bin).
mb_of() {
  local b=0 f
  for f in "$@"; do
    b=$((b + $(stat -c %s "$f")))
    case "$f" in *.mhd) [ -f "${f%.mhd}.raw" ] && b=$((b + $(stat -c %s "${f%.mhd}.raw"))) ;; esac
    case "$f" in *.gltf) [ -f "${f%.gltf}.bin" ] && b=$((b + $(stat -c %s "${f%.gltf}.bin"))) ;; esac
  done
  awk -v b="$b" 'BEGIN { printf "%.1f", b / 1e6 }'
}
# Array names isoforge reads from a file (sorted, comma-separated), or "FAIL message".
iso_arrays() {
  local out
  if out=$(iso info "$1" 2>&1); then
    echo "$out" | sed -n "s/^  '\([^']*\)'.*/\1/p" | sort | paste -sd, -
  else
    echo "FAIL $(echo "$out" | tail -n 1 | tr '|' '/')"
  fi
}
iso_points() { iso info "$1" | awk '$1 == "points:" { print $2 }'; }
# Array names and points VTK reads from a file: "arrays points", or "FAIL message".
vtk_arrays() {
  local out
  if out=$(vtkpy read "$1" 2>&1 >"$work/vtk_read.txt"); then
    awk 'NR == 2 { n = split($6, a, ","); s = ""
                   for (i = 1; i <= n; i++) print a[i] }' "$work/vtk_read.txt" | sort | paste -sd, -
  else
    echo "FAIL $(echo "$out" | grep -v '^ *$' | tail -n 1 | tr '|' '/')"
  fi
}
vtk_points() { awk 'NR == 2 { print $2 }' "$work/vtk_read.txt"; }
# check WHO FILE EXPECTED_ARRAYS EXPECTED_POINTS: "ok", "ok, lacks A,B", "n points (expected m)"
# or "FAIL message" for WHO (iso|vtk) reading FILE.
check() {
  local who=$1 file=$2 want=$3 np=$4 got pts lost
  if [ "$who" = iso ]; then got=$(iso_arrays "$file"); else got=$(vtk_arrays "$file"); fi
  case "$got" in FAIL*) echo "$got"; return 0 ;; esac
  if [ "$who" = iso ]; then pts=$(iso_points "$file"); else pts=$(vtk_points); fi
  [ "$pts" = "$np" ] || { echo "$pts points (expected $np)"; return 0; }
  lost=$(comm -23 <(tr , '\n' <<<"$want" | sort) <(tr , '\n' <<<"$got" | sort) | paste -sd, -)
  if [ -n "$lost" ]; then echo "ok, lacks $lost (has ${got:--})"; else echo ok; fi
}

# fmt_side "wall cpu call rss" -> "wall (cpu)" or the failure
side() { case "$1" in FAIL*) echo "${1#FAIL }" ;; *) awk '{ printf "%.2f (%.2f)", $1, $2 }' <<<"$1" ;; esac; }
field() { case "$1" in FAIL*) echo "—" ;; *) awk -v i="$2" '{ print $i }' <<<"$1" ;; esac; }
# rate MB "wall ..." -> MB/s; ratio A B -> wall(B) / wall(A)
rate() { case "$2" in FAIL*) echo "—" ;; *) awk -v mb="$1" '{ printf "%.0f", mb / $1 }' <<<"$2" ;; esac; }
ratio() {
  case "$1$2" in *FAIL*) echo "—" ;;
    *) awk -v a="$(field "$1" 1)" -v b="$(field "$2" 1)" 'BEGIN { printf "%.1f", b / a }' ;; esac
}
rss() { case "$1" in FAIL*) echo "—" ;; *) awk '{ print $4 }' <<<"$1" ;; esac; }
per_mb() { case "$2" in FAIL*) echo "—" ;; *) awk -v mb="$1" '{ printf "%.2f", $4 / mb }' <<<"$2" ;; esac; }

# ---- the data sets: name, raw input, formats (name:file suffix) ----
datasets=""
for n in $sizes; do datasets="$datasets volume_$n"; done
datasets="$datasets surface"
raw_of() { case "$1" in volume_*) echo "$work/vol_${1#volume_}.vti" ;; *) echo "$work/surf.vtp" ;; esac; }
formats_of() {
  case "$1" in
    volume_*) echo "vti-none:.vti vti-zlib:_zlib.vti vti-lz4:_lz4.vti vtk-binary:.vtk nrrd-raw:.nrrd mhd-raw:.mhd" ;;
    *) echo "vtp-none:.vtp vtp-zlib:_zlib.vtp vtp-lz4:_lz4.vtp vtk-binary:.vtk ply-binary:.ply glb-none:.glb glb-meshopt:_meshopt.glb glb-draco:_draco.glb" ;;
  esac
}

echo "## Reading: \`isoforge info FILE\` against VTK's reader (threads=$threads, best of $repeats)"
echo
echo "| data | format | MB | isoforge s (cpu) | VTK s (cpu) | VTK call s | isoforge MB/s | VTK MB/s | ratio VTK/isoforge | max RSS MB isoforge / VTK | RSS/MB isoforge / VTK | file MB |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for d in $datasets; do
  raw=$(raw_of "$d") base=$(raw_of "$d"); base=${base%.vt?}
  mb=$(mb_of "$raw")
  for f in $(formats_of "$d"); do
    name=${f%%:*} file=$base${f#*:}
    note "read $d $name"
    converted "$raw" "$file"
    i=$(measure "$bin" -q --threads "$threads" info "$file")
    v=$(measure "$py" "$peer" read "$file")
    echo "| $d | $name | $mb | $(side "$i") | $(side "$v") | $(field "$v" 3) | $(rate "$mb" "$i") | $(rate "$mb" "$v") | $(ratio "$i" "$v") | $(rss "$i") / $(rss "$v") | $(per_mb "$mb" "$i") / $(per_mb "$mb" "$v") | $(mb_of "$file") |"
  done
done

echo
echo "## Writing: \`isoforge convert RAW OUT\` against VTK reading RAW and writing OUT"
echo
echo "RAW: the uncompressed .vti/.vtp. VTK's writers: vtkXML*Writer (appended raw, UInt64 headers, its default level 5), vtkStructuredPointsWriter/vtkPolyDataWriter binary (VTK 9.1 writes legacy version 5.1; isoforge 4.2), vtkPLYWriter binary, vtkMetaImageWriter uncompressed. Check: VTK reading isoforge's file / isoforge reading VTK's file (points and arrays compared with RAW's)."
echo
echo "| data | format | MB | isoforge s (cpu) | VTK s (cpu) | VTK call s | isoforge MB/s | VTK MB/s | ratio VTK/isoforge | max RSS MB isoforge / VTK | size MB isoforge / VTK | VTK reads isoforge's | isoforge reads VTK's |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for d in $datasets; do
  raw=$(raw_of "$d")
  mb=$(mb_of "$raw") want=$(iso_arrays "$raw") np=$(iso_points "$raw")
  for f in $(formats_of "$d"); do
    name=${f%%:*} suffix=${f#*:}
    note "write $d $name"
    ours="$work/w_ours$suffix" theirs="$work/w_vtk$suffix"
    case "$name" in
      glb-none) opts=(--codec none) vfmt=(gltf) theirs="$work/w_vtk.gltf" ;;  # VTK: .gltf + .bin
      glb-*) opts=(--codec "${name#glb-}") vfmt=() ;;
      *-zlib | *-lz4 | *-none) opts=(--compressor "${name#*-}") vfmt=(xml "${name#*-}") ;;
      vtk-binary) opts=() vfmt=(legacy) ;;
      ply-binary) opts=() vfmt=(ply) ;;
      mhd-raw) opts=() vfmt=(mhd) ;;
      nrrd-raw) opts=() vfmt=() ;;  # VTK has no NRRD writer
    esac
    i=$(FRESH="$ours ${ours%.mhd}.raw" measure "$bin" -q --threads "$threads" convert "$raw" "$ours" "${opts[@]}")
    if [ ${#vfmt[@]} -gt 0 ]; then
      v=$(FRESH="$theirs ${theirs%.mhd}.raw ${theirs%.gltf}.bin" measure "$py" "$peer" write "$raw" "$theirs" "${vfmt[@]}")
    elif [ "$name" = nrrd-raw ]; then
      v="FAIL VTK 9.1 has no NRRD writer"
    else
      v="FAIL VTK 9.1 writes neither glTF compression extension"
    fi
    case "$i" in FAIL*) so="—" c1="${i#FAIL }" ;;
      *) so=$(mb_of "$ours") c1=$(check vtk "$ours" "$want" "$np") ;; esac
    case "$v" in FAIL*) sv="—" c2="—" ;;
      *) sv=$(mb_of "$theirs") c2=$(check iso "$theirs" "$want" "$np") ;; esac
    case "$i" in FAIL*) i_side="cannot write" ;; *) i_side=$(side "$i") ;; esac
    echo "| $d | $name | $mb | $i_side | $(side "$v") | $(field "$v" 3) | $(rate "$mb" "$i") | $(rate "$mb" "$v") | $(ratio "$i" "$v") | $(rss "$i") / $(rss "$v") | $so / $sv | $c1 | $c2 |"
    rm -f "$ours" "$theirs" "${ours%.mhd}.raw" "${theirs%.mhd}.raw" "${theirs%.gltf}.bin"
  done
done

echo
echo "## Pipelines, end to end (each side's defaults unless said)"
echo
echo "| pipeline | isoforge command | isoforge s (cpu) | VTK s (cpu) | VTK call s | ratio VTK/isoforge | max RSS MB isoforge / VTK | output MB isoforge / VTK | outputs isoforge / VTK |"
echo "|---|---|---|---|---|---|---|---|---|"
# pipe NAME "ISOFORGE ARGS" OURS THEIRS VTK_PEER_ARGS...: one row (outputs: points of each).
pipe() {
  local name=$1 args=$2 ours=$3 theirs=$4 i v so sv po pv shown rep="sample -f '$function' "
  shift 4
  note "pipeline $name"
  local out=(-o "$ours")  # convert: the output is positional
  [ "${args%% *}" = convert ] && out=("$ours")
  shown="isoforge ${args/#sample /$rep} ${out[*]/#$work\//}"
  # shellcheck disable=SC2086  # ARGS is a word list (the function expression is passed apart)
  if [ "${args%% *}" = sample ]; then
    i=$(measure "$bin" -q --threads "$threads" sample -f "$function" ${args#sample } "${out[@]}")
  else
    i=$(measure "$bin" -q --threads "$threads" $args "${out[@]}")
  fi
  v=$(measure "$@")
  pv=$(case "$v" in FAIL*) echo "—" ;; *) awk 'NR == 2 { print $2 " pts" }' "$work/out.txt" ;; esac)
  case "$i" in FAIL*) so="—" po="—" ;; *) so=$(mb_of "$ours") po="$(iso_points "$ours") pts" ;; esac
  case "$v" in FAIL*) sv="—" ;; *) sv=$(mb_of "$theirs") ;; esac
  echo "| $name | \`$shown\` | $(side "$i") | $(side "$v") | $(field "$v" 3) | $(ratio "$i" "$v") | $(rss "$i") / $(rss "$v") | $so / $sv | $po / $pv$extra |"
}
cd "$work"  # the commands in the table name the inputs relative to WORK_DIR
src="$work/vol_${small}_zlib.vti"
converted "$work/vol_$small.vti" "$src"
extra=""
pipe "contour ${small}³ zlib .vti at 0, no normals (isoforge's default; VTK ComputeNormalsOff)" \
  "contour vol_${small}_zlib.vti -v 0" "$work/p_ours.vtp" "$work/p_vtk.vtp" \
  "$py" "$peer" pipeline contour "$src" "$work/p_vtk.vtp" 0 nonormals
pipe "contour ${small}³ zlib .vti at 0, gradient normals (VTK's default)" \
  "contour vol_${small}_zlib.vti -v 0 --normals gradient" "$work/p_ours.vtp" "$work/p_vtk.vtp" \
  "$py" "$peer" pipeline contour "$src" "$work/p_vtk.vtp" 0 normals
extra=" (VTK: algebraic values, same zero set)"
pipe "sample torus ∪ sphere at ${small}³ to .vti (VTK: vtkSuperquadric ∪ vtkSphere)" \
  "sample -b -1 1 -1 1 -1 1 -d $small" "$work/p_ours.vti" "$work/p_vtk.vti" \
  "$py" "$peer" pipeline sample "$work/p_vtk.vti" "$small"
extra=""
# Distance: signed and exact at every sample on both sides (-m 2 exceeds every distance in the
# box), so that the fields are equal; VTK: vtkImplicitPolyDataDistance in vtkSampleFunction, on
# 1 thread (see above). 64^3 keeps VTK under half a minute.
converted "$work/surf.vtp" "$work/surf.ply"
dn=64
row=$(pipe "signed distance of the surface (.ply) at ${dn}³ (VTK: 1 thread)" \
  "distance surf.ply --signed -m 2 -d $dn -b -1 1 -1 1 -1 1" "$work/p_ours.vti" "$work/p_vtk.vti" \
  env VTK_THREADS=1 "$py" "$peer" pipeline distance "$work/surf.ply" "$work/p_vtk.vti" "$dn")
diff=$(vtkpy compare "$work/p_ours.vti" "$work/p_vtk.vti" 2>&1 | tail -n 1 | tr '|' '/') || true
echo "${row% |}; max abs difference of the fields: $diff |"
for d in "volume_$small" surface; do
  raw=$(raw_of "$d") base=${raw%.vt?} ext=${raw##*.}
  for f in $(formats_of "$d"); do
    name=${f%%:*} file=$base${f#*:}
    [ -f "$file" ] || continue
    pipe "convert $d $name to .$ext" "convert $(basename "$file")" \
      "$work/p_ours.$ext" "$work/p_vtk.$ext" "$py" "$peer" pipeline convert "$file" "$work/p_vtk.$ext"
  done
done
rm -f "$work"/p_ours.* "$work"/p_vtk.*

# Process start-up alone (python + import vtk; isoforge --version) for reference.
s=$(measure "$py" -c "import vtk") b=$(measure "$bin" --version)
echo
echo "start-up: python3 + import vtk $(field "$s" 1) s, $(rss "$s") MB; isoforge $(field "$b" 1) s, $(rss "$b") MB. threads=$threads, best of $repeats; max RSS: the least over the runs. isoforge: $("$bin" --version | head -n 1), built $built; VTK $("$py" -c 'import vtk; print(vtk.vtkVersion.GetVTKVersion())'). Load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)."
