#!/usr/bin/env bash
# The core as firmware: builds firmware_like/ and the demo program in firmware/ for a Cortex-M7
# board (ARM's MPS2 with the AN500 image, as QEMU emulates it) with arm-none-eabi-g++,
# newlib-nano, no exceptions, no RTTI, a static workspace and an allocator that traps; builds the
# same sources for the host with g++; runs both, and fails unless they print the same counts
# and checksums. Also checks that the board's image contains no allocator at all, and that an
# allocation, built in on purpose, does halt the program on both.
#
#   scripts/firmware_demo.sh [BUILD_DIR]     (default: build-firmware/ in the repository)
#
# Installs its Debian packages first (apt-get, idempotent). Takes about 15 s once they are
# installed: the builds, two QEMU runs of under a second each, two host runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build-firmware}")  # relative: from the caller's folder
cd "$root"
started=$SECONDS

# shellcheck source=scripts/apt_install.sh
source scripts/apt_install.sh
apt_install firmware_demo g++ libglm-dev gcc-arm-none-eabi libnewlib-arm-none-eabi \
  libstdc++-arm-none-eabi-newlib qemu-system-arm

# Every run builds from scratch (a few seconds): only a folder this script made is removed.
marker="$build/.firmware_demo_build"
if [ -e "$build" ] && [ ! -e "$marker" ] && [ -n "$(ls -A "$build")" ]; then
  echo "firmware_demo: $build exists and was not made by this script; give another folder" >&2
  exit 1
fi
rm -rf "$build"
mkdir -p "$build/include" "$build/host/core" "$build/arm/core"
touch "$marker"
# GLM (header-only) for the core's renderer files, without the rest of /usr/include: the cross
# compiler must see newlib's C headers, not glibc's.
ln -s /usr/include/glm "$build/include/glm"

# The core's sources, as firmware_like/CMakeLists.txt lists them for mvox_core.
mapfile -t core_sources < <(
  sed -n '/^add_library(mvox_core STATIC/,/)/p' firmware_like/CMakeLists.txt |
    sed -n 's|^ *\(src/[A-Za-z0-9_]*\.cpp\).*|firmware_like/\1|p')
