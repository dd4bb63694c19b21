#!/usr/bin/env bash
# Installs the Debian packages epsray needs (only those missing), then configures and
# builds a Release build into build/. Safe to run again: it skips what is done.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make pkg-config libtbb-dev libglfw3-dev libglm-dev libosmesa6-dev libhwloc-dev
  libgtest-dev libbenchmark-dev libpng-dev libstb-dev nlohmann-json3-dev libimgui-dev
  xvfb xauth gnuplot-nox tachyon clang-14 libclang-rt-14-dev openmpi-bin libopenmpi-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build_type=${BUILD_TYPE:-Release}
build_dir=${BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j"$(nproc)"
