#!/usr/bin/env bash
# Regenerates docs/benchmarks.md and docs/img/bench_ns_per_point.png from scratch (issues
# 4 and 15): VTS against CGAL (Delaunay_triangulation_2 + Projection_traits_xy_3, EPICK,
# range insertion = spatially sorted bulk insertion), one process per measurement so
# that peak RSS belongs to one method; the whole pcd_to_mesh pipeline on each input,
# without and with the post-passes (the stage breakdown); DEM rasters through the
# lattice fast path, the grid path and CGAL (tools/bench/run_lattice_bench.sh); PCL's
# GreedyProjection and Poisson through compare_methods where it is built; the targets
# of issue 15 computed from the rows.
#
# Usage: tools/bench/run_bench.sh BUILD_DIR [MAX_N]   (run from the repository root)
#   MAX_N: largest size run (default 1000000): jittered at 1e5, 1e6, 1e7, uniform,
#   clustered and grid at 1e6, 1e7, synthetic rasters at 1e6, 1e7, 1e8 cells, as far
#   as MAX_N (a raster of MAX_N cells when MAX_N < 1e6); so MAX_N=1e8 adds only the
#   1e8-cell raster to MAX_N=1e7.
# Environment:
#   BENCH_DATA         real data folder (default ../shared/data)
#   BENCH_REAL=0       skip the real files
#   BENCH_SLOW=0       skip GP3 and Poisson
#   BENCH_SLOW_LIMIT   seconds per GP3 / Poisson run before it is killed (default 120)
#   BENCH_SLOW_MAX_N   largest input given to GP3 / Poisson (default 1000000)
#   BENCH_VERIFY_MAX_N largest pcd_to_mesh output checked by verify_delaunay (1000000)
#   BENCH_DEFAULT_ROUNDS rounds of the default pipeline per input, the least
#                      grid-to-fill time kept (3)
#   BENCH_OUT          the report (default docs/benchmarks.md; the plot goes to img/ beside it)
#   BENCH_RASTER=0     skip the DEM rasters; BENCH_RASTER_ROUNDS: rounds per raster (3)
#   BENCH_SMALL_REPEAT processes per method on an input under 200000 points, the
#                      fastest kept, VTS and CGAL alternating (15)
#   (run_lattice_bench.sh's BENCH_CGAL_MAX_CELLS and BENCH_GRID_MAX_CELLS apply)
set -euo pipefail
build=${1:-build}
max_n=${2:-1000000}
max_n=$(awk -v v="$max_n" 'BEGIN{printf "%d", v}') # accepts 1e7
data=${BENCH_DATA:-../shared/data}
real=${BENCH_REAL:-1}
slow=${BENCH_SLOW:-1}
slow_limit=${BENCH_SLOW_LIMIT:-120}
slow_max_n=$(awk -v v="${BENCH_SLOW_MAX_N:-1000000}" 'BEGIN{printf "%d", v}')
verify_max_n=$(awk -v v="${BENCH_VERIFY_MAX_N:-1000000}" 'BEGIN{printf "%d", v}')
default_rounds=$(awk -v v="${BENCH_DEFAULT_ROUNDS:-3}" 'BEGIN{printf "%d", (v < 1 ? 1 : v)}')
raster=${BENCH_RASTER:-1}
raster_rounds=${BENCH_RASTER_ROUNDS:-3}
bench="$build/tools/bench/bench_triangulation"
verify="$build/tools/bench/verify_delaunay"
mesher="$build/pcd_to_mesh"
compare="$build/tools/compare/compare_methods"
out=${BENCH_OUT:-docs/benchmarks.md}
plot=$(dirname "$out")/img/bench_ns_per_point.png

die() { echo "run_bench: $*" >&2; exit 1; }
if [ ! -f CMakeLists.txt ] || [ ! -d tools/bench ]; then die "run from the repository root"; fi
for exe in "$bench" "$verify"; do
  [ -x "$exe" ] || die "$exe is not built (it needs CGAL: libcgal-dev; \`make bench\` builds it)"
done
[ -x "$mesher" ] || die "$mesher is not built (\`make bench\` builds it)"
[ -x /usr/bin/time ] || die "/usr/bin/time is missing (Debian package 'time'; scripts/install_deps.sh)"
have_compare=1
if [ "$slow" = 0 ]; then
  have_compare=0; slow_note="GP3 and Poisson were skipped (BENCH_SLOW=0)."
elif [ ! -x "$compare" ]; then
  have_compare=0
  slow_note="GP3 and Poisson were not run: $compare is not built (configure with -DPCL_VTS_BUILD_COMPARE=ON and PCL's surface and features components)."
  echo "run_bench: $compare not built: GP3 and Poisson rows are left out" >&2
fi
have_gnuplot=1
command -v gnuplot >/dev/null 2>&1 || {
  have_gnuplot=0; echo "run_bench: gnuplot missing (gnuplot-nox): no plot" >&2; }

