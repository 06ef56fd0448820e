#!/usr/bin/env bash
# Adversarial equivalence campaign (not part of make test; ~4 min at SCALE 1 on 2 cores):
#   [CASES=REGEX] tools/bench/adversarial_equivalence.sh [BUILD_DIR] [WORK_DIR] [SCALE]
# Generates nasty inputs (tools/bench/adversarial_inputs.py) and, for each, compares
# byte for byte the mesh of paths that must agree: in memory --threads 1 against
# --no-cache-blocks, --threads 2 and 3, tiled (--tile-level 2 and 3, and --memory-limit
# $MEMLIMIT (32M), tiled where the input outgrows it; --temp-dir in WORK_DIR), 2 MPI
# ranks (when pcd_to_mesh_mpi and mpirun exist); once with the defaults (trim, fill)
# and once with --no-trim --no-fill, whose output verify_delaunay (CGAL) checks.
# Inputs with duplicates run under every --duplicates rule. A run that fails must fail
# the same way (exit status) on every path. CASES (a bash regex) picks input stems.
# Prints one line per difference or failure; exit 1 if any.
set -u
BUILD=${1:-build}
WORK=${2:-/tmp/pcl_vts_adversarial}
SCALE=${3:-1.0}
HERE=$(cd "$(dirname "$0")" && pwd)
BIN=$BUILD/pcd_to_mesh
MPIBIN=$BUILD/pcd_to_mesh_mpi
VERIFY=$BUILD/tools/bench/verify_delaunay
MEMLIMIT=${MEMLIMIT:-32M}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
rm -rf "$WORK" && mkdir -p "$WORK/in" "$WORK/out" "$WORK/tmp"
python3 "$HERE/adversarial_inputs.py" "$WORK/in" "$SCALE" > "$WORK/inputs.txt" || exit 2
use_mpi=0
if [ -x "$MPIBIN" ] && command -v mpirun > /dev/null; then use_mpi=1; fi
fails=0
runs=0

# run NAME ARGS... : writes $WORK/out/NAME.ply, records the exit status in NAME.rc
run() {
  local name=$1; shift
  "$@" < /dev/null > "$WORK/out/$name.log" 2>&1
  echo $? > "$WORK/out/$name.rc"
  runs=$((runs + 1))
}

# same REF NAME: the two runs agree (status, and bytes when both succeeded)
same() {
  local a=$WORK/out/$1 b=$WORK/out/$2
  if [ "$(cat "$a.rc")" != "$(cat "$b.rc")" ]; then
    echo "DIFF exit status $1=$(cat "$a.rc") $2=$(cat "$b.rc") ($(tail -1 "$b.log"))"
    fails=$((fails + 1)); return
  fi
  [ "$(cat "$a.rc")" = 0 ] || return
  if ! cmp -s "$a.ply" "$b.ply"; then
    echo "DIFF bytes $1 vs $2: $(cmp "$a.ply" "$b.ply" 2>&1 | head -1)"
    fails=$((fails + 1))
  fi
}

while read -r file count; do
  in=$WORK/in/$file
  stem=${file%.*}
  [[ $stem =~ ${CASES:-.} ]] || continue
  rules=lowest
  case $stem in duplicates|signed_zero|few10_dups|float_rounded|pow2_boundaries) rules="lowest highest mean first" ;; esac
  for rule in $rules; do
    for mode in default notrim; do
      extra=()
      [ $mode = notrim ] && extra=(--no-trim --no-fill)
      base=$stem.$rule.$mode
      common=(--duplicates "$rule" "${extra[@]}")
      run "$base.ref" "$BIN" "$in" "$WORK/out/$base.ref.ply" --threads 1 "${common[@]}"
      run "$base.nocache" "$BIN" "$in" "$WORK/out/$base.nocache.ply" --threads 1 --no-cache-blocks "${common[@]}"
      run "$base.t2" "$BIN" "$in" "$WORK/out/$base.t2.ply" --threads 2 "${common[@]}"
      run "$base.t3" "$BIN" "$in" "$WORK/out/$base.t3.ply" --threads 3 "${common[@]}"
      run "$base.tile2" "$BIN" "$in" "$WORK/out/$base.tile2.ply" --threads 2 --tile-level 2 --temp-dir "$WORK/tmp" "${common[@]}"
      run "$base.tile3nc" "$BIN" "$in" "$WORK/out/$base.tile3nc.ply" --threads 1 --tile-level 3 --no-cache-blocks --temp-dir "$WORK/tmp" "${common[@]}"
      run "$base.mem" "$BIN" "$in" "$WORK/out/$base.mem.ply" --threads 3 --memory-limit "$MEMLIMIT" --temp-dir "$WORK/tmp" "${common[@]}"
      for v in nocache t2 t3 tile2 tile3nc mem; do same "$base.ref" "$base.$v"; done
      if [ $use_mpi = 1 ]; then
        run "$base.mpi2" mpirun --oversubscribe -np 2 "$MPIBIN" "$in" "$WORK/out/$base.mpi2.ply" --threads 1 --tile-level 2 --temp-dir "$WORK/tmp" "${common[@]}"
        same "$base.ref" "$base.mpi2"
      fi
      if [ $mode = notrim ] && [ "$(cat "$WORK/out/$base.ref.rc")" = 0 ]; then
        if ! "$VERIFY" "$WORK/out/$base.ref.ply" > "$WORK/out/$base.verify.log" 2>&1; then
          echo "FAIL verify_delaunay $base: $(tail -1 "$WORK/out/$base.verify.log")"
          fails=$((fails + 1))
        fi
      fi
      echo "$base ($count points): ref exit $(cat "$WORK/out/$base.ref.rc")" >&2
      rm -f "$WORK"/out/"$base".*.ply
    done
  done
done < "$WORK/inputs.txt"
echo "adversarial_equivalence: $runs runs, $fails differences or failures"
[ $fails = 0 ]
