#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs what PlantMorph needs from Debian 12 (only what is missing), then configures and builds it in build/.
# Sourced by scripts/run.sh and scripts/test.sh; safe to run again and again.
# PLANTMORPH_TARGETS: the CMake targets to build, separated by spaces (default: all of them, tests and benchmarks
# included, as scripts/test.sh needs; scripts/run.sh builds only the plugin, target PlantMorph).
set -euo pipefail
PLANTMORPH_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PLANTMORPH_BUILD="${PLANTMORPH_BUILD:-$PLANTMORPH_ROOT/build}"
PLANTMORPH_TARGETS="${PLANTMORPH_TARGETS:-all}"

# ParaView 5.11 with its SDK (find_package(ParaView) needs the -dev packages its CMake files look for, which
# paraview-dev does not pull in), CGAL and Eigen (header-only), GoogleTest and Google Benchmark, and for running:
# MPI, Xvfb (pvbatch renders only with an X server) and numpy for the pvpython tests.
PACKAGES=(
  build-essential cmake
  paraview paraview-dev python3-paraview python3-numpy python3-mpi4py python3-dev
  libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev
  libgtest-dev libbenchmark-dev libembree-dev
  openmpi-bin libopenmpi-dev xvfb xauth
  qtbase5-dev qttools5-dev libqt5svg5-dev libqt5x11extras5-dev libqt5opengl5-dev qtxmlpatterns5-dev-tools
  libutfcpp-dev libhdf5-dev libogg-dev libtheora-dev libtiff-dev libnetcdf-dev libxml2-dev liblzma-dev liblz4-dev
  libjpeg-dev libpng-dev libglew-dev libgl2ps-dev libgdal-dev libfreetype-dev libavformat-dev libavcodec-dev
  libavutil-dev libswscale-dev libexpat1-dev libboost-dev libx11-dev libxt-dev zlib1g-dev libgl-dev
  libdouble-conversion-dev libpugixml-dev libproj-dev libcgns-dev libsqlite3-dev
  clang libclang-rt-14-dev clang-format
)
# clang and libclang-rt-14-dev (libFuzzer; only a Recommends of clang) build the fuzz harnesses of testing/fuzz/.
# clang-format: scripts/format.sh and the ctest repo.format (the C++ follows .clang-format).
# Trimmed by experiment from the team's first, longer list: a configure + build under strace opened no file of
# libfmt-dev, libjsoncpp-dev or nlohmann-json3-dev, nothing installed depends on them, and with them removed a clean
# configure, build and every test pass. Every other package had a file opened (or is needed at run time: MPI, Xvfb).

plantmorph_install_packages() {
  local missing=()
  local p
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#PACKAGES[@]} Debian packages present"
    return
  fi
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
}

# plantmorph_build DIR [extra cmake args...]: configure (first time) and build the targets in PLANTMORPH_TARGETS.
plantmorph_build() {
  local dir="$1"
  shift
  mkdir -p "$dir"
  # ccache, when the machine has it, makes a rebuild after `git pull` or a fresh clone's build cheap.
  local launcher=()
  # CCACHE_BASEDIR makes the cached paths relative to the clone, so a second clone or worktree (CI's fresh clone
  # among them) hits the same cache.
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PLANTMORPH_ROOT}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
  fi
  cmake -S "$PLANTMORPH_ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "$@" >"$dir/configure.log" 2>&1 ||
    { cat "$dir/configure.log"; echo "setup: configuring failed (log above)"; return 1; }
  local targets
  read -r -a targets <<<"$PLANTMORPH_TARGETS"
  echo "setup: building ${targets[*]} in $dir"
  cmake --build "$dir" -j"$(nproc)" --target "${targets[@]}"
}

plantmorph_install_packages
plantmorph_build "$PLANTMORPH_BUILD"
PLANTMORPH_PLUGIN="$PLANTMORPH_BUILD/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so"
export PLANTMORPH_ROOT PLANTMORPH_BUILD PLANTMORPH_PLUGIN
