#!/usr/bin/env bash
# make bench-scale: pcd_to_mesh on synthetic LiDAR tiles of N points (make_lidar_tiles),
# in memory where it fits and tiled under --memory-limit, with wall time, points per
# minute, peak RSS and temporary disk, and a byte comparison of the two meshes.
# Usage: run_scale.sh BUILD_DIR WORK_DIR LIMIT N...   (e.g. build /tmp/scale 2G 10000000)
# POST: the post-pass options (default "--no-trim --no-fill", the triangulation alone;
# POST="" runs the default pipeline, trim and fill).
# POINT_FORMAT: the LAS point format of the generated tiles, 1 (default, 28 B a point)
# or 0 (20 B a point, no GPS time: what fits this disk at 1e9).
# Disk: 20-28 B/point of LAS input, 24 B/point of temporary files, 60 B/point of mesh.
set -euo pipefail
build=$1 work=$2 limit=$3
read -r -a post <<< "${POST---no-trim --no-fill}"
format=${POINT_FORMAT:-1}
shift 3
mkdir -p "$work"
echo "| points | path | wall (s) | Mpoints/min | peak RSS (MiB) | temp (MiB) | same bytes |"
echo "|---:|---|---:|---:|---:|---:|---|"
for n in "$@"; do
  data="$work/tiles_${n}_format$format"
  if [ ! -d "$data" ]; then
    mkdir -p "$data"
    "$build/tools/bench/make_lidar_tiles" "$data" "$n" 0 1 "$format" >/dev/null
  fi
  run() { # label, output, extra options...
    local label=$1 out=$2
    shift 2
    /usr/bin/time -f "%e %M" -o "$work/time.txt" "$build/pcd_to_mesh" "$data" "$out" \
      --classes 2 "${post[@]}" --temp-dir "$work" "$@" > "$work/log.txt" 2>&1 || {
      echo "| $n | $label | failed: $(tail -1 "$work/log.txt") |"
      return 1
    }
    read -r wall rss < "$work/time.txt"
    local temp
    temp=$(grep -o '[0-9]* MiB of temporary files' "$work/log.txt" | cut -d' ' -f1 || true)
    echo "$wall $rss ${temp:--}"
  }
  memory_bytes=$((n * 320))
  same="-"
  if [ "$memory_bytes" -lt $((16 * 1024 * 1024 * 1024)) ]; then
    if m=$(run memory "$work/memory.ply" --memory-limit 20G); then
      read -r wall rss temp <<< "$m"
      echo "| $n | in memory | $wall | $(awk -v n="$n" -v t="$wall" 'BEGIN{printf "%.1f", n/1e6/(t/60)}') | $((rss / 1024)) | - | |"
    fi
  fi
  if t=$(run tiled "$work/tiled.ply" --memory-limit "$limit"); then
    read -r wall rss temp <<< "$t"
    [ -f "$work/memory.ply" ] && { cmp -s "$work/memory.ply" "$work/tiled.ply" && same=yes || same=NO; }
    echo "| $n | tiled, --memory-limit $limit | $wall | $(awk -v n="$n" -v t="$wall" 'BEGIN{printf "%.1f", n/1e6/(t/60)}') | $((rss / 1024)) | $temp | $same |"
  fi
  rm -f "$work/memory.ply" "$work/tiled.ply"
  # MPI (issue 13): 1 and 2 ranks of one thread each, when pcd_to_mesh_mpi was built.
  if [ -x "$build/pcd_to_mesh_mpi" ] && command -v mpirun > /dev/null; then
    for ranks in 1 2; do
      /usr/bin/time -f "%e %M" -o "$work/time.txt" env OMPI_ALLOW_RUN_AS_ROOT=1 \
        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np "$ranks" \
        "$build/pcd_to_mesh_mpi" "$data" "$work/mpi$ranks.ply" --classes 2 --no-trim \
        --no-fill --threads 1 --memory-limit "$limit" --temp-dir "$work" > "$work/log.txt" 2>&1 ||
        { echo "| $n | mpi, $ranks ranks | failed |"; continue; }
      read -r wall rss < "$work/time.txt"
      echo "| $n | mpi, $ranks rank(s) x 1 thread | $wall | $(awk -v n="$n" -v t="$wall" 'BEGIN{printf "%.1f", n/1e6/(t/60)}') | $((rss / 1024)) (mpirun's largest child) | - | - |"
    done
    cmp -s "$work/mpi1.ply" "$work/mpi2.ply" && echo "(1 and 2 ranks: same bytes)" || echo "(1 and 2 ranks: DIFFERENT)"
    rm -f "$work/mpi1.ply" "$work/mpi2.ply"
  fi
done
