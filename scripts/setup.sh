#!/usr/bin/env bash
# Installs every Debian 12 package mpumesh needs (as root; idempotent: apt runs only when
# something is missing), then configures and builds in Release under build/.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  # toolchain
  g++ cmake ninja-build pkg-config
  # Vulkan: loader and headers, lavapipe (software device), validation layers, shader compiler
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
  # maths, geometry, medical image I/O
  libeigen3-dev libglm-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev libtet1.5-dev
  libinsighttoolkit5-dev zlib1g-dev libdeflate-dev
  # command line, JSON, formatting, threads, neighbour search, images
  libcli11-dev nlohmann-json3-dev libfmt-dev libspdlog-dev libtbb-dev libnanoflann-dev libstb-dev
  # the Python module, its wheel and pip install, and the cohort workflow
  pybind11-dev python3-dev python3-numpy python3-build python3-venv python3-pip snakemake
  # tests (chromium: the HTML report opened in a real, headless browser; clang and its
  # runtime: the libFuzzer targets; pytest and nibabel: the Python module's tests; meshio:
  # an independent reader of the volume meshes; CalculiX: a finite-element solver on them)
  libgtest-dev chromium clang libclang-rt-14-dev python3-pytest python3-nibabel python3-meshio calculix-ccx
  # tests: a single-node SLURM cluster that runs the workflow's jobs
  slurm-wlm munge
  # sample data: the InVesalius head CT, pydicom's small real DICOM files
  invesalius-examples python3-pydicom
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup: these packages are missing and installing them needs root: ${missing[*]}" >&2
    exit 1
  fi
  echo "setup: installing ${#missing[@]} package(s): ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-} >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)"
