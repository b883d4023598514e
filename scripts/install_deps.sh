#!/usr/bin/env bash
# Installs every Debian package mvox needs to build, test and benchmark.
# Idempotent: apt-get skips packages that are already installed.
set -euo pipefail

packages=(
  cmake g++ make pkg-config
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev  # slice images in and out
  # Only for --show's window, loaded at run time: it brings Qt, which mvox itself never links.
  libopencv-highgui-dev
  libglm-dev                                                        # vector math (header-only)
  zlib1g-dev                                                        # gzip NRRD and compressed MetaImage volumes
  libtiff-dev                                                       # multi-page TIFF stacks, read page by page
  libgdcm-dev                                                       # DICOM series (GDCM)
  libcli11-dev                                                      # command-line parsing
  googletest libgtest-dev                                           # tests
  time hyperfine                                                    # benchmarks (/usr/bin/time -v)
)

if [ "$(id -u)" -eq 0 ]; then
  sudo_cmd=()
elif command -v sudo >/dev/null 2>&1; then
  sudo_cmd=(sudo)
else
  echo "install_deps.sh: need root or sudo to run apt-get" >&2
  exit 1
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps.sh: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install_deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
