#!/usr/bin/env bash
# Extra Debian packages for the benchmarks and the independent mesh checks (not needed to build
# or test mvox): Debian's VTK and scikit-image Python bindings. Idempotent; apt-get update first.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
packages=(python3 python3-vtk9 python3-numpy python3-skimage python3-matplotlib)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && { echo "install_bench_deps.sh: all packages already installed"; exit 0; }
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
