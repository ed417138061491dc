#!/usr/bin/env bash
# End-to-end tests of isoforge streamlines: the lines and arrays of the files it writes, tubes,
# seeds from a file, and every option's validation.
# Usage: streamlines_cli_test.sh ISOFORGE DATA_DIR SCRATCH_DIR
set -u
bin=$1 data=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
failures=0
# shellcheck source=assert.sh
source "$(dirname "$0")/assert.sh"
office=$data/office.binary.vtk

# 20 seeds on a line in the office's air: 40 lines (forward and backward), none outside.
expect_ok line_seeds "wrote .*: 40 lines, [0-9]+ points from 20 seeds \(0 outside the input\)" "$bin" streamlines "$office" --seeds line 0.1 2.1 0.5 0.1 2.7 0.5 20 -o "$tmp/lines.vtp"
expect_ok line_file "cells: 40 \(40 polyline\)" "$bin" info "$tmp/lines.vtp"
for a in IntegrationTime ArcLength Vorticity AngularVelocity Rotation Normals scalars vectors SeedIds ReasonForTermination; do
  expect_ok "line_array_$a" "'$a'" "$bin" info "$tmp/lines.vtp"
done
# Forward only, RK4, a length limit: every line ends by length or by leaving the room.
expect_ok rk4_length "wrote .*: 20 lines, .*ended by domain [0-9]+, length [0-9]+, steps 0, stagnation 0" "$bin" streamlines "$office" --seeds line 0.1 2.1 0.5 0.1 2.7 0.5 20 --direction forward --integrator rk4 --max-length 0.5 -o "$tmp/short.vtk"
# A step long enough to overflow the coordinates leaves the domain at once (was an internal error).
expect_ok huge_step "wrote .*: 0 lines, 0 points from 1 seeds .*ended by domain 2" "$bin" streamlines "$office" --seeds point 2 2 1 --step 1e308 --integrator rk4 -o "$tmp/huge.vtp"
# ArcLength never exceeds --max-length (0.5): its range in the file.
expect_ok rk4_arc "'ArcLength' +Float64 x1 +\[0, 0\.(4[0-9]*|5)\]" "$bin" info "$tmp/short.vtk"
# --max-steps 3: four points per line.
expect_ok steps "wrote .*: 2 lines, 8 points from 1 seeds" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --max-steps 3 --integrator rk2 -o "$tmp/steps.vtp"
# Tubes around the lines: triangles, closed ends.
expect_ok tubes "2 tubes of [0-9]+ triangles" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --tube 0.01 --sides 6 -o "$tmp/tubes.ply"
# Tubes by speed (the interpolated "vectors"), ribbons turned by the rotation.
expect_ok tube_by "2 tubes of [0-9]+ triangles" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --tube 0.005 --tube-by vectors -o "$tmp/speed.vtp"
expect_ok ribbons "2 ribbons of [0-9]+ triangles" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --ribbon 0.05 -o "$tmp/ribbon.vtp"
expect_ok ribbon_normals "'Normals' +Float32 x3 \[normals\]" "$bin" info "$tmp/ribbon.vtp"
expect_usage tube_and_ribbon "exclude each other" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --tube 0.01 --ribbon 0.1 -o "$tmp/x.vtp"
expect_usage ribbon_no_vorticity "--ribbon: ribbons turn with the flow's rotation" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --ribbon 0.1 --no-vorticity -o "$tmp/x.vtp"
expect_usage tube_by_alone "--tube-by: applies with --tube only" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --tube-by vectors -o "$tmp/x.vtp"
expect_error tube_by_missing "radius by 'nope': no such point array" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --tube 0.01 --tube-by nope -o "$tmp/x.vtp"
# Seeds from a file: the points of a probe line, one outside the room.
"$bin" -q probe "$office" --line 0.1 2.1 0.5 0.1 2.7 0.5 5 -o "$tmp/seeds.vtp" || fail "seeds_file: probe failed"
expect_ok seeds_file "wrote .*: 10 lines, [0-9]+ points from 5 seeds \(0 outside" "$bin" streamlines "$office" --seeds "$tmp/seeds.vtp" -o "$tmp/from_file.vtp"
expect_ok seed_outside "from 1 seeds \(1 outside the input\)" "$bin" streamlines "$office" --seeds point 100 0 0 -o "$tmp/none.vtp"

