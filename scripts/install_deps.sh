#!/usr/bin/env bash
# Installs every Debian 12 package that the build, the tests and the demo need.
# Idempotent and quiet when everything is present; must run as root (or via sudo) to install.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libpcl-dev            # PCL 1.13 (pulls FLANN, Boost, Eigen, VTK)
  libcgal-dev libgmp-dev libmpfr-dev   # the Delaunay oracle in tests and benchmarks
  libgtest-dev libbenchmark-dev
  clang-format
  clang libclang-rt-14-dev   # libFuzzer + ASan/UBSan runtimes: the reader fuzzers in ctest
  time                  # peak-memory figures in make bench
  gnuplot-nox           # make bench: docs/img/bench_ns_per_point.png
  libgdal-dev           # optional: GeoTIFF input of pcd_to_mesh
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "[install_deps] installing: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "[install_deps] error: need root to install ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "[install_deps] done"
