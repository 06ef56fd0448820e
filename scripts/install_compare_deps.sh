#!/usr/bin/env bash
# Installs the Debian 12 packages that only `make compare` needs (on top of
# scripts/install_deps.sh): Open3D for the Ball-Pivoting rows, gnuplot for the time
# plot. Idempotent and quiet when everything is present; must run as root (or sudo).
# Without Open3D the comparison still runs and reports Ball-Pivoting as not built.
set -euo pipefail

PACKAGES=(
  libopen3d-dev   # Open3D 0.16: TriangleMesh::CreateFromPointCloudBallPivoting
  gnuplot-nox     # docs/img/compare/time_vs_points.png
)

# shellcheck source=scripts/apt_install.sh
source "$(dirname "$0")/apt_install.sh"
apt_install install_compare_deps "${PACKAGES[@]}"