# Validation
expect_usage no_seeds "--seeds is required" "$bin" streamlines "$office" -o "$tmp/x.vtp"
expect_usage seeds_line_count "'line' takes 7 values: line X0 Y0 Z0 X1 Y1 Z1 N, got 6" "$bin" streamlines "$office" --seeds line 0 0 0 1 1 1 -o "$tmp/x.vtp"
expect_usage seeds_plane_flat "degenerate plane" "$bin" streamlines "$office" --seeds plane 0 0 0 1 0 0 2 0 0 3 3 -o "$tmp/x.vtp"
expect_usage seeds_nan "--seeds: P0 must be a finite number, got 'nan'" "$bin" streamlines "$office" --seeds line nan 0 0 1 1 1 5 -o "$tmp/x.vtp"
expect_usage seeds_n "--seeds: N must be an integer >= 1, got '0'" "$bin" streamlines "$office" --seeds line 0 0 0 1 1 1 0 -o "$tmp/x.vtp"
expect_usage seeds_extra "give 'line ...', 'plane ...', 'point X Y Z' or one file name" "$bin" streamlines "$office" --seeds a.vtp b.vtp -o "$tmp/x.vtp"
expect_usage step_zero "--step: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --step 0 -o "$tmp/x.vtp"
expect_usage step_nan "--step: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --step nan -o "$tmp/x.vtp"
expect_usage max_steps_zero "--max-steps: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --max-steps 0 -o "$tmp/x.vtp"
expect_usage max_steps_negative "--max-steps: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --max-steps -3 -o "$tmp/x.vtp"
expect_usage length_negative "--max-length: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --max-length -1 -o "$tmp/x.vtp"
expect_usage speed_negative "--terminal-speed: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --terminal-speed -1 -o "$tmp/x.vtp"
expect_usage min_max "--min-step 2 exceeds --max-step 1" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --min-step 2 -o "$tmp/x.vtp"
expect_usage min_rk4 "--min-step: applies with --integrator rk45 only" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --integrator rk4 --min-step 0.1 -o "$tmp/x.vtp"
expect_usage error_rk2 "--max-error: applies with --integrator rk45 only" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --integrator rk2 --max-error 1e-3 -o "$tmp/x.vtp"
expect_usage integrator "--integrator: .*not in" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --integrator euler -o "$tmp/x.vtp"
expect_usage direction "--direction: .*not in" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --direction up -o "$tmp/x.vtp"
expect_usage sides_no_tube "--sides: applies with --tube only" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --sides 5 -o "$tmp/x.vtp"
expect_usage tube_negative "--tube: .*" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 --tube -0.1 -o "$tmp/x.vtp"
expect_usage format "unknown file extension '.stl'" "$bin" streamlines "$office" --seeds point 0.1 2.4 0.5 -o "$tmp/x.stl"
expect_error no_array "streamlines: no point array 'nope'" "$bin" streamlines "$office" --vectors nope --seeds point 0.1 2.4 0.5 -o "$tmp/x.vtp"
expect_error scalar_array "streamlines: point array 'scalars' has 1 component, 3 needed" "$bin" streamlines "$office" --vectors scalars --seeds point 0.1 2.4 0.5 -o "$tmp/x.vtp"
expect_error no_vectors "streamlines: the input has no active point vectors" "$bin" streamlines "$data/bunny.ply" --seeds point 0 0 0 -o "$tmp/x.vtp"
expect_error missing_seeds "nowhere.vtp" "$bin" streamlines "$office" --seeds "$tmp/nowhere.vtp" -o "$tmp/x.vtp"
# Nothing written by the failed runs.
[ ! -e "$tmp/x.vtp" ] || fail "a failed run left $tmp/x.vtp behind"

if [ "$failures" -gt 0 ]; then echo "$failures failure(s)"; exit 1; fi
echo "all streamlines CLI tests passed"
