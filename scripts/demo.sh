#!/usr/bin/env bash
# Sets up a fresh Debian machine and runs the main job on its built-in default: installs the
# dependencies, builds mvox (Release) and runs `mvox demo`, which streams a 3-D Shepp-Logan head
# phantom through the engine and writes demo.ply and its picture demo.png in the current
# directory.
# Extra arguments go to `mvox demo` (try --help).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$root/build" -j"$(nproc)" --target mvox mvox_python
"$root/scripts/install_python.sh" > /dev/null  # import mvox from any folder (README, Python)
"$root/build/src/mvox" demo "$@"
