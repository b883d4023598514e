# Cross-compiling for 64-bit ARM (aarch64) on a Debian x86-64 machine, with Debian's
# g++-aarch64-linux-gnu. The host level's libraries (libtiff, libjpeg, libpng, zlib) and
# GoogleTest come from Debian's arm64 multiarch packages (libtiff-dev:arm64, ...), which put
# their libraries in /usr/lib/aarch64-linux-gnu; header-only GLM and CLI11 are shared with the
# build machine. Test programs run under qemu-aarch64 (qemu-user), through
# CMAKE_CROSSCOMPILING_EMULATOR, so ctest and gtest_discover_tests work as on a native build.
#
#   cmake -S . -B build-aarch64 --toolchain cmake/aarch64-linux-gnu.cmake
#
# scripts/test_aarch64.sh installs all this, builds and runs the tests.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# find_library and find_package then search /usr/lib/aarch64-linux-gnu, and never the build
# machine's /usr/lib/x86_64-linux-gnu.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# qemu-aarch64 runs the arm64 programs. When Debian's arm64 C library is installed (libc6:arm64,
# which every -dev:arm64 package brings), they find it and the multiarch libraries where an arm64
# machine has them; otherwise they take the cross compiler's copy (libc6-arm64-cross) through -L.
# Never a mix of the two: with -L, the loader comes from the cross copy but libc.so.6 from the
# multiarch one, and mvox then hangs as it starts a thread.
find_program(MVOX_QEMU_AARCH64 qemu-aarch64)
if(MVOX_QEMU_AARCH64 AND EXISTS /lib/ld-linux-aarch64.so.1)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${MVOX_QEMU_AARCH64})
elseif(MVOX_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${MVOX_QEMU_AARCH64} -L /usr/aarch64-linux-gnu)
endif()
