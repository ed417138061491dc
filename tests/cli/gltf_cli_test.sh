#!/usr/bin/env bash
# End-to-end tests of glTF output (isoforge convert ... OUT.glb) and of isoforge view: exit
# codes, messages, the files (every .glb checked by the Khronos validator) and the HTTP server.
# Usage: gltf_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR NODE VALIDATE_MJS
set -u
bin=$1 data=$2 tmp=$3 node=$4 validate=$5
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"

if [ -z "$node" ] || ! [ -x "$node" ]; then
  echo "FAIL: node (Node.js) not found: the glTF validator needs it (make deps)"; exit 1
fi

valid() {  # valid FILE: 0 errors from the Khronos validator
  local out
  out=$("$node" "$validate" "$1" 2>&1) || fail "validator on $1: $out"
  grep -q ": 0 errors" <<<"$out" || fail "validator on $1: $out"
}

# ---- convert to .glb with each codec; read back with info; validate ----
# The default codec is Draco: its measured errors are printed.
expect_ok glb_default "draco Points: 11 bits" "$bin" convert "$data/fran_cut.vtk" "$tmp/fran.glb"
expect_ok glb_default_back "cells: 4224 \(4224 triangle\)" "$bin" info "$tmp/fran.glb"
valid "$tmp/fran.glb"
expect_ok glb_none "wrote" "$bin" convert "$data/bunny.ply" "$tmp/bunny_none.glb" --codec none
expect_ok glb_meshopt "wrote .*bunny_meshopt.glb \(1 mesh, 35947 points, 69451 triangles\): [0-9]+ bytes" "$bin" convert "$data/bunny.ply" "$tmp/bunny_meshopt.glb" --codec meshopt
expect_ok glb_meshopt_back "cells: 69451 \(69451 triangle\)" "$bin" info "$tmp/bunny_meshopt.glb"
valid "$tmp/bunny_none.glb"
valid "$tmp/bunny_meshopt.glb"
[ "$(stat -c %s "$tmp/bunny_meshopt.glb")" -lt "$(stat -c %s "$tmp/bunny_none.glb")" ] ||
  fail "meshopt file is not smaller than the plain one"
# Lines (hello: 15 polylines) as a LINES primitive, quads (Torso) triangulated.
expect_ok glb_lines "wrote" "$bin" convert "$data/hello.vtk" "$tmp/hello.glb"
expect_ok glb_lines_back "points: 22" "$bin" info "$tmp/hello.glb"
valid "$tmp/hello.glb"
expect_ok glb_quads "wrote" "$bin" convert "$data/Torso.vtp" "$tmp/torso.glb" --codec meshopt
expect_ok glb_quads_back "cells: 23762 \(23762 triangle\)" "$bin" info "$tmp/torso.glb"  # 1134 + 2 * 11314
valid "$tmp/torso.glb"
# Draco with an error budget (relative to the diagonal), as for .drc; the budget is met.
expect_ok glb_draco_budget "draco Points: .*measured max error .* \(budget " "$bin" convert "$data/bunny.ply" "$tmp/bunny_draco.glb" --codec draco --max-error-rel 1e-4
valid "$tmp/bunny_draco.glb"
expect_ok glb_draco_back "cells: 69451 \(69451 triangle\)" "$bin" info "$tmp/bunny_draco.glb"
[ "$(stat -c %s "$tmp/bunny_draco.glb")" -lt "$(stat -c %s "$tmp/bunny_meshopt.glb")" ] ||
  fail "Draco file is not smaller than the meshopt one"
# Colours from a colour map: COLOR_0 (read back as 'Colors') and the legend.
expect_ok glb_color_by "coloured by 'intensity' \(plasma, range 0 .. 0.5\)" "$bin" convert "$data/bunny.ply" "$tmp/bunny_color.glb" --color-by intensity --colormap plasma --codec none
expect_ok glb_color_back "'Colors' +UInt8 +x3" "$bin" info "$tmp/bunny_color.glb"
valid "$tmp/bunny_color.glb"
# .glb back to .vtp keeps the points.
expect_ok glb_to_vtp "wrote .*\(35947 points, 69451 cells\)" "$bin" convert "$tmp/bunny_meshopt.glb" "$tmp/bunny_back.vtp"

