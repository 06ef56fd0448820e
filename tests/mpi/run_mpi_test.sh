#!/usr/bin/env bash
# pcd_to_mesh_mpi on 1, 2 and 3 ranks writes the bytes of the one-process run, and a
# rank that meets a corrupt input makes every rank fail with one clear error, leaving
# no output and no temporary file. Usage: run_mpi_test.sh PCD_TO_MESH PCD_TO_MESH_MPI WORK
set -euo pipefail
single=$1 mpi=$2 work=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work"
# mpirun as root (CI containers) and more ranks than cores.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
fail() { echo "FAIL: $*" >&2; exit 1; }

# Five inputs with duplicates across them, clustered and uniform parts, UTM offsets.
for k in 0 1 2 3 4; do
  awk -v k="$k" 'BEGIN { srand(7 + k); for (i = 0; i < 6000; ++i) {
      if (i % 3 == 0) { x = 500000 + 200 * k + 50 * rand(); y = 4100000 + 50 * rand() }
      else { x = 500000 + 1000 * rand(); y = 4100000 + 1000 * rand() }
      if (i % 50 == 0) { x = 500000 + 10 * (i % 7); y = 4100000 + 10 * (i % 11) }
      printf "%.3f %.3f %.3f\n", x, y, 100 * rand() } }' > "in$k.xyz"
done
# An exact integer grid (cocircular everywhere) with a void, in two files.
awk 'BEGIN { for (y = 0; y < 120; ++y) for (x = 0; x < 120; ++x) {
    if ((x - 60) * (x - 60) + (y - 50) * (y - 50) < 400) continue
    printf "%d %d %d\n", x, y, (x * 7 + y * 3) % 11 > (y < 60 ? "grid0.xyz" : "grid1.xyz") } }'

post=(--no-trim --no-fill) # the post-passes of compare's runs
compare() { # name, inputs...: 1, 2, 3 ranks against one process
  local name=$1
  shift
  "$single" "$@" "$name.ply" "${post[@]}" --quiet || fail "$name: single-process run"
  for ranks in 1 2 3; do
    mpirun -np "$ranks" "$mpi" "$@" "$name.mpi$ranks.ply" "${post[@]}" \
      --threads 1 --temp-dir . > "out$ranks.txt" 2> "err$ranks.txt" ||
      fail "$name, $ranks ranks: exit $? $(cat "err$ranks.txt")"
    cmp -s "$name.ply" "$name.mpi$ranks.ply" ||
      fail "$name, $ranks ranks: the mesh differs from one process"
    grep -q "$ranks MPI ranks" "out$ranks.txt" || [ "$ranks" = 1 ] || fail "no rank count"
  done
}
inputs=(in0.xyz in1.xyz in2.xyz in3.xyz in4.xyz)
compare mixed "${inputs[@]}"
compare grid grid0.xyz grid1.xyz
# Trimmed, then trimmed and filled across ranks (rank 0 runs the post-passes from the
# tile results): the one-process bytes.
post=(--no-fill)
compare trimmed grid0.xyz grid1.xyz
post=()
compare surface grid0.xyz grid1.xyz
compare surface_mixed "${inputs[@]}"
# --ground pmf: rank 0 buckets the points into pre-tiles (with the filter's halo), the
# ranks share their filtering, every rank meshes their ground points.
post=(--ground pmf --pmf-window 5 --tile-level 1)
compare ground grid0.xyz grid1.xyz
post=(--no-trim --no-fill)
# A LAZ file (../shared/data beside the project, when present): each rank decodes its
# share of the chunks.
laz="$here/../../../shared/data/laz/lidR_Topography.laz"
if [ -f "$laz" ]; then
  compare laz "$laz"
fi

