#!/usr/bin/env bash
# mvox on aarch64 (64-bit ARM), from an x86-64 Debian machine: cross-compiles with Debian's
# g++-aarch64-linux-gnu (cmake/aarch64-linux-gnu.cmake) and runs the arm64 programs under
# qemu-aarch64 (qemu-user). Three checks:
#
#   1. the core's and sim's tests (ctest -L 'core|sim'), so the NEON loops of PASS 1 and PASS 3
#      (classify.cpp, word_configs.h) against their definitions;
#   2. the mvox executable, without its optional modules (OpenCV's and GDCM's), builds;
#   3. the arm64 mvox leaves the same files as the x86-64 mvox, byte for byte: PLY meshes of a
#      raw volume as u8, u16le, i16le and f32le; an OBJ with spacing and origin; marching cubes
#      with normals and a picture; and `mvox demo`.
#
# Installs what it needs first (apt-get, idempotent; adds dpkg's arm64 architecture for the
# multiarch packages libgtest-dev:arm64, libtiff-dev:arm64, ...). Build trees in build-aarch64/.
# Prints a summary; exits non-zero on any failure. From scratch on 2 cores, 2 to 3 minutes on a
# quiet machine and 12 on a busy one (packages 1 min, core build 5, tests under QEMU 1.5, the
# mvox build 4.5); 25 s when the builds are up to date. Run the arm64 mvox by hand without
# `-L /usr/aarch64-linux-gnu` (cmake/aarch64-linux-gnu.cmake says why: it hangs starting a
# thread).
#
#   scripts/test_aarch64.sh
#
# Environment: MVOX_X86_BINARY, the x86-64 mvox to compare with (default build/src/mvox, as
# scripts/test.sh builds it); MVOX_JOBS (default: nproc).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
out=$repo/build-aarch64
x86_mvox=${MVOX_X86_BINARY:-$repo/build/src/mvox}
jobs=${MVOX_JOBS:-$(nproc)}
toolchain=$repo/cmake/aarch64-linux-gnu.cmake
me=test_aarch64.sh

say() { printf '\n== %s: %s (%ds)\n' "$me" "$*" "$SECONDS"; }
die() { echo "$me: $*" >&2; exit 1; }

[ -x "$x86_mvox" ] || die "no x86-64 mvox at $x86_mvox to compare with: build it first (scripts/test.sh), or name one in MVOX_X86_BINARY"

# 1. Packages. ---------------------------------------------------------------------------------
# The arm64 libraries come as Debian multiarch packages, next to the x86-64 ones; GLM and CLI11
# are header-only and shared. Installing libc6:arm64 with them also lets qemu-aarch64 run the
# programs without -L (cmake/aarch64-linux-gnu.cmake says why that matters).
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  say "dpkg --add-architecture arm64"
  if [ "$(id -u)" -eq 0 ]; then dpkg --add-architecture arm64; else sudo dpkg --add-architecture arm64; fi
fi
packages=(cmake make python3 g++-aarch64-linux-gnu qemu-user libglm-dev libcli11-dev
          libgtest-dev:arm64 libtiff-dev:arm64 libjpeg-dev:arm64 libpng-dev:arm64 zlib1g-dev:arm64)
source "$repo/scripts/apt_install.sh"
apt_install "$me" "${packages[@]}"
neon=$(aarch64-linux-gnu-g++ -dM -E -x c++ /dev/null | grep -cE '^#define (__ARM_NEON|__AARCH64EL__) ' || true)
[ "$neon" -eq 2 ] || die "aarch64-linux-gnu-g++ does not define __ARM_NEON and __AARCH64EL__: the NEON loops would not be built"

# 2. The core, sim and their tests, run under qemu-aarch64. -------------------------------------
say "core, sim and tests: configure and build (-j$jobs)"
mkdir -p "$out"
nice cmake -S "$repo" -B "$out/core" --toolchain "$toolchain" \
  -DMVOX_BUILD_HOST=OFF -DMVOX_BUILD_CLI=OFF > "$out/core.log" 2>&1 \
  || { tail -n 30 "$out/core.log" >&2; die "configure failed (log: $out/core.log)"; }
nice cmake --build "$out/core" -j"$jobs" >> "$out/core.log" 2>&1 \
  || { tail -n 30 "$out/core.log" >&2; die "build failed (log: $out/core.log)"; }
say "ctest -L 'core|sim' under qemu-aarch64"
tests_ok=1
nice ctest --test-dir "$out/core" -L 'core|sim' -j"$jobs" --output-on-failure \
  > "$out/ctest.log" 2>&1 || tests_ok=0
grep -E 'tests passed|tests failed|^(core|sim) +=' "$out/ctest.log" || true
if [ "$tests_ok" -ne 1 ]; then
  grep -E '\(Failed\)|\(Timeout\)|\(SEGFAULT\)|Not Run' "$out/ctest.log" >&2 || true
fi
tests_line=$(grep -E 'tests passed' "$out/ctest.log" || echo "ctest did not finish")

# 3. The mvox executable without its modules. --------------------------------------------------
# The modules (mvox_image_codecs: OpenCV, mvox_dicom_codecs: GDCM) are loaded at run time and are
# not needed to extract a raw volume; there are no arm64 packages of OpenCV or GDCM here, so
# they are left out (-DMVOX_BUILD_MODULES=OFF), as a device build would.
say "mvox without modules: configure and build (-j$jobs)"
nice cmake -S "$repo" -B "$out/cli" --toolchain "$toolchain" -DMVOX_BUILD_MODULES=OFF \
  -DMVOX_BUILD_TESTS=OFF -DMVOX_BUILD_PYTHON=OFF > "$out/cli.log" 2>&1 \
  || { tail -n 30 "$out/cli.log" >&2; die "configure failed (log: $out/cli.log)"; }
