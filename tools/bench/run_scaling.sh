#!/usr/bin/env bash
# Thread scaling of the VTS triangulation: one process per run, JSON lines on stdout.
# Usage: tools/bench/run_scaling.sh BENCH_BINARY [N ...]   (threads 1 2 4 8 16)
set -euo pipefail
bench=${1:?usage: run_scaling.sh BENCH_BINARY [N ...]}
shift
sizes=("${@:-1000000}")
for n in "${sizes[@]}"; do
  "$bench" cgal jittered "$n"
  for t in 1 2 4 8 16; do
    [ "$t" -le "$(nproc)" ] || continue
    "$bench" vts jittered "$n" 1 "$t"
  done
done
