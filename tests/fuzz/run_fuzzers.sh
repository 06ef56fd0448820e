#!/usr/bin/env bash
# Builds one libFuzzer binary per reader (clang++, ASan + UBSan: the PCL-free LAS, ASCII
# grid, XYZ and PLY readers, and the PCD reader where PCL is found) and runs each
# for a fixed number of inputs (20,000 per budgeted second, 750 for LAS/LAZ; seed 1:
# deterministic) on
# its seed corpus (test_data/fuzz_seeds/<reader>/); first replays
# every kept crasher (tests/fuzz/regressions/<reader>/). Fails on any crash, leak, UB,
# timeout or out-of-memory. Exit 77 (ctest: skipped) when clang's fuzzer runtime is
# missing (scripts/install_deps.sh installs clang and libclang-rt-14-dev).
#   usage: run_fuzzers.sh SOURCE_DIR WORK_DIR [SECONDS_PER_READER [GENERATED_INCLUDE]]
#          SECONDS_PER_READER: default 20, PCL_VTS_FUZZ_SECONDS overrides;
#          GENERATED_INCLUDE: the build's include/ with the export headers
#          (<pcl_vts/core/export.h>, <pcl_vts/io/export.h>; default WORK_DIR/../../include)
set -euo pipefail

SRC=${1:?source dir}
WORK=${2:?work dir}
SECONDS_PER_READER=${PCL_VTS_FUZZ_SECONDS:-${3:-20}}
GENERATED_INCLUDE=${4:-$WORK/../../include}
CXX=${PCL_VTS_FUZZ_CXX:-clang++}

if ! command -v "$CXX" >/dev/null 2>&1; then
  echo "run_fuzzers: $CXX not found: skipped (scripts/install_deps.sh installs clang)"
  exit 77
fi
mkdir -p "$WORK"
probe="$WORK/probe.cpp"
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' >"$probe"
if ! "$CXX" -fsanitize=fuzzer "$probe" -o "$WORK/probe" 2>/dev/null; then
  echo "run_fuzzers: $CXX has no libFuzzer runtime: skipped (install libclang-rt-14-dev)"
  exit 77
fi

# reader name -> its source (plus the shared helpers every reader uses). The PCD
# reader needs PCL (headers + pcl_io, pcl_common): fuzzed only where they are found.
READERS=(las_reader asc_grid_reader xyz_text_reader ply_point_reader)
declare -A SEEDS=([las_reader]=las [asc_grid_reader]=asc [xyz_text_reader]=xyz
                  [ply_point_reader]=ply [pcd_cloud_reader]=pcd)
# Inputs up to 4 KiB, LAS/LAZ up to 12 KiB: the LAZ seeds need their chunk tables.
# Runs per budgeted second: 20,000, but LAZ inputs decode ~1000 points each (about
# 6 ms under the sanitizers), so the LAS/LAZ reader gets 750.
declare -A MAX_LEN=([las_reader]=12288)
declare -A RUNS_PER_SECOND=([las_reader]=750)
PCL_FLAGS=${PCL_VTS_FUZZ_PCL_FLAGS:-"-isystem /usr/include/pcl-1.13 -isystem /usr/include/eigen3"}
if [ -d /usr/include/pcl-1.13 ] || [ -n "${PCL_VTS_FUZZ_PCL_FLAGS:-}" ]; then
  READERS+=(pcd_cloud_reader)
else
  echo "run_fuzzers: PCL headers not found: the PCD reader is not fuzzed"
fi
FLAGS=(-std=c++17 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined
       -fno-sanitize-recover=undefined -I"$SRC/include" -I"$GENERATED_INCLUDE")

status=0
for reader in "${READERS[@]}"; do
  bin="$WORK/fuzz_$reader"
  srcs=("$SRC/tests/fuzz/fuzz_$reader.cpp" "$SRC/src/io/$reader.cpp"
        "$SRC/src/core/mapped_file.cpp" "$SRC/src/core/status.cpp")
  if [ "$reader" = las_reader ]; then # the LAS reader decodes LAZ too
    srcs+=("$SRC"/src/io/laz/*.cpp)
  fi
  newest=$(ls -t "${srcs[@]}" "$SRC/include/pcl_vts/io/$reader.h" "$SRC/src/io/text_scan.h" \
           "$SRC/src/io/reader_guard.h" "$SRC/include/pcl_vts/core/mapped_file.h" "$SRC"/src/io/laz/*.h | head -1)
  extra=()
  if [ "$reader" = pcd_cloud_reader ]; then
    # shellcheck disable=SC2206
    extra=($PCL_FLAGS -lpcl_io -lpcl_common)
  fi
  if [ ! -x "$bin" ] || [ "$newest" -nt "$bin" ]; then
    "$CXX" "${FLAGS[@]}" "${srcs[@]}" "${extra[@]}" -o "$bin"
  fi
  regressions="$SRC/tests/fuzz/regressions/$reader"
  if [ -d "$regressions" ] && [ -n "$(ls -A "$regressions")" ]; then
    if ! "$bin" -runs=0 "$regressions"/* >"$WORK/$reader.regressions.log" 2>&1; then
      echo "run_fuzzers: $reader FAILED on a kept crasher; see $WORK/$reader.regressions.log"
      tail -30 "$WORK/$reader.regressions.log"
      status=1
      continue
    fi
  fi
  corpus="$WORK/corpus_$reader"
  rm -rf "$corpus" "$WORK/artifacts_$reader"
  mkdir -p "$corpus" "$WORK/artifacts_$reader"
  # -seed fixed and a fixed number of runs: the same inputs are tried on every
  # machine, so the test is deterministic (a time budget explores further on a faster
  # machine). About SECONDS_PER_READER seconds here; the time cap only guards slow hosts.
  if "$bin" "$corpus" "$SRC/test_data/fuzz_seeds/${SEEDS[$reader]}" -seed=1 \
      -runs="$((SECONDS_PER_READER * ${RUNS_PER_SECOND[$reader]:-20000}))" \
      -max_total_time="$((SECONDS_PER_READER * 6))" -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=512 -max_len="${MAX_LEN[$reader]:-4096}" -print_final_stats=1 \
      -artifact_prefix="$WORK/artifacts_$reader/" >"$WORK/$reader.log" 2>&1; then
    echo "run_fuzzers: $reader clean: $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$WORK/$reader.log" | grep -o '[0-9]*$') runs"
  else
    echo "run_fuzzers: $reader FAILED; crasher in $WORK/artifacts_$reader/ (keep it in tests/fuzz/regressions/$reader/)"
    grep -E "ERROR|SUMMARY|runtime error|#[0-9]+ 0x" "$WORK/$reader.log" | head -30
    status=1
  fi
done
exit $status
