#!/usr/bin/env bash
# The core alone, as a device or another project builds it: configures a fresh tree with
# -DMVOX_BUILD_HOST=OFF -DMVOX_BUILD_CLI=OFF, checks that no host library (OpenCV, GDCM,
# libtiff, libjpeg, zlib, CLI11) was even looked for, builds, and runs `ctest -L core`.
# Needs only a compiler, CMake, GLM and GoogleTest.
#
#   scripts/test_core_only.sh [BUILD_DIR]     # default: build-core
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$repo/build-core}
rm -rf "$build"
cmake -S "$repo" -B "$build" -DMVOX_BUILD_HOST=OFF -DMVOX_BUILD_CLI=OFF > /dev/null
looked_up=$(grep -E '^(GDCM_DIR|OpenCV_DIR|MVOX_OPENCV_[A-Za-z_]*|TIFF_[A-Z_]*|JPEG_[A-Z_]*|ZLIB_[A-Z_]*|CLI11_DIR)[:=]' \
  "$build/CMakeCache.txt" || true)
if [ -n "$looked_up" ]; then
  echo "test_core_only.sh: the core's build looked for host libraries:" >&2
  echo "$looked_up" >&2
  exit 1
fi
cmake --build "$build" -j"$(nproc)"
ctest --test-dir "$build" -L core --output-on-failure -j"$(nproc)"
