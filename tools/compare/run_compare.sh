#!/usr/bin/env bash
# Regenerates docs/comparison.md and docs/img/compare/ from scratch: compare_methods on
# each data set (one method at a time, each in its own process), then a gnuplot plot of
# time against point count. Usage: tools/compare/run_compare.sh BUILD_DIR
# (run from the repository root; `make compare` installs, builds and calls it).
# Environment: COMPARE_DATA (default ../shared/data), COMPARE_TIME_LIMIT (seconds per
# method, default 240), COMPARE_PICTURE_WIDTH (pixels per method, default 300).
set -euo pipefail
build=${1:-build}
tool="$build/tools/compare/compare_methods"
data=${COMPARE_DATA:-../shared/data}
limit=${COMPARE_TIME_LIMIT:-240}
width=${COMPARE_PICTURE_WIDTH:-300}
img=docs/img/compare
out=docs/comparison.md
[ -x "$tool" ] || { echo "run_compare: $tool is not built (make compare builds it)" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rm -rf "$img"
mkdir -p "$img"
start=$(date +%s)
names=()
commands=()

# run_set NAME TITLE INPUT-ARGS...: one data set; a failure becomes its section.
run_set() {
  local name=$1 title=$2
  shift 2
  local args=("$@" --name "$name" --title "$title" --time-limit "$limit"
              --pictures "$img" --picture-link img/compare --picture-width "$width")
  names+=("$name")
  commands+=("$(printf '%q ' "$tool" "${args[@]}")")
  echo "[run_compare] $name: ${commands[-1]}" >&2
  if ! "$tool" "${args[@]}" --report "$tmp/$name.md" --tsv "$tmp/$name.tsv" \
       2> >(tee "$tmp/$name.log" >&2); then
    {
      echo "## $title"
      echo
      echo "**compare_methods failed on this data set:** $(grep 'error:' "$tmp/$name.log" | tail -1)"
      echo
    } > "$tmp/$name.md"
  fi
}

# file_set NAME TITLE FILE [ARGS...]: as run_set, or a "missing" section.
file_set() {
  local name=$1 title=$2 file=$3
  shift 3
  if [ -f "$file" ]; then
    run_set "$name" "$title" "$file" "$@"
  else
    names+=("$name")
    printf '## %s\n\n**Skipped: %s not found** (the data sets live in ../shared/data).\n\n' \
      "$title" "$file" > "$tmp/$name.md"
  fi
}

run_set synthetic_1e5 "Synthetic terrain, 1e5 points" --synthetic 100000
run_set synthetic_1e6 "Synthetic terrain, 1e6 points" --synthetic 1000000
file_set ign_lidar_hd "IGN LiDAR HD tile corner, ground points (class 2)" \
  "$data/las/from_laz/pdal_las_with_several_extra_byte_bloc.las" --classes 2
file_set big_tujunga "Big Tujunga DEM, 30 m SRTM grid (770k cells)" \
  "$data/dem/topotoolbox/srtm_bigtujunga30m_utm11.derived.asc"
file_set isprs_samp11 "ISPRS filter test sample 11, reference ground points" \
  "$data/pcd/isprs_filtertest/samp11-utm-ground.pcd"
seconds=$(( $(date +%s) - start ))

# Time against point count, one line per method (failed runs have no point).
cat "$tmp"/*.tsv > "$tmp/all.tsv" 2>/dev/null || : > "$tmp/all.tsv"
methods=(vts-raw vts gp3 poisson bpa)
titles=("VTS, Delaunay only" "VTS + trim + fill" "PCL GreedyProjection" "PCL Poisson" \
        "Open3D Ball-Pivoting")
plot=""
for i in "${!methods[@]}"; do
  awk -F'\t' -v m="${methods[i]}" '$3 == m && $5 == "ok" { print $2, $4 }' \
    "$tmp/all.tsv" | sort -n > "$tmp/${methods[i]}.dat"
  if [ -s "$tmp/${methods[i]}.dat" ]; then
    plot+="${plot:+, }'$tmp/${methods[i]}.dat' using 1:2 with linespoints lw 2 pt 7 title '${titles[i]}'"
  fi
done
plot_note="no plot: gnuplot is not installed (scripts/install_compare_deps.sh)"
if command -v gnuplot >/dev/null 2>&1 && [ -n "$plot" ]; then
  terminal="png size 800,500"
  if gnuplot -e "set terminal pngcairo" >/dev/null 2>&1; then
    terminal="pngcairo size 800,500 font ',10'"
  fi
  gnuplot <<GNUPLOT
set terminal $terminal
set output '$img/time_vs_points.png'
set logscale xy
set grid
set key top left
set xlabel 'input points'
set ylabel 'method time, s (normal estimation excluded)'
set title 'Time against point count (all data sets, one method at a time, 1 thread)'
plot $plot
GNUPLOT
  plot_note=""
fi

# Overview: time per data set and method, or why there is none.
overview() {
  printf '| data set | points |'
  for t in "${titles[@]}"; do printf ' %s |' "$t"; done
  printf '\n| --- | ---: |'
  for _ in "${titles[@]}"; do printf ' ---: |'; done
  printf '\n'
  for name in "${names[@]}"; do
    awk -F'\t' -v n="$name" -v list="${methods[*]}" '
      $1 == n { points = $2; t[$3] = ($5 == "ok") ? sprintf("%.2f s", $4) : "failed: " $5 }
      END {
        if (points == "") { printf "| %s | - | see below | | | | |\n", n; exit }
        split(list, m, " ")
        printf "| %s | %s |", n, points
        for (i = 1; i <= 5; ++i) printf " %s |", (m[i] in t) ? t[m[i]] : "-"
        printf "\n"
      }' "$tmp/all.tsv"
  done
}

commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)
{
  cat <<'INTRO'
# VTS against GreedyProjection, Poisson and Ball-Pivoting

Generated from scratch by `make compare` (tools/compare/run_compare.sh, which runs
`compare_methods` on each data set); do not edit by hand.

Every method runs on the same points, on the same machine, one after another, each in
its own process on one thread: **VTS** as `pcd_to_mesh` runs it (exact Delaunay
triangulation of the XY projection, then with trimming of outward triangles and hole
filling), **pcl::GreedyProjectionTriangulation** and **pcl::Poisson** after
`pcl::NormalEstimation` (k = 10, normals turned to +z; its time is the "normals"
column), and **Open3D's Ball-Pivoting** (Debian `libopen3d-dev` 0.16; normals by
Open3D, k = 10). Parameters follow the measured point spacing (median
nearest-neighbour distance) and are listed under each table. Coordinates are shifted
by a whole-unit offset in double before any method sees them (PCL works in float).

How to read the columns:

- **time**: the method alone (no file I/O, normals separate); **peak MiB**: the peak
  resident memory of the method's process (`ru_maxrss`), which includes the libraries
  and the input copy that process holds: compare the columns with each other rather
  than as bytes per point. A method that crashes or passes the time limit keeps its
  row, with the reason.
- **vertices**: vertices used by at least one triangle. **boundary edges**: edges of
  one triangle (the outline and every hole); **non-manifold edges**: edges of three or
  more. **unused points**: input points that no triangle uses (an exact duplicate in
  XY of a used point counts as used; n/a for Poisson, whose vertices are new).
  **flipped**: triangles seen from below (normal z < 0). **overlapping (XY)**:
  triangles whose XY interiors intersect another's (exact separating-axis test on all
  nearby pairs: a 2.5D surface should cover each XY position once); **overlap area**:
  the XY area covered more than once, estimated on the samples, in % of the mesh's XY
  area.
- **Error** (Metro-style, in input units): about 10 area-weighted samples per
  triangle. mesh -> points: distance from each sample to the tangent disc of its
  nearest input point (PCL kd-tree; the plane of that point's 10 nearest neighbours,
  as wide as they reach), so a mesh lying on the sampled surface scores zero while a
  mesh reaching past the data scores its distance to the data. points -> mesh: exact
  distance from each input point to the nearest triangle. Hausdorff: the larger of
  the two maxima. On synthetic data also against the true surface z = f(x, y):
  vertical |z - f| at the samples and the exact distance from a lattice of points on
  f to the mesh.
- **Poisson** fits a closed implicit surface in the bounding cube, so on open terrain
  it extrapolates past the data (a skirt down to the cube, and bridges over voids).
  Its figures are for its mesh trimmed to the data footprint: triangles whose XY
  centroid is farther than 4 x spacing from every input point are cut; the notes say
  how far the raw output reached and how much was cut.

INTRO
  echo "Run on $(date -u +%Y-%m-%d), commit $commit; machine: ${cpu:-unknown CPU}, $(nproc) cores,"
  echo "$(free -g 2>/dev/null | awk '/^Mem:/ { print $2 " GiB" }') memory. Methods ran on one thread each, the metrics on all cores."
  echo "Time limit $limit s per method. The data sets took $((seconds / 60)) min $((seconds % 60)) s"
  echo "(building and installing excluded)."
  echo
  echo "## Overview: method time"
  echo
  overview
  echo
  if [ -z "$plot_note" ]; then
    echo "![time against point count](img/compare/time_vs_points.png)"
  else
    echo "($plot_note)"
  fi
  echo
  for name in "${names[@]}"; do cat "$tmp/$name.md"; done
  echo "## Commands"
  echo
  echo '```sh'
  echo "make compare BUILD_DIR=$build   # = scripts/install_compare_deps.sh, build, then:"
  echo "tools/compare/run_compare.sh $build"
  for c in "${commands[@]}"; do echo "${c}--report SECTION.md --tsv ROWS.tsv"; done
  echo '```'
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "[run_compare] wrote $out and $img/ in $((seconds / 60)) min $((seconds % 60)) s" >&2