tmp=$(mktemp -d "${TMPDIR:-/tmp}/run_bench.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
t_start=$(date +%s)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

declare -A json e2e dflt slowrow label input_n missing
order=()     # input ids in table order
commands=()  # every command run, for the report
log() { echo "[run_bench] $*" >&2; }

# Inputs under SMALL_N points run in milliseconds, where one preempted run (a timer
# tick, another process) moves a ratio by 10-30 %: they run SMALL_REPEAT times and
# keep the fastest line, for every method alike, VTS and CGAL alternating so that a
# slow stretch of the machine falls on both.
SMALL_N=200000
SMALL_REPEAT=${BENCH_SMALL_REPEAT:-15}

# run_once KEY ARGS...: one bench_triangulation process; its JSON line goes under KEY
# unless KEY already holds a faster one. Returns 1 when it failed.
run_once() {
  local key=$1 line
  shift
  if ! line=$("$bench" "$@" 2>"$tmp/err"); then
    log "FAILED: $bench $*: $(tail -1 "$tmp/err")"
    return 1
  fi
  log "$line"
  if [ -z "${json[$key]:-}" ] || awk -v a="$(run_seconds "$line")" \
    -v b="$(run_seconds "${json[$key]}")" 'BEGIN{exit !(a < b)}'; then
    json[$key]=$line
  fi
}

# run_seconds JSON: the run's wall time in seconds, to the microsecond where the line
# has it.
run_seconds() {
  local us
  us=$(field "$1" wall_us)
  if [ -n "$us" ]; then awk -v u="$us" 'BEGIN{printf "%.6f", u / 1e6}'; else field "$1" seconds; fi
}

# small KEY: whether the input of the line under KEY has fewer than SMALL_N points.
small() {
  local n
  n=$(field "${json[$1]:-}" n)
  [ -n "$n" ] && [ "$n" -lt "$SMALL_N" ]
}

# run_json KEY ARGS...: one bench_triangulation process (SMALL_REPEAT for a small
# input); the fastest JSON line under KEY ("" when it failed).
run_json() {
  local key=$1 r
  shift
  commands+=("$bench $*")
  json[$key]=""
  run_once "$key" "$@" || return 0
  if small "$key"; then
    for ((r = 1; r < SMALL_REPEAT; ++r)); do run_once "$key" "$@" || true; done
  fi
}

# run_vts_cgal ID ARGS...: VTS and CGAL single-threaded on the same input (ARGS after
# the method), alternating SMALL_REPEAT times on a small input; under ID|vts|1 and
# ID|cgal|1.
run_vts_cgal() {
  local id=$1 r m
  shift
  for m in vts cgal; do
    commands+=("$bench $m $*")
    json[$id|$m|1]=""
    run_once "$id|$m|1" "$m" "$@" || true
  done
  if small "$id|vts|1" || small "$id|cgal|1"; then
    for ((r = 1; r < SMALL_REPEAT; ++r)); do
      for m in vts cgal; do run_once "$id|$m|1" "$m" "$@" || true; done
    done
  fi
}

# field JSON KEY: a value of a one-line JSON object ("" when absent).
field() { sed -nE "s/.*\"$2\":\"?([^,\"}]*).*/\1/p" <<<"$1"; }

# time_mesher PLY COMMAND...: runs pcd_to_mesh under /usr/bin/time, its summary in
# $tmp/summary; sets the caller's `wall` (s) and `peak` (KiB). Returns 1 when the
# command failed (logged, PLY removed).
time_mesher() {
  local ply=$1
  shift
  commands+=("/usr/bin/time -f '%e %M' -o TIME $*")
  if ! /usr/bin/time -f "%e %M" -o "$tmp/time" "$@" >"$tmp/summary" 2>&1; then
    log "FAILED: $*: $(tail -1 "$tmp/summary")"
    rm -f "$ply"
    return 1
  fi
  read -r wall peak < <(tail -1 "$tmp/time")
}

# run_e2e ID N FILE [pcd_to_mesh options]: the whole pipeline, single thread, then an
# independent exact check of its output up to BENCH_VERIFY_MAX_N points.
run_e2e() {
  local id=$1 n=$2 file=$3 ply="$tmp/out.ply" verdict times wall peak
  shift 3
  if ! time_mesher "$ply" "$mesher" "$file" "$ply" --no-trim --no-fill --threads 1 "$@"; then
    e2e[$id]="failed"
    return 0
  fi
  # "time (ms)  read R, grid G, hull H, triangulate T, trim -, fill -, write W, total S"
  times=$(sed -nE 's/.*time \(ms\) +read ([0-9.]+), grid ([0-9.]+), hull ([0-9.]+), triangulate ([0-9.]+), trim [0-9.]+, fill [0-9.]+, write ([0-9.]+), .*total ([0-9.]+).*/\1 \2 \3 \4 \5 \6/p' "$tmp/summary")
  local meshing
  meshing=$(sed -nE 's/^Meshing .*\[done, ([0-9.]+) ms.*/\1/p' "$tmp/summary")
  if [ "$n" -le "$verify_max_n" ]; then
    commands+=("$verify OUTPUT.ply")
    verdict=$("$verify" "$ply" 2>&1 | tail -1 || true)
  else
    verdict="not run above $verify_max_n points (BENCH_VERIFY_MAX_N)"
  fi
  e2e[$id]="$wall|$peak|${times:-? ? ? ? ? ?}|${meshing:-?}|$verdict"
  log "e2e $id: wall $wall s, peak $peak KiB, ms read grid hull tri write total: $times; $verdict"
  rm -f "$ply"
}

# run_default ID N FILE [pcd_to_mesh options]: the default pipeline (trim and fill on),
# single thread: its stage times, for the stage breakdown (issue 15). It runs
# $default_rounds times and keeps the round with the least grid-to-fill time (grid +
# hull + triangulate + trim + fill): every stage and ratio of the row comes from that
# one round, the least disturbed on a shared host.
# dflt[ID] = "wall peak_KiB read grid hull triangulate trim fill write total (ms)
# holes_found holes_filled", or "failed".
run_default() {
  local id=$1 file=$3 ply="$tmp/out.ply" times holes wall peak round row best="" best_sum="" sum
  shift 3
  for ((round = 0; round < default_rounds; ++round)); do
    if ! time_mesher "$ply" "$mesher" "$file" "$ply" --threads 1 "$@"; then
      dflt[$id]="failed"
      return 0
    fi
    times=$(sed -nE 's/.*time \(ms\) +read ([0-9.]+), grid ([0-9.]+), hull ([0-9.]+), triangulate ([0-9.]+), trim ([0-9.]+), fill ([0-9.]+), write ([0-9.]+), .*total ([0-9.]+).*/\1 \2 \3 \4 \5 \6 \7 \8/p' "$tmp/summary")
    holes=$(sed -nE 's/^ +holes +([0-9]+) found, ([0-9]+) filled.*/\1 \2/p' "$tmp/summary")
    row="$wall $peak ${times:-? ? ? ? ? ? ? ?} ${holes:-? ?}"
    log "default pipeline $id, round $((round + 1)) of $default_rounds: wall peak_KiB read grid hull tri trim fill write total holes: $row"
    sum=$(awk '$4 ~ /^[0-9.]+$/ && $8 ~ /^[0-9.]+$/ { printf "%.3f", $4 + $5 + $6 + $7 + $8 }' <<<"$row")
    if [ -z "$best" ] || { [ -n "$sum" ] && [ -n "$best_sum" ] && awk -v a="$sum" -v b="$best_sum" 'BEGIN{exit !(a < b)}'; }; then
      best=$row; best_sum=$sum
    fi
  done
  dflt[$id]=$best
  rm -f "$ply"
}
dflt_field() { # ID INDEX (0 wall, 1 peak KiB, 2-9 read grid hull tri trim fill write total ms, 10-11 holes)
  local f
  [ -n "${dflt[$1]:-}" ] && [ "${dflt[$1]}" != failed ] || { echo "-"; return; }
  read -r -a f <<<"${dflt[$1]}"
  echo "${f[$2]:--}"
}

# run_slow ID N FILE [compare_methods options]: GP3 and Poisson (normals included).
run_slow() {
  local id=$1 n=$2 file=$3
  shift 3
  [ "$have_compare" = 1 ] || return 0
  if [ "$n" -gt "$slow_max_n" ]; then
    slowrow[$id|gp3]="skip|not run above $slow_max_n points (BENCH_SLOW_MAX_N)"
    slowrow[$id|poisson]=${slowrow[$id|gp3]}
    return 0
  fi
  local cmd=("$compare" "$file" "$@" --methods "gp3,poisson" --time-limit "$slow_limit"
             --samples-per-triangle 1 --max-samples 100000 --name "$id")
  commands+=("${cmd[*]}")
  log "${cmd[*]}"
  if ! "${cmd[@]}" --report "$tmp/slow.md" >/dev/null 2>"$tmp/slow.log"; then
    log "FAILED: ${cmd[*]}: $(tail -1 "$tmp/slow.log")"
    slowrow[$id|gp3]="failed|compare_methods: $(tail -1 "$tmp/slow.log")"
    slowrow[$id|poisson]=${slowrow[$id|gp3]}
    return 0
  fi
  local idle m line
  idle=$(grep -oE 'peaks at [0-9.]+ MiB' "$tmp/slow.md" | head -1 | grep -oE '[0-9.]+' || true)
  for m in gp3 poisson; do
    line=$(grep -E "^\[compare\] $id $m: " "$tmp/slow.log" | tail -1 || true)
    if [[ $line =~ :\ ([0-9.]+)\ s\ \(\+([0-9.]+)\ s\ normals\),\ ([0-9.]+)\ MiB ]]; then
      slowrow[$id|$m]="ok|${BASH_REMATCH[1]}|${BASH_REMATCH[2]}|${BASH_REMATCH[3]}|${idle:-?}"
    elif [[ $line =~ timed\ out ]]; then
      slowrow[$id|$m]="over|over $slow_limit s (killed)"
    elif [[ $line =~ failed:\ (.*) ]]; then
      slowrow[$id|$m]="failed|${BASH_REMATCH[1]}"
    else
      slowrow[$id|$m]="failed|no result line from compare_methods"
    fi
    log "$id $m: ${slowrow[$id|$m]}"
  done
}

# bench_synthetic DIST N: VTS, CGAL (and 2 threads on jittered), the pipeline on a
# float64 binary PCD of the same points at UTM-like offsets, GP3/Poisson on jittered.
bench_synthetic() {
  local dist=$1 n=$2 id="$1_$2"
  order+=("$id"); label[$id]=$dist; input_n[$id]=$n
  run_vts_cgal "$id" "$dist" "$n"
  if [ "$dist" = jittered ]; then run_json "$id|vts|2" vts "$dist" "$n" 1 2; fi
  local pcd="$tmp/$id.pcd"
  commands+=("$bench write-pcd $dist $n $id.pcd")
  "$bench" write-pcd "$dist" "$n" "$pcd" || die "write-pcd $dist $n failed"
  run_e2e "$id" "$n" "$pcd"
  if [ "$n" -ge 1000000 ]; then run_default "$id" "$n" "$pcd"; fi
  if [ "$dist" = jittered ]; then run_slow "$id" "$n" "$pcd"; fi
  rm -f "$pcd"
}

# bench_file ID LABEL PATH [--classes LIST]: the same measurements on a real file.
bench_file() {
  local id=$1 path=$3
  order+=("$id"); label[$id]=$2
  shift 3
  if [ ! -f "$path" ]; then
    log "missing data file $path (BENCH_DATA=$data): row left empty"
    missing[$id]=$path
    return 0
  fi
  run_vts_cgal "$id" file "$path" "$@" --name "$id"
  local n
  n=$(field "${json[$id|vts|1]}" n)
  input_n[$id]=${n:-0}
  run_e2e "$id" "${n:-0}" "$path" "$@"
  run_default "$id" "${n:-0}" "$path" "$@"
  run_slow "$id" "${n:-0}" "$path" "$@"
}

for n in 100000 1000000 10000000; do
  if [ "$n" -le "$max_n" ]; then bench_synthetic jittered "$n"
  else log "jittered $n skipped (above MAX_N $max_n)"; fi
done
for n in 1000000 10000000; do
  for dist in uniform clustered grid; do
    if [ "$n" -le "$max_n" ]; then bench_synthetic "$dist" "$n"
    else log "$dist $n skipped (above MAX_N $max_n)"; fi
  done
done
if [ "$real" != 0 ]; then
  bench_file ign "IGN LiDAR HD, ground (class 2)" \
    "$data/las/from_laz/pdal_las_with_several_extra_byte_bloc.las" --classes 2
  bench_file tujunga "Big Tujunga DEM (SRTM 30 m)" \
    "$data/dem/topotoolbox/srtm_bigtujunga30m_utm11.derived.asc"
  bench_file csite1 "ISPRS CSite1 (40 % duplicate XY)" \
    "$data/pcd/isprs_filtertest/CSite1_red2-utm.pcd"
  bench_file fsite8 "ISPRS FSite8" "$data/pcd/isprs_filtertest/FSite8_red2-utm.pcd"
  bench_file samp11 "ISPRS samp11" "$data/pcd/isprs_filtertest/samp11-utm.pcd"
fi
# DEM rasters: lattice fast path, grid path, CGAL (one table, rows and commands kept).
raster_md="" raster_note=""
: >"$tmp/raster.tsv"
if [ "$raster" != 0 ]; then
  raster_max=$((max_n < 100000000 ? max_n : 100000000))
  commands+=("tools/bench/run_lattice_bench.sh $build $raster_max $raster_rounds (it ran each command below in every round, interleaved)")
  : >"$tmp/raster_commands"
  if raster_md=$(BENCH_DATA="$data" BENCH_LATTICE_TSV="$tmp/raster.tsv" \
      BENCH_COMMANDS_FILE="$tmp/raster_commands" \
      bash tools/bench/run_lattice_bench.sh "$build" "$raster_max" "$raster_rounds"); then :
  else raster_note="(run_lattice_bench.sh failed: the table may be incomplete)"; fi
  while IFS= read -r line; do commands+=("$line"); done < <(awk '!seen[$0]++' "$tmp/raster_commands")
else
  raster_note="The rasters were skipped (BENCH_RASTER=0)."
fi
t_end=$(date +%s)
load_end=$(cut -d' ' -f1-3 /proc/loadavg)

# ---- derived numbers ----------------------------------------------------------------
num() { awk -v v="$1" 'BEGIN{exit !(v ~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/)}'; }
calc() { awk "BEGIN{printf \"$1\", $2}"; } # calc FORMAT EXPRESSION
speedup() { # CGAL_SECONDS METHOD_SECONDS: 2 decimals, 2 significant digits below 0.1
  if num "$1" && num "$2"; then
    awk -v a="$1" -v b="$2" 'BEGIN{if (b <= 0) {print "-"; exit}
      r = a / b; printf (r < 0.1 ? "%.2g" : "%.2f"), r}'
  else echo "-"; fi
}
val() { # KEY FIELD: a JSON field or "-"
  local j=${json[$1]:-}
  if [ -n "$j" ]; then field "$j" "$2"; else echo "-"; fi
}
have() { [ -n "${json[$1]:-}" ]; }
e2e_field() { # ID INDEX (0 wall, 1 peak KiB, 2-7 read grid hull tri write total ms, 8 meshing ms, 9 verdict)
  local IFS='|' parts
  read -r -a parts <<<"${e2e[$1]:-}"
  if [ "${#parts[@]}" -lt 4 ]; then echo "-"; return; fi
  if [ "$2" -le 1 ]; then echo "${parts[$2]}"
  elif [ "$2" -le 8 ]; then
    local IFS=' ' t
    read -r -a t <<<"${parts[2]}"
    if [ "$2" -le 7 ]; then echo "${t[$(($2 - 2))]:-?}"; else echo "${parts[3]}"; fi
  else echo "${parts[4]}"; fi
}
# secs KEY: the run's wall time (s, to the microsecond where measured) or "-";
# shown KEY: the same to 4 significant digits, as the tables print it.
secs() { if have "$1"; then run_seconds "${json[$1]}"; else echo "-"; fi; }
shown() { local t; t=$(secs "$1"); if [ "$t" = "-" ]; then echo "-"; else calc "%.4g" "$t"; fi; }
cgal_s() { secs "$1|cgal|1"; }

