#!/usr/bin/env bash
# Installs every Debian 12 package that the build, the tests and the demo need.
# Idempotent and quiet when everything is present; must run as root (or via sudo) to install.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  dpkg-dev file         # make package: CPack's .deb (dpkg-shlibdeps, ELF detection)
  libpcl-dev            # PCL 1.13 (pulls FLANN, Boost, Eigen, VTK)
  zlib1g-dev            # the PNG writer's deflate and CRC (also pulled by VTK)
  libcgal-dev libgmp-dev libmpfr-dev   # the Delaunay oracle in tests and benchmarks
  libboost-program-options-dev   # the command lines of pcd_to_mesh and compare_methods
  libgtest-dev
  clang-format clang-tidy   # .ci/run: the format check, clang-tidy on changed files
  clang libclang-rt-14-dev   # libFuzzer + ASan/UBSan runtimes: the reader fuzzers in ctest
  time                  # peak-memory figures in make bench
  gnuplot-nox           # make bench: docs/img/bench_ns_per_point.png
  libgdal-dev           # optional: GeoTIFF input of pcd_to_mesh
  libopenmpi-dev openmpi-bin   # pcd_to_mesh_mpi: the tiled job across MPI ranks
)

# shellcheck source=scripts/apt_install.sh
source "$(dirname "$0")/apt_install.sh"
apt_install install_deps "${PACKAGES[@]}"
