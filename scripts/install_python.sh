#!/usr/bin/env bash
# Installs the Python module mvox into the system Python: builds it (build/, as the README's
# commands do) and copies it, with the modules that read DICOM and OpenCV's formats, into
# /usr/local/lib/python3.X/dist-packages, where Debian's python3 finds it in any folder.
# Idempotent. Needs root (or sudo) to write under /usr/local, and the packages of
# scripts/install_deps.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$root/build" -j"$(nproc)" --target mvox_python
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" cmake --install "$root/build" --component python
cd /
/usr/bin/python3 -c 'import mvox, numpy; m = mvox.extract(numpy.full((2, 2, 2), 9, numpy.uint8), 5); print("install_python.sh: import mvox works:", m)'