# ---- plot ----------------------------------------------------------------------------
: >"$tmp/vts1.dat"; : >"$tmp/vts2.dat"; : >"$tmp/cgal.dat"
: >"$tmp/vts_other.dat"; : >"$tmp/cgal_other.dat"; : >"$tmp/gp3.dat"; : >"$tmp/poisson.dat"
: >"$tmp/raster_vts.dat"; : >"$tmp/raster_cgal.dat"
while IFS=$'\t' read -r rl rn rv _ _ rc _; do
  num "$rn" && num "$rv" || continue
  echo "$rn $(calc "%.1f" "1e9 * $rv / $rn")" >>"$tmp/raster_vts.dat"
  if num "$rc"; then echo "$rn $(calc "%.1f" "1e9 * $rc / $rn")" >>"$tmp/raster_cgal.dat"; fi
done <"$tmp/raster.tsv"
for id in "${order[@]}"; do
  have "$id|vts|1" || continue
  n=$(val "$id|vts|1" n)
  if [[ $id == jittered_* ]]; then
    echo "$n $(val "$id|vts|1" ns_per_point)" >>"$tmp/vts1.dat"
    have "$id|vts|2" && echo "$n $(val "$id|vts|2" ns_per_point)" >>"$tmp/vts2.dat"
    have "$id|cgal|1" && echo "$n $(val "$id|cgal|1" ns_per_point)" >>"$tmp/cgal.dat"
  else
    echo "$n $(val "$id|vts|1" ns_per_point)" >>"$tmp/vts_other.dat"
    have "$id|cgal|1" && echo "$n $(val "$id|cgal|1" ns_per_point)" >>"$tmp/cgal_other.dat"
  fi
  for m in gp3 poisson; do
    IFS='|' read -r st s ns _ <<<"${slowrow[$id|$m]:-none}"
    if [ "$st" = ok ]; then echo "$n $(calc "%.1f" "1e9 * ($s + $ns) / $n")" >>"$tmp/$m.dat"; fi
  done
