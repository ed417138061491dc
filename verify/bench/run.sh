#!/usr/bin/env bash
# Runs every benchmark and its peers in the same run and writes ratio tables to OUT_DIR/*.md.
# Usage: run.sh BENCH_BUILD_DIR OUT_DIR [SECTION...]
#   (sections: io implicit contour model decimate; default io implicit contour)
set -euo pipefail
build=$1 out=$2; shift 2
sections=${*:-io implicit contour}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
mkdir -p "$out"
have_vtk=0; /usr/bin/python3 -c "import vtk" 2>/dev/null && have_vtk=1
[ $have_vtk = 1 ] || echo "python3-vtk9 is missing: peer timings will be n/a"

for s in $sections; do
  case $s in
    io)
      "$build/verify/bench/bench_io" --benchmark_format=json --benchmark_repetitions=5 \
        --benchmark_report_aggregates_only=true > "$out/io_isoforge.json"
      if [ $have_vtk = 1 ]; then /usr/bin/python3 "$here/peers/vtk_io.py" "$root/data" 5 > "$out/io_vtk.json"; else echo '{}' > "$out/io_vtk.json"; fi
      ;;
    implicit)
      "$build/verify/bench/bench_implicit" --benchmark_format=json --benchmark_repetitions=3 \
        --benchmark_report_aggregates_only=true > "$out/implicit_isoforge.json"
      if [ $have_vtk = 1 ]; then /usr/bin/python3 "$here/peers/vtk_sample.py" 256 512 > "$out/implicit_vtk.json"; else echo '{}' > "$out/implicit_vtk.json"; fi
      ;;
    contour)
      /usr/bin/python3 "$here/peers/make_fields.py" "$out/fields" 256 512
      ISOFORGE_BENCH_FIELDS="$out/fields" "$build/verify/bench/bench_contour" --benchmark_format=json \
        --benchmark_filter='^contour_dense' --benchmark_repetitions=3 \
        --benchmark_report_aggregates_only=true > "$out/contour_isoforge.json"
      # Peak memory: each case in its own process.
      for m in 0/256 1/256 0/512 1/512; do
        ISOFORGE_BENCH_FIELDS="$out/fields" "$build/verify/bench/bench_contour" --benchmark_format=json \
          --benchmark_filter="^contour_memory/${m}/" > "$out/contour_memory_${m/\//_}.json"
      done
      if [ $have_vtk = 1 ]; then /usr/bin/python3 "$here/peers/vtk_contour.py" "$out/fields" 256 512 > "$out/contour_vtk.json"; else echo '{}' > "$out/contour_vtk.json"; fi
      ;;
    model)
      # Dense modeller cases and the attractor in one process (the dense results go to
      # model_fields/ for the peer to compare); each narrow-band case in its own process, so that
      # its peak memory is its own.
      mkdir -p "$out/model_fields"
      ISOFORGE_BENCH_OUT="$out/model_fields" "$build/verify/bench/bench_model" \
        --benchmark_filter='^(modeller|attractor)' --benchmark_format=json > "$out/model_isoforge.json"
      "$build/verify/bench/bench_model" --benchmark_filter='^crossover' --benchmark_format=json \
        > "$out/model_crossover.json"
      for nb in 512/0 512/1 1024/0 1024/1; do
        "$build/verify/bench/bench_model" --benchmark_filter="^narrowband/${nb}/" \
          --benchmark_format=json > "$out/model_nb_${nb/\//_}.json"
      done
      if [ $have_vtk = 1 ]; then /usr/bin/python3 "$here/peers/vtk_model.py" "$root/data" "$out/model_fields" > "$out/model_vtk.json"; else echo '{}' > "$out/model_vtk.json"; fi
      ;;
    decimate)
      # Its own driver and table (decimate.sh, about 10 minutes): OUT_DIR/decimate/decimate.md.
      "$here/decimate.sh" "$build" "$out/decimate"
      continue
      ;;
    *) echo "unknown section $s"; exit 2 ;;
  esac
  /usr/bin/python3 "$here/report.py" "$out" "$s"
done
