#!/bin/sh
# Installs multiray's build and test dependencies from Debian 12's packages. Idempotent:
# when everything is present it only runs dpkg-query (well under a second).
# clang-15 + libclang-common-15-dev (its libFuzzer runtime) build the fuzz targets
# (fuzz/README.md); PoCL pulls clang-15 in too, but fuzzing should not rely on that.
# lld-15 links the fuzz targets four times faster than GNU ld (fuzz/CMakeLists.txt).
# mesa-opencl-icd (rusticl, on llvmpipe with RUSTICL_ENABLE=llvmpipe) is a second OpenCL
# implementation beside PoCL and oclgrind a simulator that checks every memory access of
# the kernels: the OpenCL tests run on each (docs/devices.md, "Portability").
set -eu
PACKAGES="build-essential cmake pkg-config clang-format libembree-dev libtbb-dev \
  libtinyobjloader-dev libtinygltf-dev libtinyxml2-dev libstb-dev libopenexr-dev libcli11-dev \
  nlohmann-json3-dev libfmt-dev libspdlog-dev libgtest-dev libgmock-dev libbenchmark-dev \
  assimp-testmodels libnanoflann-dev pocl-opencl-icd ocl-icd-opencl-dev opencl-headers \
  opencl-clhpp-headers clang-15 libclang-common-15-dev lld-15 \
  libteem-dev libdlib-dev libblas-dev liblapack-dev libjpeg-dev libassimp-dev \
  libopenmpi-dev openmpi-bin libzstd-dev libxxhash-dev libcivetweb-dev chromium \
  pybind11-dev python3-pybind11 python3-dev python3-numpy python3-pytest \
  mesa-opencl-icd oclgrind"
missing=""
for p in $PACKAGES; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
    missing="$missing $p"
  fi
done
if [ -z "$missing" ]; then
  exit 0
fi
echo "multiray: installing missing packages:$missing"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends $missing
