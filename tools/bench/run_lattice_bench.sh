#!/usr/bin/env bash
# Rasters through the lattice fast path (docs/algorithm.md section 7) against CGAL and
# against the grid path (the fast path off), one thread: prints the markdown rows of
# docs/benchmarks.md's raster section. Rounds are interleaved (vts, vts-grid, cgal per
# round), each figure is the minimum of the rounds, so a busy machine slows all three;
# CPU time (user + system, the process) is given beside the wall clock: on a machine
# shared with other work it is the steadier of the two.
# Times are printed in seconds to the microsecond (the small files take well under a
# millisecond).
#
# `make bench` runs it through tools/bench/run_bench.sh, which puts the table in
# docs/benchmarks.md; it can also be run alone.
#
# Usage: tools/bench/run_lattice_bench.sh BUILD_DIR [MAX_CELLS [ROUNDS]]
#   (from the repository root) MAX_CELLS: largest synthetic raster (1e6, 1e7, 1e8 as
#   far as this; a single raster of MAX_CELLS cells when it is below 1e6; default 1e7).
#   ROUNDS: default 3 (1 above 1e7 cells; BENCH_RASTER_SMALL_ROUNDS, default 15, for
#   a raster of under 200000 points). BENCH_DATA: default ../shared/data.
#   BENCH_CGAL_MAX_CELLS: no CGAL run on a synthetic raster above this (default: what
#   MemAvailable holds at 220 bytes per point: CGAL takes about 170 above the input).
#   BENCH_GRID_MAX_CELLS: the same for the grid path (default: 130 bytes per point).
#   BENCH_LATTICE_TSV: also write one line per row there: label, points, lattice wall
#   s, lattice CPU s, grid path wall s, CGAL wall s, CGAL CPU s (tab-separated, "-"
#   where not run). BENCH_COMMANDS_FILE: append every command run there.
set -euo pipefail
build=${1:-build}
max_cells=$(awk -v v="${2:-1e7}" 'BEGIN{printf "%d", v}')
rounds=${3:-3}
small_points=200000
small_rounds=${BENCH_RASTER_SMALL_ROUNDS:-15}
avail=$(awk '/MemAvailable/{print $2 * 1024}' /proc/meminfo)
cgal_max=$(awk -v v="${BENCH_CGAL_MAX_CELLS:-$(awk -v a="$avail" 'BEGIN{printf "%d", a / 220}')}" 'BEGIN{printf "%d", v}')
grid_max=$(awk -v v="${BENCH_GRID_MAX_CELLS:-$(awk -v a="$avail" 'BEGIN{printf "%d", a / 130}')}" 'BEGIN{printf "%d", v}')
data=${BENCH_DATA:-../shared/data}
tsv=${BENCH_LATTICE_TSV:-}
commands_file=${BENCH_COMMANDS_FILE:-}
bench="$build/tools/bench/bench_triangulation"
[ -x "$bench" ] || { echo "run_lattice_bench: $bench is not built" >&2; exit 1; }

field() { sed -nE "s/.*\"$2\":\"?([^,\"}]*).*/\1/p" <<<"$1"; }
# Seconds from the microsecond fields (files of a millisecond or less), else the
# seconds fields of an older bench_triangulation.
seconds() {
  local us
  us=$(field "$1" "$2")
  if [ -n "$us" ]; then awk -v u="$us" 'BEGIN{printf "%.6f", u / 1e6}'; else field "$1" "$3"; fi
}
minimum() { awk 'NR == 1 || $1 < m {m = $1} END {if (NR) printf "%.6f", m; else printf "-"}'; }

# row LABEL ARGS...: one table row for bench_triangulation METHOD ARGS...
row() {
  local label=$1 method line n="" fringe="" cells
  shift
  cells=$(awk -v v="${2:-0}" 'BEGIN{printf "%d", v}')
  declare -A times=([vts]="" [vts-grid]="" [cgal]="") cpus=([vts]="" [vts-grid]="" [cgal]="")
  local row_rounds=$rounds
  [ "$1" = file ] || [ "$cells" -le 10000000 ] || row_rounds=1
  for ((r = 0; r < row_rounds; ++r)); do
    for method in vts vts-grid cgal; do
      if [ "$1" != file ]; then
        if [ "$method" = cgal ] && [ "$cells" -gt "$cgal_max" ]; then continue; fi
        if [ "$method" = vts-grid ] && [ "$cells" -gt "$grid_max" ]; then continue; fi
      fi
      [ -z "$commands_file" ] || echo "$bench $method $*" >>"$commands_file"
      line=$("$bench" "$method" "$@") || { echo "run_lattice_bench: $method $* failed" >&2; continue; }
      echo "[run_lattice_bench] $line" >&2
      times[$method]+="$(seconds "$line" wall_us seconds)"$'\n'
      cpus[$method]+="$(seconds "$line" cpu_us cpu_s)"$'\n'
      if [ "$method" = vts ]; then
        n=$(field "$line" distinct)
        fringe=$(field "$line" fringe_points)
        [ "$(field "$line" lattice)" = true ] || fringe="(not a lattice)"
      fi
    done
    # A raster of under SMALL_POINTS points runs in a millisecond or less, where one
    # timer tick or preemption moves a ratio by tens of per cent: more rounds.
    if [ "$r" -eq 0 ] && [ -n "$n" ] && [ "$n" -lt "$small_points" ] &&
      [ "$row_rounds" -lt "$small_rounds" ]; then row_rounds=$small_rounds; fi
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
  [ -z "$tsv" ] || printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "${n:--}" "$v" "$vc" "$g" "$c" "$cc" >>"$tsv"
  echo "| $label | $n | $fringe | $v | $vc | $g | $c | $cc | **$ratio** | **$cratio** | $gratio |"
}

echo "| input | points | fringe points | VTS lattice wall (s) | VTS lattice CPU (s) | VTS grid path wall (s) | CGAL wall (s) | CGAL CPU (s) | lattice vs CGAL, wall | lattice vs CGAL, CPU | lattice vs grid path, wall |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
sizes=()
for cells in 1000000 10000000 100000000; do
  if [ "$cells" -le "$max_cells" ]; then sizes+=("$cells"); fi
done
[ "${#sizes[@]}" -gt 0 ] || sizes=("$max_cells")
for cells in "${sizes[@]}"; do
  note=""
  [ "$cells" -le "$cgal_max" ] || note=", no CGAL (memory)"
  [ "$cells" -le "$grid_max" ] || note="$note, no grid path (memory)"
  row "synthetic raster, $(awk -v v="$cells" 'BEGIN{printf "%.0e", v}') cells, NODATA holes$note" raster "$cells"
done
for f in topotoolbox/srtm_bigtujunga30m_utm11.tif topotoolbox/srtm_bigtujunga30m_utm11.derived.asc \
  pysheds/dem.tif landlab/zSW3.asc landlab/SRTMGL3_boulder_40.09_-105.55.asc \
  topotoolbox/exampleDEM_orkhon.asc landlab/pre_runout_DEM.asc landlab/hugo_site.asc \
  landlab/west_bijou_gully.asc; do
  [ -f "$data/dem/$f" ] || { echo "run_lattice_bench: $data/dem/$f missing" >&2; continue; }
  row "$(basename "$f")" file "$data/dem/$f"
done
