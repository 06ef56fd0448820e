#!/usr/bin/env bash
# Rasters through the lattice fast path (docs/algorithm.md section 7) against CGAL and
# against the grid path (the fast path off), one thread: prints the markdown rows of
# docs/benchmarks.md's raster section. Rounds are interleaved (vts, vts-grid, cgal per
# round), each figure is the minimum of the rounds, so a busy machine slows all three;
# CPU time (user + system, the process) is given beside the wall clock: on a machine
# shared with other work it is the steadier of the two.
#
# Usage: tools/bench/run_lattice_bench.sh BUILD_DIR [MAX_CELLS [ROUNDS]]
#   (from the repository root) MAX_CELLS: largest synthetic raster (1e6, 1e7, 1e8 as
#   far as this; default 1e7). ROUNDS: default 3. BENCH_DATA: default ../shared/data.
#   BENCH_CGAL_MAX_CELLS: no CGAL (nor grid path) run above this (default 1e7).
set -euo pipefail
build=${1:-build}
max_cells=$(awk -v v="${2:-1e7}" 'BEGIN{printf "%d", v}')
rounds=${3:-3}
cgal_max=$(awk -v v="${BENCH_CGAL_MAX_CELLS:-1e7}" 'BEGIN{printf "%d", v}')
data=${BENCH_DATA:-../shared/data}
bench="$build/tools/bench/bench_triangulation"
[ -x "$bench" ] || { echo "run_lattice_bench: $bench is not built" >&2; exit 1; }

field() { sed -nE "s/.*\"$2\":\"?([^,\"}]*).*/\1/p" <<<"$1"; }
minimum() { awk 'NR == 1 || $1 < m {m = $1} END {if (NR) printf "%.4f", m; else printf "-"}'; }

# row LABEL ARGS...: one table row for bench_triangulation METHOD ARGS...
row() {
  local label=$1 method line n="" fringe="" pieces cells
  shift
  cells=$(awk -v v="${2:-0}" 'BEGIN{printf "%d", v}')
  declare -A times=([vts]="" [vts-grid]="" [cgal]="") cpus=([vts]="" [vts-grid]="" [cgal]="")
  for ((r = 0; r < rounds; ++r)); do
    for method in vts vts-grid cgal; do
      if [ "$method" != vts ] && [ "$1" != file ] && [ "$cells" -gt "$cgal_max" ]; then
        continue
      fi
      line=$("$bench" "$method" "$@") || { echo "run_lattice_bench: $method $* failed" >&2; continue; }
      echo "[run_lattice_bench] $line" >&2
      times[$method]+="$(field "$line" seconds)"$'\n'
      cpus[$method]+="$(field "$line" cpu_s)"$'\n'
      if [ "$method" = vts ]; then
        n=$(field "$line" distinct)
        fringe=$(field "$line" fringe_points)
        [ "$(field "$line" lattice)" = true ] || fringe="(not a lattice)"
      fi
    done
  done
  local v g c vc cc
  v=$(printf '%s' "${times[vts]}" | minimum)
  g=$(printf '%s' "${times[vts-grid]}" | minimum)
  c=$(printf '%s' "${times[cgal]}" | minimum)
  vc=$(printf '%s' "${cpus[vts]}" | minimum)
  cc=$(printf '%s' "${cpus[cgal]}" | minimum)
  local ratio="-" cratio="-" gratio="-"
  [ "$c" != "-" ] && ratio=$(awk -v c="$c" -v v="$v" 'BEGIN{printf "%.1fx", c / v}')
  [ "$cc" != "-" ] && cratio=$(awk -v c="$cc" -v v="$vc" 'BEGIN{printf "%.1fx", c / v}')
  [ "$g" != "-" ] && gratio=$(awk -v g="$g" -v v="$v" 'BEGIN{printf "%.1fx", g / v}')
  echo "| $label | $n | $fringe | $v | $vc | $g | $c | $cc | **$ratio** | **$cratio** | $gratio |"
}

echo "| input | points | fringe points | VTS lattice wall (s) | VTS lattice CPU (s) | VTS grid path wall (s) | CGAL wall (s) | CGAL CPU (s) | lattice vs CGAL, wall | lattice vs CGAL, CPU | lattice vs grid path, wall |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for cells in 1000000 10000000 100000000; do
  [ "$cells" -le "$max_cells" ] || break
  row "synthetic raster, $(awk -v v=$cells 'BEGIN{printf "%.0e", v}') cells, NODATA holes" raster "$cells"
done
for f in topotoolbox/srtm_bigtujunga30m_utm11.tif topotoolbox/srtm_bigtujunga30m_utm11.derived.asc \
  pysheds/dem.tif landlab/zSW3.asc landlab/SRTMGL3_boulder_40.09_-105.55.asc \
  topotoolbox/exampleDEM_orkhon.asc landlab/pre_runout_DEM.asc landlab/hugo_site.asc \
  landlab/west_bijou_gully.asc; do
  [ -f "$data/dem/$f" ] || { echo "run_lattice_bench: $data/dem/$f missing" >&2; continue; }
  row "$(basename "$f")" file "$data/dem/$f"
done
