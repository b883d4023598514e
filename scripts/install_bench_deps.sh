#!/usr/bin/env bash
# Extra Debian packages for the benchmarks and the independent mesh checks (not needed to build
# or test mvox): Debian's VTK and scikit-image Python bindings. Idempotent; apt-get update first.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
packages=(python3 python3-vtk9 python3-numpy python3-skimage python3-matplotlib)
source "$(dirname "$0")/apt_install.sh"
apt_install install_bench_deps.sh "${packages[@]}"