done
plot_note=""
if [ "$have_gnuplot" = 1 ] && [ -s "$tmp/vts1.dat" ]; then
  terminal="pngcairo size 900,650 font ',10'"
  gnuplot -e "set terminal pngcairo" >/dev/null 2>&1 || terminal="png size 900,650"
  series=()
  add() { if [ -s "$tmp/$1" ]; then series+=("'$tmp/$1' using 1:2 $2"); fi; }
  add vts1.dat "with linespoints lw 2 pt 7 lc rgb '#1f4e9c' title 'pcl_vts, 1 thread (jittered)'"
  add vts2.dat "with linespoints lw 2 pt 5 lc rgb '#4fa3d9' title 'pcl_vts, 2 threads (jittered)'"
  add cgal.dat "with linespoints lw 2 pt 9 lc rgb '#c0392b' title 'CGAL DT2, EPICK, bulk (jittered)'"
  add vts_other.dat "with points pt 6 ps 1.6 lw 2 lc rgb '#1f4e9c' title 'pcl_vts, 1 thread (other inputs)'"
  add cgal_other.dat "with points pt 8 ps 1.6 lw 2 lc rgb '#c0392b' title 'CGAL (other inputs)'"
  add gp3.dat "with points pt 13 ps 1.6 lc rgb '#222222' title 'PCL GreedyProjection + normals'"
  add poisson.dat "with points pt 11 ps 1.6 lc rgb '#8e44ad' title 'PCL Poisson + normals'"
  add raster_vts.dat "with points pt 12 ps 1.4 lw 2 lc rgb '#2e8b57' title 'pcl_vts lattice path (DEM rasters)'"
  add raster_cgal.dat "with points pt 10 ps 1.4 lw 2 lc rgb '#e67e22' title 'CGAL (DEM rasters)'"
  mkdir -p "$(dirname "$plot")"
  joined=$(printf '%s, ' "${series[@]}")
  if gnuplot >"$tmp/gnuplot.log" 2>&1 <<EOF
set terminal $terminal
set termoption noenhanced
set output '$plot'
set logscale xy
set grid xtics ytics mxtics mytics
set xlabel 'points n'
set ylabel 'ns per point'
set title 'Triangulation time per point (make bench, $(date -u +%Y-%m-%d), $(nproc) cores)'
set key below maxrows 4
set xrange [5e2:2e8]
plot ${joined%, }
EOF
  then plot_note="![ns per point against n](img/$(basename "$plot"))"
  else plot_note="(gnuplot failed: $(tail -1 "$tmp/gnuplot.log"))"; fi
else
  plot_note="(no plot: gnuplot is not installed; scripts/install_deps.sh installs gnuplot-nox)"
fi

# ---- report ----------------------------------------------------------------------------
target_rows=()
target() { target_rows+=("| $1 | $2 | $3 |"); } # TARGET MEASURED STATUS
verdict_ge() { # VALUE LIMIT
  if num "$1"; then awk -v a="$1" -v b="$2" 'BEGIN{print (a >= b) ? "met" : "**missed**"}'
  else echo "not measured"; fi
}
verdict_le() {
  if num "$1"; then awk -v a="$1" -v b="$2" 'BEGIN{print (a <= b) ? "met" : "**missed**"}'
  else echo "not measured"; fi
}
not_run() { echo "not run (MAX_N $max_n)"; }

for n in 1000000 10000000; do
  id=jittered_$n
  if have "$id|vts|1"; then
    s=$(speedup "$(cgal_s "$id")" "$(secs "$id|vts|1")")
    target "VTS >= 3x faster than CGAL, jittered $n" "${s}x" "$(verdict_ge "$s" 3)"
  else target "VTS >= 3x faster than CGAL, jittered $n" "$(not_run)" "not measured"; fi
done
for id in uniform_1000000 ign tujunga csite1; do
  what=${label[$id]:-}
  if [ -z "$what" ]; then
    case $id in
      uniform_1000000) what="uniform 1e6" ;;
      ign) what="IGN LiDAR HD ground" ;;
      tujunga) what="Big Tujunga DEM" ;;
      *) what="ISPRS CSite1" ;;
    esac
  fi
  if have "$id|vts|1"; then
    s=$(speedup "$(cgal_s "$id")" "$(secs "$id|vts|1")")
    target "VTS >= 2x faster than CGAL, $what" "${s}x" "$(verdict_ge "$s" 2)"
  elif [ -n "${missing[$id]:-}" ]; then
    target "VTS >= 2x faster than CGAL, $what" "not run: data file missing" "not measured"
  elif [ -n "${label[$id]:-}" ]; then
    target "VTS >= 2x faster than CGAL, $what" "failed (see the table)" "not measured"
  elif [[ $id == *_* ]]; then
    target "VTS >= 2x faster than CGAL, $what" "$(not_run)" "not measured"
  else
    target "VTS >= 2x faster than CGAL, $what" "not run (BENCH_REAL=0)" "not measured"
  fi
done
if have "clustered_1000000|vts|1"; then
  s=$(speedup "$(cgal_s clustered_1000000)" "$(secs "clustered_1000000|vts|1")")
  target "never slower than CGAL, clustered 1e6" "${s}x" "$(verdict_ge "$s" 1)"
else target "never slower than CGAL, clustered 1e6" "$(not_run)" "not measured"; fi
if have "jittered_10000000|vts|1" && have "jittered_100000|vts|1"; then
  r=$(calc "%.2f" "$(val "jittered_10000000|vts|1" ns_per_point) / $(val "jittered_100000|vts|1" ns_per_point)")
  target "ns/pt at 1e7 within 1.3x of 1e5 (jittered, VTS)" "${r}x ($(val "jittered_10000000|vts|1" ns_per_point) vs $(val "jittered_100000|vts|1" ns_per_point) ns)" "$(verdict_le "$r" 1.3)"