# The DEM of a 2-rank run (rank 0 rasterizes it out of core from the tile results) has
# the one-process pixels: each GeoTIFF, read back as input under the same name, meshes
# to the same bytes only if every pixel is the same.
if "$single" --help | grep -q -- '--dem'; then
  "$single" grid0.xyz grid1.xyz dem1.ply --no-trim --no-fill --quiet --dem dem1.tif \
    --resolution 0.7 || fail "dem: single-process run"
  mpirun -np 2 "$mpi" grid0.xyz grid1.xyz dem2.ply --no-trim --no-fill --threads 1 \
    --temp-dir . --dem dem2.tif --resolution 0.7 > out_dem.txt 2> err_dem.txt ||
    fail "dem, 2 ranks: exit $? $(cat err_dem.txt)"
  grep -q "GIS: DEM" out_dem.txt || fail "dem, 2 ranks: no DEM line: $(cat out_dem.txt)"
  mkdir -p d1 d2 && cp dem1.tif d1/dem.tif && cp dem2.tif d2/dem.tif
  (cd d1 && "$single" dem.tif back.ply --no-trim --no-fill --quiet) || fail "dem1 back"
  (cd d2 && "$single" dem.tif back.ply --no-trim --no-fill --quiet) || fail "dem2 back"
  cmp -s d1/back.ply d2/back.ply || fail "the DEM of 2 ranks differs from one process"
  rm -rf d1 d2
  # Contours of the trimmed and filled mesh, traced by rank 0 from the tile results:
  # the one-process Shapefile (geometry and attributes; the .dbf's date skipped).
  "$single" grid0.xyz grid1.xyz iso1.ply --quiet --contours iso1.shp --interval 0.5 ||
    fail "contours: single-process run"
  mpirun -np 2 "$mpi" grid0.xyz grid1.xyz iso2.ply --threads 1 --temp-dir . \
    --contours iso2.shp --interval 0.5 > out_iso.txt 2> err_iso.txt ||
    fail "contours, 2 ranks: exit $? $(cat err_iso.txt)"
  grep -q "GIS: .* contour lines" out_iso.txt || fail "no contour line: $(cat out_iso.txt)"
  cmp -s iso1.shp iso2.shp && cmp -s iso1.shx iso2.shx && cmp -s -i 4 iso1.dbf iso2.dbf ||
    fail "the contours of 2 ranks differ from one process"
fi

# A corrupt input read by the last rank: every rank stops, rank 0 reports it once.
printf '1 2 3\n4 five 6\n' > in4.xyz
set +e
mpirun -np 3 "$mpi" "${inputs[@]}" bad.ply --no-trim --no-fill --threads 1 --temp-dir . \
  > out_bad.txt 2> err_bad.txt
rc=$?
set -e
[ "$rc" -ne 0 ] || fail "a corrupt input on one rank did not fail the job"
grep -q "in4.xyz" err_bad.txt || fail "the error does not name the file: $(cat err_bad.txt)"
[ "$(grep -c 'pcd_to_mesh: error' err_bad.txt)" = 1 ] || fail "not one error line: $(cat err_bad.txt)"
[ ! -e bad.ply ] || fail "a partial output was left"
leftovers=$(ls -A | grep '^\.pcl_vts-' || true)
[ -z "$leftovers" ] || fail "temporary files left: $leftovers"

# A rank killed mid-run: mpirun stops the job (no hang), no output, no temporary file.
awk 'BEGIN { srand(3); for (i = 0; i < 400000; ++i)
    printf "%.3f %.3f %.3f\n", 1000 * rand(), 1000 * rand(), rand() }' > big.xyz
mpirun -np 2 "$mpi" big.xyz big.xyz killed.ply --no-trim --no-fill --threads 1 \
  --temp-dir . --tile-level 3 > out_killed.txt 2> err_killed.txt &
job=$!
victim=""
for _ in $(seq 1 200); do # find rank 1 once it runs (its environment names its rank)
  for pid in $(pgrep -f "pcl_vts|pcd_to_mesh_mpi" || true); do
    # Only this job's rank (its working folder is ours): other MPI jobs may run beside.
    [ "$(readlink "/proc/$pid/cwd" 2>/dev/null)" = "$(pwd -P)" ] || continue
    if tr '\0' '\n' < "/proc/$pid/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then
      victim=$pid
    fi
  done
  [ -n "$victim" ] && break
  sleep 0.05
done
[ -n "$victim" ] || fail "rank 1 never appeared"
for _ in $(seq 1 400); do # wait until tiles are being meshed: the folder holds results
  compgen -G ".pcl_vts-*/result_*" > /dev/null && break
  sleep 0.05
done
compgen -G ".pcl_vts-*/result_*" > /dev/null || fail "the job never reached the tiles"
kill -9 "$victim" 2>/dev/null || true
set +e
timeout 120 tail --pid="$job" -f /dev/null
waited=$?
wait "$job"
rc=$?
set -e
[ "$waited" -eq 0 ] || fail "the job hung after a rank was killed"
[ "$rc" -ne 0 ] || fail "a killed rank did not fail the job"
[ ! -e killed.ply ] || fail "a killed rank left an output"
sleep 0.5
leftovers=$(ls -A | grep '^\.pcl_vts-' || true)
[ -z "$leftovers" ] || fail "temporary files left after a killed rank: $leftovers"
echo "mpi: 1, 2, 3 ranks identical to one process on mixed, grid, --ground pmf and LAZ inputs, the DEM and contours of 2 ranks too; a failing and a killed rank fail the job cleanly"