[ ${#core_sources[@]} -gt 0 ] || { echo "firmware_demo: no core sources found" >&2; exit 1; }
# The program: the same files for both, but for its platform layer and the board's startup.
program_sources=(firmware/main.cpp firmware/traps.cpp firmware/sim_check_grid.cpp
  sim/shepp_logan.cpp)
host_sources=(firmware/platform_host.cpp)
board_sources=(firmware/startup_cortex_m.cpp firmware/platform_semihosting.cpp)

# Flags for both targets. The core's are those of firmware_like/CMakeLists.txt (Release);
# -ffp-contract=off keeps the compilers from fusing a*b+c into one rounding on the board's FPU
# (x86-64's baseline has no FMA), so the phantom's densities round alike on both.
common=(-std=c++17 -O2 -DNDEBUG -fno-exceptions -fno-rtti -fno-math-errno -ffp-contract=off
  -ffunction-sections -fdata-sections -Wall -Wextra -Ifirmware_like/include
  -isystem "$build/include")
core_flags=(-Wpedantic -Ifirmware_like/src)
program_flags=(-Isim -Ifirmware)
# Cortex-M7 with its double-precision FPU (FPv5-D16), Thumb-2, hard-float calling convention;
# newlib-nano's headers and libraries; no thread-safe statics (one thread, no guard library).
board=(-mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard --specs=nano.specs
  -fno-threadsafe-statics)

# compile CXX OBJECT_DIR SOURCE FLAG...: one object, named after its source.
compile() {
  local cxx=$1 dir=$2 source=$3
  shift 3
  nice "$cxx" "$@" -c "$source" -o "$dir/$(basename "${source%.cpp}").o"
}
# compile_all CXX OBJECT_DIR FLAGS_ARRAY_NAME SOURCE...: two at a time (the machine's cores).
compile_all() {
  local cxx=$1 dir=$2 source
  local -n flags=$3
  shift 3
  for source in "$@"; do
    while [ "$(jobs -pr | wc -l)" -ge 2 ]; do wait -n; done
    compile "$cxx" "$dir" "$source" "${flags[@]}" &
  done
  while [ "$(jobs -pr | wc -l)" -gt 0 ]; do wait -n; done
}
# shellcheck disable=SC2034  # used through compile_all's nameref
host_core=("${common[@]}" "${core_flags[@]}")
host_program=("${common[@]}" "${program_flags[@]}")
# shellcheck disable=SC2034
board_core=("${common[@]}" "${core_flags[@]}" "${board[@]}")
board_program=("${common[@]}" "${program_flags[@]}" "${board[@]}")

echo "== building the core and the demo for the host (g++)"
compile_all g++ "$build/host/core" host_core "${core_sources[@]}"
ar rcs "$build/host/libmvox_core.a" "$build/host/core"/*.o
compile_all g++ "$build/host" host_program "${program_sources[@]}" "${host_sources[@]}"
host_objects=("$build/host"/*.o)
g++ -Wl,--gc-sections "${host_objects[@]}" "$build/host/libmvox_core.a" \
  -o "$build/host/firmware_demo"

echo "== building the core and the demo for the board (arm-none-eabi-g++, Cortex-M7,"\
  "newlib-nano)"
compile_all arm-none-eabi-g++ "$build/arm/core" board_core "${core_sources[@]}"
arm-none-eabi-ar rcs "$build/arm/libmvox_core.a" "$build/arm/core"/*.o
compile_all arm-none-eabi-g++ "$build/arm" board_program "${program_sources[@]}" \
  "${board_sources[@]}"
board_objects=("$build/arm"/*.o)
# -nostartfiles: firmware/startup_cortex_m.cpp is the startup code. No syscall library
# (rdimon, nosys) is linked: the image needs none, and a reference to one would fail the link.
link_board() {  # link_board OUTPUT.elf OBJECT...
  local output=$1
  shift
  arm-none-eabi-g++ "${board[@]}" -nostartfiles -T firmware/mps2_an500.ld -Wl,--gc-sections \
    -Wl,-Map="${output%.elf}.map" "$@" "$build/arm/libmvox_core.a" -o "$output"
}
link_board "$build/arm/firmware_demo.elf" "${board_objects[@]}"

# The negative control: the same program with one allocation before the scan, on both.
mkdir -p "$build/host/allocate" "$build/arm/allocate"
compile g++ "$build/host/allocate" firmware/main.cpp "${host_program[@]}" -DFIRMWARE_DEMO_ALLOCATE
compile arm-none-eabi-g++ "$build/arm/allocate" firmware/main.cpp "${board_program[@]}" \
  -DFIRMWARE_DEMO_ALLOCATE
host_others=() board_others=()  # every object but main.o
for object in "${host_objects[@]}"; do [[ $object == */main.o ]] || host_others+=("$object"); done
for object in "${board_objects[@]}"; do [[ $object == */main.o ]] || board_others+=("$object"); done
g++ -Wl,--gc-sections "$build/host/allocate/main.o" "${host_others[@]}" \
  "$build/host/libmvox_core.a" -o "$build/host/firmware_demo_allocate"
link_board "$build/arm/firmware_demo_allocate.elf" "$build/arm/allocate/main.o" "${board_others[@]}"

run_board() {  # run_board ELF: QEMU, with the semihosting console on its standard error
  timeout 120 qemu-system-arm -M mps2-an500 -cpu cortex-m7 -nographic \
    -semihosting-config enable=on,target=native -kernel "$1" </dev/null 2>&1
}

echo "== running on the host"
host_status=0
"$build/host/firmware_demo" >"$build/host/output.txt" 2>&1 || host_status=$?
cat "$build/host/output.txt"
echo "== running on the board (qemu-system-arm -M mps2-an500 -cpu cortex-m7)"
board_status=0
run_board "$build/arm/firmware_demo.elf" >"$build/arm/output.txt" || board_status=$?
cat "$build/arm/output.txt"

failed=0
fail() {
  echo "firmware_demo: FAILED: $*" >&2
  failed=1
}
[ "$host_status" -eq 0 ] || fail "the host run exited with status $host_status"
[ "$board_status" -eq 0 ] || fail "the board run (QEMU) exited with status $board_status"