else target "ns/pt at 1e7 within 1.3x of 1e5 (jittered, VTS)" "$(not_run)" "not measured"; fi
worst=""; worst_id=""
for id in "${order[@]}"; do
  have "$id|vts|1" || continue
  b=$(val "$id|vts|1" bytes_per_point_above_input)
  if [ -z "$worst" ] || awk -v a="$b" -v c="$worst" 'BEGIN{exit !(a > c)}'; then worst=$b; worst_id=$id; fi
done
target "VTS peak <= 80 bytes/point above the input (every input)" \
  "${worst:-?} B/pt at worst (${worst_id:-none})" "$(verdict_le "${worst:-x}" 80)"
for n in 1000000 10000000; do
  id=jittered_$n
  if have "$id|vts|2"; then
    s=$(speedup "$(secs "$id|vts|1")" "$(secs "$id|vts|2")")
    same=$([ "$(val "$id|vts|1" triangles)" = "$(val "$id|vts|2" triangles)" ] && echo "same triangle count" || echo "**triangle counts differ**")
    if [ "$n" = 10000000 ]; then
      target "2 threads >= 1.7x over 1, jittered 1e7" "${s}x, $same" "$(verdict_ge "$s" 1.7)"
    else
      target "(2 threads over 1, jittered 1e6: no target)" "${s}x, $same" "reported"
    fi
  elif [ "$n" = 10000000 ]; then target "2 threads >= 1.7x over 1, jittered 1e7" "$(not_run)" "not measured"; fi
done
if [ -n "${e2e[jittered_1000000]:-}" ] && [ "${e2e[jittered_1000000]}" != failed ]; then
  w=$(e2e_field jittered_1000000 0)
  s=$(speedup "$(cgal_s jittered_1000000)" "$w")
  target "pcd_to_mesh --no-trim --no-fill, 1e6 PCD -> PLY, >= 2x faster than CGAL's triangulation alone" \
    "${s}x (wall $w s vs CGAL $(shown "jittered_1000000|cgal|1") s)" "$(verdict_ge "$s" 2)"
else target "pcd_to_mesh end to end 1e6 >= 2x faster than CGAL alone" "$(not_run)" "not measured"; fi
split_text() { # ID: "read R s + write W s = P % of wall; triangulation T s"
  local id=$1 r w g h t wall
  wall=$(e2e_field "$id" 0); r=$(e2e_field "$id" 2); g=$(e2e_field "$id" 3)
  h=$(e2e_field "$id" 4); t=$(e2e_field "$id" 5); w=$(e2e_field "$id" 6)
  if num "$r" && num "$w" && num "$wall" && num "$t"; then
    calc "read %.2f s + write %.2f s = %.0f %% of the %.2f s wall; grid + hull + triangulate %.2f s = %.0f %%" \
      "$r / 1000, $w / 1000, 100 * ($r + $w) / 1000 / $wall, $wall, ($g + $h + $t) / 1000, 100 * ($g + $h + $t) / 1000 / $wall"
  else echo "-"; fi
}
if [ -n "${e2e[jittered_10000000]:-}" ]; then
  target "split between I/O and triangulation, 1e7 end to end" "$(split_text jittered_10000000)" "reported"
else target "split between I/O and triangulation, 1e7 end to end" "$(not_run)" "not measured"; fi