# ---- errors ----
expect_fail 2 codec_not_glb "--codec: applies to glTF output \(.glb\) only" "$bin" convert "$data/bunny.ply" "$tmp/x.vtp" --codec meshopt
expect_fail 2 codec_bogus "--codec: bogus not in" "$bin" convert "$data/bunny.ply" "$tmp/x.glb" --codec bogus
expect_fail 2 glb_bits_meshopt "--bits: applies to Draco output \(.drc, or .glb with the draco codec\) only" "$bin" convert "$data/bunny.ply" "$tmp/x.glb" --codec meshopt --bits 12
expect_fail 1 glb_volume "glTF holds polygonal data only" "$bin" convert "$data/ironProt.vtk" "$tmp/x.glb"
printf 'glTF\002\000\000\000\377\000\000\000\010\000\000\000JSON' > "$tmp/trunc.glb"
expect_fail 1 glb_truncated "trunc.glb: byte 8: truncated" "$bin" info "$tmp/trunc.glb"
printf 'not a glb at all' > "$tmp/text.glb"
expect_fail 1 glb_magic "text.glb: byte 0: not a binary glTF" "$bin" info "$tmp/text.glb"
expect_fail 2 view_port "--port: must be an integer in \[0, 65535\], got 70000" "$bin" view "$tmp/fran.glb" --port 70000
expect_fail 2 view_port_negative "--port" "$bin" view "$tmp/fran.glb" --port -1
expect_fail 2 view_codec "--codec: bogus not in" "$bin" view "$tmp/fran.glb" --codec bogus
expect_fail 1 view_missing "nosuch.vtp" "$bin" view "$tmp/nosuch.vtp"
expect_fail 1 view_volume "view: .*ironProt.vtk is image data; only polygonal data can be shown" "$bin" view "$data/ironProt.vtk"
expect_fail 1 view_bad_glb "text.glb: byte 0: not a binary glTF" "$bin" view "$tmp/text.glb"
expect_fail 2 view_nothing "files is required" "$bin" view
expect_fail 2 view_for_zero "--for: must be a finite number > 0" "$bin" view "$tmp/fran.glb" --for 0
expect_ok view_for "stopped after 0 request" "$bin" view "$tmp/fran.glb" --for 0.5

# ---- view: serves the page and the files, only those, and stops on SIGINT ----
# http GET PATH: the raw response (status line, headers, body) from the server on $port.
http() {
  local method=${2:-GET}
  exec 3<>"/dev/tcp/127.0.0.1/$port" || return 1
  printf '%s %s HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n' "$method" "$1" >&3
  cat <&3
  exec 3<&-
}
export TMPDIR="$tmp/viewtmp" && mkdir -p "$TMPDIR"
"$bin" view "$tmp/fran.glb" "$data/bunny.ply" --port 0 > "$tmp/view.out" 2> "$tmp/view.err" &
pid=$!
for _ in $(seq 100); do grep -q "^http://" "$tmp/view.out" && break; sleep 0.1; done
url=$(head -1 "$tmp/view.out")
port=$(sed -E 's|^http://127\.0\.0\.1:([0-9]+)/$|\1|' <<<"$url")
if ! [[ "$port" =~ ^[0-9]+$ ]]; then
  fail "view printed no URL: $(cat "$tmp/view.out" "$tmp/view.err")"
else
  [ "$(ls "$TMPDIR" | wc -l)" -eq 1 ] || fail "view made no temporary directory for the converted bunny"
  r=$(http /); grep -q "^HTTP/1.1 200 OK" <<<"$r" && grep -q "isoforge viewer" <<<"$r" || fail "GET / : $r"
  r=$(http /files.json)
  grep -q '\[{"name":"fran.glb","url":"files/0/fran.glb"},{"name":"bunny.glb","url":"files/1/bunny.glb"}\]' <<<"$r" ||
    fail "files.json: $r"
  r=$(http /files/1/bunny.glb | head -c 300 | tr -d '\0')
  grep -q "Content-Type: model/gltf-binary" <<<"$r" || fail "GET the converted bunny: $r"
  r=$(http /three/build/three.module.js | head -5); grep -q "text/javascript" <<<"$r" || fail "GET three.js: $r"
  r=$(http /three/examples/jsm/libs/draco/gltf/draco_decoder.wasm | head -5 | tr -d '\0')
  grep -q "application/wasm" <<<"$r" || fail "GET the Draco decoder: $r"
  for p in /../../etc/passwd /three/../../../etc/passwd /%2e%2e/etc/passwd "/files/0/../../fran.glb" /nosuch; do
    r=$(http "$p" | head -1); grep -q "^HTTP/1.1 404" <<<"$r" || fail "GET $p is not 404: $r"
  done
  r=$(http / POST | head -1); grep -q "^HTTP/1.1 405" <<<"$r" || fail "POST is not 405: $r"
  r=$(http / HEAD); grep -q "Content-Length: [1-9]" <<<"$r" || fail "HEAD: $r"
  grep -q "<html" <<<"$r" && fail "HEAD sent a body"
fi
kill -INT $pid
wait $pid; rc=$?
[ $rc -eq 0 ] || fail "view did not stop cleanly on SIGINT: exit $rc: $(cat "$tmp/view.err")"
grep -q "stopped after [0-9]* request" "$tmp/view.err" || fail "view did not report stopping: $(cat "$tmp/view.err")"
[ "$(ls "$TMPDIR" | wc -l)" -eq 0 ] || fail "view left its temporary directory: $(ls "$TMPDIR")"

if [ $failures -ne 0 ]; then echo "$failures glTF/view CLI test(s) failed"; exit 1; fi
echo "all glTF/view CLI tests passed"