nice cmake --build "$out/cli" -j"$jobs" --target mvox >> "$out/cli.log" 2>&1 \
  || { tail -n 30 "$out/cli.log" >&2; die "build failed (log: $out/cli.log)"; }
arm_mvox=$out/cli/src/mvox

# 4. The same outputs from both processors. ----------------------------------------------------
# One raw volume as u8, u16le, i16le and f32le: 150 columns are two full 64-voxel chunks a row
# (the vector loops) and a partial one (the scalar loop); three blobs with seeded noise give the
# surface many cube configurations. Then floats through and through: vertices placed by an odd
# spacing and origin, marching cubes with gradient normals and a picture, and `mvox demo` (the
# simulated scanner and the renderer).
say "the same runs with the x86-64 and the arm64 mvox"
work=$out/outputs
rm -rf "$work"
mkdir -p "$work"
size=150x60x40
python3 - "$work" <<'EOF_PY'
import array, math, random, sys
w, h, d = 150, 60, 40
rng = random.Random(13)
balls = [(40, 30, 20, 18), (95, 25, 15, 14), (120, 40, 28, 10)]
u8 = array.array('B')
for z in range(d):
    for y in range(h):
        for x in range(w):
            near = min(math.dist((x, y, z), b[:3]) / b[3] for b in balls)
            u8.append(max(0, min(255, int(200 - 100 * near + rng.uniform(-60, 60)))))
types = {'u8': u8, 'u16le': array.array('H', (v * 257 for v in u8)),
         'i16le': array.array('h', (v * 200 - 25000 for v in u8)),
         'f32le': array.array('f', (v * 0.01 - 1 for v in u8))}
for name, samples in types.items():
    if sys.byteorder == 'big':
        samples.byteswap()
    with open(f'{sys.argv[1]}/volume_{name}.raw', 'wb') as f:
        samples.tofile(f)
EOF_PY
# compare NAME ARGS...: `mvox ARGS...` on both processors, each in a directory of its own; every
# file left must be the same, byte for byte. libc6:arm64 is installed (step 1), so qemu-aarch64
# needs no -L (cmake/aarch64-linux-gnu.cmake).
compared=()
differing=()
compare() {
  local name=$1 file same=1
  shift
  mkdir -p "$work/x86_64/$name" "$work/aarch64/$name"
  (cd "$work/x86_64/$name" && "$x86_mvox" "$@") || { echo "$name: x86-64 mvox failed"; same=0; }
  (cd "$work/aarch64/$name" && qemu-aarch64 "$arm_mvox" "$@") || { echo "$name: arm64 mvox failed"; same=0; }
  [ "$(ls "$work/x86_64/$name")" = "$(ls "$work/aarch64/$name")" ] || same=0
  for file in "$work/x86_64/$name"/*; do
    cmp "$file" "$work/aarch64/$name/${file##*/}" || same=0
  done
  compared+=("$name")
  if [ "$same" -eq 1 ]; then
    echo "$name: identical ($(cd "$work/x86_64/$name" && stat -c '%n %s bytes' -- * | paste -sd ' '))"
  else
    differing+=("$name")
  fi
}
volume() { echo "$work/volume_$1.raw"; }
compare u8 extract "$(volume u8)" --raw "$size:u8" -t 128 -o mesh.ply -q
compare u16le extract "$(volume u16le)" --raw "$size:u16le" -t 32896 -o mesh.ply -q
compare i16le extract "$(volume i16le)" --raw "$size:i16le" -t 600 -o mesh.ply -q
compare f32le extract "$(volume f32le)" --raw "$size:f32le" -t 0.28 -o mesh.ply -q
compare u8-placed extract "$(volume u8)" --raw "$size:u8" -t 128 --spacing 0.7,0.3,1.1 \
  --origin 3.3,-1.7,0.1 -o mesh.obj -q
compare f32le-cubes-normals extract "$(volume f32le)" --raw "$size:f32le" -t 0.28 -o mesh.ply \
  --method cubes --normals --image picture.png -q
# STL's records have a path of their own without SSE2 (stl_triangle_records.cpp).
compare u8-stl extract "$(volume u8)" --raw "$size:u8" -t 128 -o mesh.stl -q
compare u16le-stl-placed extract "$(volume u16le)" --raw "$size:u16le" -t 32896 \
  --spacing 0.7,0.3,1.1 --origin 3.3,-1.7,0.1 -o mesh.stl -q
compare demo demo --size 64 -o mesh.ply --image picture.png -q

say "summary"
echo "arm64 core and sim tests under qemu-aarch64: $tests_line"
echo "arm64 mvox (no modules), outputs identical to x86-64's: $((${#compared[@]} - ${#differing[@]})) of ${#compared[@]} (${compared[*]})"
echo "time: ${SECONDS}s"
[ "$tests_ok" -eq 1 ] || die "some arm64 tests failed (log: $out/ctest.log)"
[ ${#differing[@]} -eq 0 ] || die "arm64 outputs differ from x86-64's: ${differing[*]} (in $work)"
echo "passed"