# ---- targets of issue 15 ---------------------------------------------------------------
t15_rows=()
t15() { t15_rows+=("| $1 | $2 | $3 |"); } # TARGET MEASURED STATUS
vs_cgal() { # ID: CGAL s / VTS s of the triangulation table, or "-"
  if have "$1|vts|1" && have "$1|cgal|1"; then speedup "$(cgal_s "$1")" "$(secs "$1|vts|1")"
  else echo "-"; fi
}
why_not() { # ID: why a row has no figure
  if [ -n "${missing[$1]:-}" ]; then echo "not run: data file missing"
  elif [ -n "${label[$1]:-}" ]; then echo "failed (see the tables)"
  elif [[ $1 == *_* ]]; then echo "$(not_run)"
  else echo "not run (BENCH_REAL=0)"; fi
}
ratio_target() { # ID WHAT LIMIT
  local s
  s=$(vs_cgal "$1")
  if [ "$s" != "-" ]; then t15 "triangulation >= ${3}x CGAL, $2" "${s}x" "$(verdict_ge "$s" "$3")"
  else t15 "triangulation >= ${3}x CGAL, $2" "$(why_not "$1")" "not measured"; fi
}
for id in jittered_1000000 jittered_10000000 uniform_1000000 uniform_10000000; do
  ratio_target "$id" "${id%_*} $(awk -v v="${id##*_}" 'BEGIN{printf "%.0e", v}')" 2
done
for id in ign tujunga csite1 fsite8 samp11; do
  what=${label[$id]:-$id}
  ratio_target "$id" "$what" 2
done
for id in clustered_1000000 clustered_10000000; do
  ratio_target "$id" "clustered $(awk -v v="${id##*_}" 'BEGIN{printf "%.0e", v}')" 1.3
done
worst_s="" worst_gen=""
for id in "${order[@]}"; do
  [[ $id == *_* ]] || continue
  s=$(vs_cgal "$id")
  [ "$s" != "-" ] || continue
  if [ -z "$worst_s" ] || awk -v a="$s" -v b="$worst_s" 'BEGIN{exit !(a < b)}'; then worst_s=$s; worst_gen=$id; fi
done
if [ -n "$worst_s" ]; then
  t15 "never slower than CGAL on any generator (every synthetic row)" "${worst_s}x at worst (${worst_gen/_/ })" "$(verdict_ge "$worst_s" 1)"
else t15 "never slower than CGAL on any generator" "$(not_run)" "not measured"; fi
# Rasters: lattice fast path against CGAL, wall clock (CPU beside it).
real_met=0 real_all=0 real_worst="" real_worst_label=""
while IFS=$'\t' read -r rl rn rv rvc _ rc rcc; do
  [ -n "$rl" ] || continue
  if [ "$rc" = "-" ] || [ "$rv" = "-" ]; then
    [[ $rl == synthetic* ]] && t15 "DEM raster >= 10x CGAL: $rl" "CGAL not run" "not measured"
    continue
  fi
  r=$(speedup "$rc" "$rv")
  rcpu=$(speedup "$rcc" "$rvc")
  if [[ $rl == synthetic* ]]; then
    t15 "DEM raster >= 10x CGAL: $rl ($rn points)" "${r}x wall, ${rcpu}x CPU" "$(verdict_ge "$r" 10)"
  else
    real_all=$((real_all + 1))
    awk -v a="$r" 'BEGIN{exit !(a >= 10)}' && real_met=$((real_met + 1))
    if [ -z "$real_worst" ] || awk -v a="$r" -v b="$real_worst" 'BEGIN{exit !(a < b)}'; then
      real_worst=$r; real_worst_label="$rl, $rn points"
    fi
  fi
done <"$tmp/raster.tsv"
if [ "$real_all" -gt 0 ]; then
  t15 "DEM rasters >= 10x CGAL: the files of $data/dem" "$real_met of $real_all files; worst ${real_worst}x wall ($real_worst_label)" "$([ "$real_met" = "$real_all" ] && echo met || echo "**missed**")"
elif [ "$raster" != 0 ]; then t15 "DEM rasters >= 10x CGAL: the files" "no file measured" "not measured"; fi
for n in 1000000 10000000; do
  id=jittered_$n
  tri=$(dflt_field "$id" 5); gr=$(dflt_field "$id" 3); hu=$(dflt_field "$id" 4)
  tr=$(dflt_field "$id" 6); fi_=$(dflt_field "$id" 7)
  what="post-passes: trim + fill <= 0.3x the triangulation (grid + hull + triangulate), jittered $(awk -v v="$n" 'BEGIN{printf "%.0e", v}'), 1 thread"
  if num "$tri" && num "$tr" && num "$fi_" && num "$gr"; then
    r=$(calc "%.2f" "($tr + $fi_) / ($gr + $hu + $tri)")
    t15 "$what" "$r (trim $(calc "%.2f" "$tr / 1000") s + fill $(calc "%.2f" "$fi_ / 1000") s; triangulate stage alone: $(calc "%.2f" "($tr + $fi_) / $tri")x)" "$(verdict_le "$r" 0.3)"
  else t15 "$what" "$(not_run)" "not measured"; fi
done
id=jittered_10000000
gr=$(dflt_field "$id" 3); hu=$(dflt_field "$id" 4); tri=$(dflt_field "$id" 5)
tr=$(dflt_field "$id" 6); fi_=$(dflt_field "$id" 7); wall=$(dflt_field "$id" 0)
what="default pcd_to_mesh (trim + fill), jittered 1e7, 1 thread, no slower than CGAL's triangulation alone"
if num "$gr" && num "$tri" && num "$fi_" && have "$id|cgal|1"; then
  mesh_s=$(calc "%.3f" "($gr + $hu + $tri + $tr + $fi_) / 1000")
  r=$(speedup "$(cgal_s "$id")" "$mesh_s")
  t15 "$what" "${r}x: grid to fill $mesh_s s vs CGAL $(shown "$id|cgal|1") s (whole process with read and write: $wall s)" "$(verdict_ge "$r" 1)"
else t15 "$what" "$(not_run)" "not measured"; fi
id=jittered_10000000
if have "$id|vts|2"; then
  s=$(speedup "$(secs "$id|vts|1")" "$(secs "$id|vts|2")")
  t15 "threads: 2 threads >= 1.8x one thread, jittered 1e7 (grid included)" "${s}x" "$(verdict_ge "$s" 1.8)"
else t15 "threads: 2 threads >= 1.8x one thread, jittered 1e7" "$(not_run)" "not measured"; fi
same_all=yes compared=0
for id in "${order[@]}"; do
  have "$id|vts|2" || continue
  compared=$((compared + 1))
  [ "$(val "$id|vts|1" hash)" = "$(val "$id|vts|2" hash)" ] || same_all=no
done
if [ "$compared" -gt 0 ]; then
  t15 "output identical for every thread count" "mesh hash 1 vs 2 threads on $compared inputs: $([ "$same_all" = yes ] && echo same || echo "**differs**") (ctest checks more counts)" "$([ "$same_all" = yes ] && echo met || echo "**missed**")"
fi
mem=() mem_worst=""
for id in jittered_10000000 uniform_10000000 clustered_10000000 grid_10000000; do
  have "$id|vts|1" || continue
  b=$(val "$id|vts|1" bytes_per_point_above_input)
  mem+=("${id%_*} $b")
  if [ -z "$mem_worst" ] || awk -v a="$b" -v c="$mem_worst" 'BEGIN{exit !(a > c)}'; then mem_worst=$b; fi
done
if [ -n "$mem_worst" ]; then
  t15 "memory <= 80 B/point above the input at 1e7 (triangulation)" "$(IFS=,; echo "${mem[*]}" | sed 's/,/, /g') B/pt" "$(verdict_le "$mem_worst" 80)"
else t15 "memory <= 80 B/point above the input at 1e7" "$(not_run)" "not measured"; fi

{
  echo "# Benchmarks"
  echo
  echo "Generated from scratch by \`make bench\` (tools/bench/run_bench.sh); do not edit by hand."
  echo "VTS (this library) against CGAL's \`Delaunay_triangulation_2\` with"
  echo "\`Projection_traits_xy_3\` and the EPICK kernel, built by range insertion (CGAL"
  echo "spatially sorts the points first: its fastest use), on the same points in the same"
  echo "run. Single thread unless a column says otherwise. Each number is one process"
  echo "(tools/bench/bench_triangulation), so its peak memory belongs to one method and one"
  echo "input (inputs under 200000 points: the fastest of $SMALL_REPEAT such processes per method,"
  echo "VTS and CGAL alternating, since one preempted run of a few milliseconds moves a ratio"
  echo "by tens of per cent). Timed: VTS's whole core pipeline (input conditioning and duplicate merging,"
  echo "grid, hull, region growing) and CGAL's construction; not timed: generating or reading"
  echo "the input (real files go through pcl_vts::loadPointCloud, as pcd_to_mesh does). Both"
  echo "get every input point: VTS merges identical XY positions by its duplicate rule, CGAL's"
  echo "insertion keeps the first vertex at a position; the \"distinct\" column checks that"
  echo "both triangulated the same set. ns/pt divides by the input points (duplicates"
  echo "included). Memory: \"peak\" is the process's resident-set high-water mark while the"
  echo "method ran (reset once the input is resident), which includes the input and about"
  echo "50 MiB of mapped PCL/VTK libraries; \"B/pt\" is (peak - resident set before the"
  echo "method) / input points, i.e. the method's own memory."
  echo
  echo "- Date: $(date -u '+%Y-%m-%d %H:%M UTC'); run time $(( (t_end - t_start) / 60 )) min $(( (t_end - t_start) % 60 )) s"
  echo "- Commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD -- . ':!docs/benchmarks.md' ':!docs/img/bench_ns_per_point.png' 2>/dev/null || echo ' (plus uncommitted changes)')"
  echo "- Machine: $(lscpu 2>/dev/null | sed -nE 's/^Model name: +//p' | head -1), $(nproc) cores ($(lscpu 2>/dev/null | sed -nE 's/^Thread\(s\) per core: +/threads per core: /p' | head -1)), $(awk '/MemTotal/{printf "%.1f GiB", $2 / 1048576}' /proc/meminfo) RAM, $(uname -sr)"
  echo "- Compiler and build: $(c++ --version 2>/dev/null | head -1), CMake build type $(sed -nE 's/^CMAKE_BUILD_TYPE:[A-Z]+=//p' "$build/CMakeCache.txt" 2>/dev/null || echo '?')"
  echo "- Load average (1, 5, 15 min) at start: $load_start; at end: $load_end (other work on the machine is not visible in the numbers otherwise)"
  echo "- Command: \`make bench BENCH_MAX_N=$max_n\` = \`tools/bench/run_bench.sh $build $max_n\`"
  for key in "${!json[@]}"; do
    if [[ ${json[$key]} == *'"peak_reset":false'* ]]; then
      echo "- **Note:** /proc/self/clear_refs was not writable, so \"peak\" is the whole process's peak (input generation or reading included) for at least $key"
      break
    fi
  done
  echo
  echo "## VTS against CGAL"
  echo
  echo "| input | n | distinct | VTS s | CGAL s | speed-up vs CGAL | VTS ns/pt | CGAL ns/pt | VTS peak MiB | CGAL peak MiB | VTS B/pt | CGAL B/pt | VTS grid / hull / triangulate s | triangles |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |"
  for id in "${order[@]}"; do
    if [ -n "${missing[$id]:-}" ]; then
      echo "| ${label[$id]} | missing file \`${missing[$id]}\` | | | | | | | | | | | | |"; continue
    fi
    v="$id|vts|1"; c="$id|cgal|1"
    tri=$(val "$v" triangles)
    [ "$tri" = "$(val "$c" triangles)" ] || tri="$tri (CGAL $(val "$c" triangles))"
    dv=$(val "$v" distinct); dc=$(val "$c" distinct)
    [ "$dv" = "$dc" ] || dv="$dv (CGAL $dc)"
    echo "| ${label[$id]} | $(val "$v" n) | $dv | $(shown "$v") | $(shown "$c") | $(speedup "$(secs "$c")" "$(secs "$v")")x | $(val "$v" ns_per_point) | $(val "$c" ns_per_point) | $(val "$v" peak_rss_mib) | $(val "$c" peak_rss_mib) | $(val "$v" bytes_per_point_above_input) | $(val "$c" bytes_per_point_above_input) | $(val "$v" grid_s) / $(val "$v" hull_s) / $(val "$v" triangulate_s) | $tri |"
  done
  echo
  echo "speed-up = CGAL s / VTS s (> 1: VTS faster). Synthetic inputs (tools/bench/bench_triangulation.cpp):"
  echo "jittered = a unit grid with +-0.2 jitter, uniform = uniform in the same square, clustered ="
  echo "64 gaussian clusters in a square 4x wider (large voids), grid = the exact unit grid"
  echo "(cocircular everywhere; not in the issue's list, kept as the worst tie-breaking case);"
  echo "heights from a smooth terrain function. Real files from \`$data\`: IGN LiDAR HD tile"
  echo "\`las/from_laz/pdal_las_with_several_extra_byte_bloc.las\` (class 2), Big Tujunga"
  echo "\`dem/topotoolbox/srtm_bigtujunga30m_utm11.derived.asc\` (cell centres), ISPRS"
  echo "\`pcd/isprs_filtertest/CSite1_red2-utm.pcd\` (float32 UTM, 40 % duplicate XY),"
  echo "\`FSite8_red2-utm.pcd\` and \`samp11-utm.pcd\` (every point, not only the ground)."
  echo
  echo "## Threads"
  echo
  echo "| input | n | 1 thread s | 2 threads s | speed-up | triangles 1 / 2 threads | same output (mesh hash) |"
  echo "| --- | ---: | ---: | ---: | ---: | --- | --- |"
  for id in "${order[@]}"; do
    have "$id|vts|2" || continue
    h1=$(val "$id|vts|1" hash); h2=$(val "$id|vts|2" hash)
    echo "| ${label[$id]} | $(val "$id|vts|1" n) | $(shown "$id|vts|1") | $(shown "$id|vts|2") | $(speedup "$(secs "$id|vts|1")" "$(secs "$id|vts|2")")x | $(val "$id|vts|1" triangles) / $(val "$id|vts|2" triangles) | $([ -n "$h1" ] && [ "$h1" = "$h2" ] && echo "yes ($h1)" || echo "**no** ($h1 / $h2)") |"
  done
  echo
  echo "The whole core pipeline, grid phase included (bench_triangulation vts DIST N 1 2)."
  echo "Mesh hash: FNV-1a over the output's triangles, twins and vertices, computed after"
  echo "the clock. ctest also checks identical triangles for every thread count"
  echo "(\`GridTriangulator.OutputIsIdenticalForEveryThreadCount\`). docs/scaling.md has 1 to 16"
  echo "threads on a 16-core machine; \`tools/bench/bench_threads\` (static, PCL-free) measures"
  echo "1 to 16 threads on any x86-64 Linux machine."
  echo
  echo "## End to end: pcd_to_mesh"
  echo
  echo "\`pcd_to_mesh INPUT OUT.ply --no-trim --no-fill --threads 1\` under \`/usr/bin/time\`"
  echo "(wall clock and peak RSS of the process); stage times from pcd_to_mesh's own summary."
  echo "Synthetic inputs are written first as binary PCDs with float64 x y z at UTM-like"
  echo "offsets (+5e5 east, +5e6 north; \`bench_triangulation write-pcd\`); real files are read"
  echo "as they are. The output is binary PLY (double vertices where float would round)."
  echo "\"start/exit\" = wall - pcd_to_mesh's own total (loading the PCL/VTK libraries, freeing)."
  echo "\"meshing other\" = pcd_to_mesh's meshing stage - grid - hull - triangulate (the output"
  echo "check, id maps)."
  echo
  echo "| input | n | wall s | peak MiB | read s | grid + hull + triangulate s | meshing other s | write s | start/exit s | I/O share of wall | CGAL triangulation alone s | speed-up vs CGAL | verify_delaunay |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"
  for id in "${order[@]}"; do
    [ -n "${e2e[$id]:-}" ] || continue
    if [ "${e2e[$id]}" = failed ]; then echo "| ${label[$id]} | ${input_n[$id]} | failed | | | | | | | | | | |"; continue; fi
    wall=$(e2e_field "$id" 0); pk=$(e2e_field "$id" 1); r=$(e2e_field "$id" 2)
    g=$(e2e_field "$id" 3); h=$(e2e_field "$id" 4); t=$(e2e_field "$id" 5)
    w=$(e2e_field "$id" 6); tot=$(e2e_field "$id" 7); me=$(e2e_field "$id" 8)
    ver=$(e2e_field "$id" 9)
    if num "$r" && num "$g" && num "$w" && num "$tot" && num "$me"; then
      cols=$(calc "%.3f | %.3f | %.3f | %.3f | %.3f | %.0f %%" "$r / 1000, ($g + $h + $t) / 1000, ($me - $g - $h - $t) / 1000, $w / 1000, $wall - $tot / 1000, 100 * ($r + $w) / 1000 / ($wall > 0 ? $wall : 0.01)")
    else cols="- | - | - | - | - | -"; fi
    case $ver in OK*) ver="OK";; not\ run*) ;; *) ver="**${ver}**";; esac
    echo "| ${label[$id]} | ${input_n[$id]} | $wall | $(calc "%.1f" "$pk / 1024") | $cols | $(shown "$id|cgal|1") | $(speedup "$(cgal_s "$id")" "$wall")x | $ver |"
  done
  echo
  echo "verify_delaunay (tools/bench/verify_delaunay.cpp) uses CGAL's exact predicates only:"
  echo "counter-clockwise, manifold, every vertex used, locally Delaunay on every interior edge,"
  echo "same triangle count and hull as CGAL's triangulation of the written vertices."
  for id in jittered_10000000 jittered_1000000; do
    if [ -n "${e2e[$id]:-}" ] && [ "${e2e[$id]}" != failed ]; then
      echo "I/O split, jittered ${id#jittered_}: $(split_text "$id")."
    fi
  done
  echo
  echo "## Stage breakdown: the default pipeline (issue 15)"
  echo
  echo "\`pcd_to_mesh INPUT OUT.ply --threads 1\` (the defaults: trim and fill on) under"
  echo "\`/usr/bin/time\`, on the same files as the end-to-end table; stage times from its"
  echo "summary, wall clock, $default_rounds rounds, each row from the round with the least"
  echo "grid-to-fill time. \"grid to fill\" = grid + hull + triangulate + trim + fill, the"
  echo "meshing without reading, writing and the output checks, against CGAL's triangulation"
  echo "alone (the triangulation table: neither reads nor writes a file)."
  echo
  echo "| input | n | grid s | hull s | triangulate s | trim s | fill s | write s | holes found / filled | (trim + fill) / triangulate | (trim + fill) / (grid + hull + triangulate) | grid to fill s | CGAL triangulation alone s | CGAL / grid to fill | wall s | peak MiB |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
  for id in "${order[@]}"; do
    [ -n "${dflt[$id]:-}" ] || continue
    if [ "${dflt[$id]}" = failed ]; then echo "| ${label[$id]} | ${input_n[$id]} | failed | | | | | | | | | | | | | |"; continue; fi
    read -r -a f <<<"${dflt[$id]}"
    if num "${f[3]}" && num "${f[5]}" && num "${f[6]}" && num "${f[7]}"; then
      cols=$(calc "%.3f | %.3f | %.3f | %.3f | %.3f | %.3f" "${f[3]} / 1000, ${f[4]} / 1000, ${f[5]} / 1000, ${f[6]} / 1000, ${f[7]} / 1000, ${f[8]} / 1000")
      r1=$(calc "%.2f" "(${f[6]} + ${f[7]}) / (${f[5]} > 0 ? ${f[5]} : 1)")
      r2=$(calc "%.2f" "(${f[6]} + ${f[7]}) / (${f[3]} + ${f[4]} + ${f[5]})")
      gf=$(calc "%.3f" "(${f[3]} + ${f[4]} + ${f[5]} + ${f[6]} + ${f[7]}) / 1000")
    else cols="- | - | - | - | - | -"; r1="-"; r2="-"; gf="-"; fi
    echo "| ${label[$id]} | ${input_n[$id]} | $cols | ${f[10]} / ${f[11]} | $r1 | $r2 | $gf | $(shown "$id|cgal|1") | $(speedup "$(cgal_s "$id")" "$gf")x | ${f[0]} | $(calc "%.1f" "${f[1]} / 1024") |"
  done
  echo
  echo "Targets (issue 15): (trim + fill) <= 0.3x the triangulation; grid to fill no slower"
  echo "than CGAL's triangulation alone at 1e7 (CGAL / grid to fill >= 1)."
  echo
  echo "## DEM rasters: the lattice fast path (issue 15)"
  echo
  echo "DEM rasters meshed through the lattice fast path (docs/algorithm.md section 7: complete"
  echo "lattice cells split without search, only the NODATA rims through the region growing)"
  echo "against CGAL and against the same pipeline with the fast path off (\`vts-grid\`, as"
  echo "\`pcd_to_mesh --no-lattice\`: the grid path), one thread, the same points, the same"
  echo "triangle set (tests/core/test_lattice_triangulation.cpp). By"
  echo "tools/bench/run_lattice_bench.sh: rounds interleaved (lattice, grid path, CGAL), the"
  echo "minimum of $raster_rounds rounds per figure (1 round above 1e7 cells, 15 below 200000 points); wall clock and"
  echo "process CPU time (user + system) both. Synthetic raster: square, spacing 1, rows from"
  echo "the top like an .asc, NODATA ellipses (one per 20000 cells, radii 0.5 to 12.5 cells)"
  echo "and 0.1 % single-cell dropouts (\`bench_triangulation METHOD raster N\`); CGAL and the"
  echo "grid path are left out of a synthetic raster that MemAvailable cannot hold (about 220"
  echo "and 130 bytes per point). Files: the .asc and .tif of \`$data/dem\`."
  echo
  if [ -n "$raster_md" ]; then echo "$raster_md"; fi
  if [ -n "$raster_note" ]; then echo; echo "$raster_note"; fi
  echo
  echo "## PCL GreedyProjection and Poisson"
  echo
  if [ "$have_compare" = 0 ]; then
    echo "$slow_note"
  else
    echo "Through \`compare_methods\` (tools/compare, one process per method, killed after"
    echo "$slow_limit s), on the same points as above (synthetic: the same PCD as the end-to-end"
    echo "run). Time = the method's own time plus its \`pcl::NormalEstimation\` (file exchange"
    echo "excluded), single thread. Peak = the method process's peak RSS; B/pt = (peak - the"
    echo "peak of an idle method process that only loaded its libraries and the points) / n."
    echo "Run on jittered terrain up to $slow_max_n points and on the real files; uniform,"
    echo "clustered and grid are left out to keep \`make bench\` short."
    echo
    echo "| input | n | method | time s (normals s) | ns/pt | speed-up vs CGAL | VTS s | peak MiB | B/pt above idle process |"
    echo "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
    for id in "${order[@]}"; do
      for m in gp3 poisson; do
        [ -n "${slowrow[$id|$m]:-}" ] || continue
        name=$([ "$m" = gp3 ] && echo "GP3 (GreedyProjectionTriangulation)" || echo "Poisson")
        IFS='|' read -r st a b c d <<<"${slowrow[$id|$m]}"
        n=${input_n[$id]}
        if [ "$st" = ok ]; then
          tot=$(calc "%.2f" "$a + $b")
          bpt=$(num "$d" && calc "%.0f" "($c - $d) * 1048576 / $n" || echo "-")
          echo "| ${label[$id]} | $n | $name | $tot ($b) | $(calc "%.0f" "1e9 * $tot / $n") | $(speedup "$(cgal_s "$id")" "$tot")x | $(shown "$id|vts|1") | $c | $bpt |"
        else
          echo "| ${label[$id]} | $n | $name | $a | - | - | $(shown "$id|vts|1") | - | - |"
        fi
      done
    done
  fi
  echo
  echo "## Targets (issue 4)"
  echo
  echo "| target | measured | status |"
  echo "| --- | --- | --- |"
  printf '%s\n' "${target_rows[@]}"
  echo
  echo "## Targets of issue 15"
  echo
  echo "Computed from the rows above (ratios of the same run; single thread unless said)."
  echo
  echo "| target | measured | status |"
  echo "| --- | --- | --- |"
  printf '%s\n' "${t15_rows[@]}"
  echo
  echo "## Time per point"
  echo
  echo "$plot_note"
  echo
  echo "Log-log; lines: jittered terrain at 1e5, 1e6, 1e7 (as far as MAX_N); open symbols:"
  echo "the other inputs at their sizes; GP3 and Poisson (normals included) where they ran;"
  echo "diamonds and down triangles: the DEM rasters (lattice fast path, CGAL)."
  echo
  echo "Figures measured by hand (profiles before and after a change, the post-passes before"
  echo "and after issue 15, LAZ decoding, DEM writing, the 1e8-cell raster's memory) are in"
  echo "[benchmark_notes.md](benchmark_notes.md): \`make bench\` does not regenerate them."
  echo
  echo "## Exact commands"
  echo
  echo "Every process this run started, in order (temporary paths shortened):"
  echo
  echo '```'
  printf '%s\n' "${commands[@]}" | sed -e "s#$tmp/##g"
  echo '```'
} >"$out"
log "wrote $out$([ -f "$plot" ] && echo " and $plot")"