# The results: every line but the "target:" ones, which differ by platform (the build, the
# stack, the workspace's size with 32- or 64-bit pointers).
grep -v '^target:' "$build/host/output.txt" >"$build/host/results.txt" || true
grep -v '^target:' "$build/arm/output.txt" >"$build/arm/results.txt" || true
value() { sed -n "s/^$1: \([0-9a-fx]*\).*/\1/p" "$build/host/results.txt"; }
echo "== host and board compared"
if ! grep -qx 'result: ok' "$build/host/results.txt" || [ -z "$(value 'vertex checksum')" ] ||
  [ -z "$(value 'polygon checksum')" ]; then
  fail "the host run did not print its checksums and 'result: ok'"
elif ! diff -u --label host "$build/host/results.txt" --label board "$build/arm/results.txt"; then
  fail "the board's results differ from the host's"
else
  echo "identical on host and board: vertices $(value vertices), polygons $(value polygons)," \
    "vertex checksum $(value 'vertex checksum'), polygon checksum $(value 'polygon checksum')"
fi

echo "== no heap on the board"
# The image must hold no allocation function at all: neither newlib's allocator nor even
# traps.cpp's (which --gc-sections drops when nothing refers to them).
allocation_symbols='malloc|calloc|realloc|free|memalign|aligned_alloc|_sbrk|_sbrk_r'
allocation_symbols+='|_(malloc|calloc|realloc|free|memalign)_r'
allocation_symbols+='|__malloc_free_list|__malloc_sbrk_start'  # nano-mallocr's state'
allocation_symbols+='|_Zn[wa]j|_Zn[wa]jRKSt9nothrow_t|_Zn[wa]jSt11align_val_t.*'  # operator new
allocators=$(arm-none-eabi-nm "$build/arm/firmware_demo.elf" | awk '{print $NF}' |
  grep -E "^($allocation_symbols)\$" || true)
if [ -n "$allocators" ]; then
  fail "the board's image contains allocation functions: ${allocators//$'\n'/ }"
else
  echo "the image contains no allocation function (malloc, operator new, _sbrk: none)"
fi
# What the image takes from the C and compiler libraries (the linker map's archive members).
echo "library code in the image besides the core: $(
  sed -n '/^Archive member included/,/^Discarded/p' "$build/arm/firmware_demo.map" |
  grep -v libmvox_core |
  sed -n 's|^/.*/\(lib[a-z_+]*\.a\)(\(lib_a-\)\{0,1\}\([^)]*\)\.o)$|\3 (\1)|p' |
  sort | paste -sd ',' | sed 's/,/, /g')"

echo "== the allocator traps (negative control: one operator new before the scan)"
for target in host board; do
  status=0
  if [ $target = host ]; then
    output=$("$build/host/firmware_demo_allocate" 2>&1) || status=$?
  else
    output=$(run_board "$build/arm/firmware_demo_allocate.elf") || status=$?
  fi
  echo "$target: $(echo "$output" | grep '^halt:' || echo 'no halt line') (exit status $status)"
  if [ "$status" -ne 2 ] || ! grep -q '^halt: the program tried to allocate' <<<"$output"; then
    fail "on the $target, an allocation did not halt the program with status 2"
  fi
done

echo "== size of the board's image (arm-none-eabi-size)"
arm-none-eabi-size "$build/arm/firmware_demo.elf"
elf_size() {  # elf_size WHAT: a static variable's or a section's size in bytes
  arm-none-eabi-size -A "$build/arm/firmware_demo.elf" | awk -v s="$1" '$1 == s {print $2}'
}
symbol_bytes() {  # symbol_bytes NAME: the size of a static variable of firmware/main.cpp
  local hex
  hex=$(arm-none-eabi-nm -S -C "$build/arm/firmware_demo.elf" |
    awk -v name="$1" '$NF ~ name"$" {print $2}')
  echo $((16#$hex))
}
read -r text data bss _ < <(arm-none-eabi-size "$build/arm/firmware_demo.elf" | tail -1)
echo "flash: $((text + data)) bytes (text + data); RAM: $((data + bss)) bytes (data + bss), of" \
  "which the engine's static workspace $(symbol_bytes g_workspace), the slice" \
  "$(symbol_bytes g_slice), the stack $(elf_size .stack)"
grep '^target: engine workspace' "$build/host/output.txt" | sed 's/^target:/host: /'
grep '^target: engine workspace' "$build/arm/output.txt" | sed 's/^target:/board:/'

if [ "$failed" -ne 0 ]; then
  echo "firmware_demo: FAILED ($((SECONDS - started)) s)" >&2
  exit 1
fi
echo "firmware_demo: passed: host and board agree ($((SECONDS - started)) s)"
