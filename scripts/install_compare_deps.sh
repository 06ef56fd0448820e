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

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "[install_compare_deps] installing: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "[install_compare_deps] error: need root to install ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "[install_compare_deps] done"
