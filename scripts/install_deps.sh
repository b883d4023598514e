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
  libjpeg-dev                                                       # JPEG slices, decoded strictly (libjpeg62-turbo)
  libpng-dev                                                        # grey PNG slices and pictures, without OpenCV
  libgdcm-dev                                                       # DICOM series (GDCM)
  libcli11-dev                                                      # command-line parsing
  libmeshoptimizer-dev                                              # --decimate (meshopt_simplify)
  googletest libgtest-dev                                           # tests
  xvfb                                                              # the --show window's test, on a virtual display
  strace                                                            # --sync's test sees mvox's fsync calls
  pybind11-dev python3-dev python3-numpy python3-pytest             # the Python module and its tests
  python3-meshio                                                    # the Python tests read mvox.write's files with it
  libopenmpi-dev openmpi-bin                                        # mvox-mpi (only it links MPI) and mpirun
  time hyperfine                                                    # benchmarks (/usr/bin/time -v)
)

source "$(dirname "$0")/apt_install.sh"
apt_install install_deps.sh "${packages[@]}"
