#!/usr/bin/env bash
# Installs the Debian packages pipescope builds against, only those that are missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev      # image I/O, video, calibration, SIFT, essential matrix
  libeigen3-dev      # linear algebra, Umeyama alignment
  libceres-dev       # every nonlinear least-squares problem
  libcli11-dev       # command line
  libyaml-cpp-dev    # dataset.yaml, camera.yaml, scene.yaml
  nlohmann-json3-dev # run.json, metrics.json
  libspdlog-dev      # logging
  libgtest-dev libgmock-dev  # unit tests
  libbenchmark-dev   # kernel benchmarks
  chromium python3    # report.html's browser test (headless Chromium, scripts/check_report_in_browser.py)
)
# report.html's pinned JavaScript libraries come from the npm registry through npm (`npm ci` at
# configure time); Debian's npm only where the machine has none.
command -v npm >/dev/null || packages+=(nodejs npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "Installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
