#!/usr/bin/env bash
# Installs the Debian 12 packages Lacet builds with, if any is missing. Run as root.
set -euo pipefail
packages=(
  build-essential cmake ninja-build ccache python3
  libglm-dev libcgal-dev libgmp-dev libmpfr-dev
  libcli11-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtbb-dev libopenimageio-dev pkg-config
  libgdal-dev gdal-bin libgeographiclib-dev libsqlite3-dev osmium-tool
  libopenmpi-dev openmpi-bin
  libpng-dev libjpeg-dev libwebp-dev zlib1g-dev
  libglfw3-dev libepoxy-dev libimgui-dev libgl-dev xvfb xauth libgl1-mesa-dri
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then echo "Missing packages and not root: ${missing[*]}" >&2; exit 1; fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
