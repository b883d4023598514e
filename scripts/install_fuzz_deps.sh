#!/usr/bin/env bash
# Installs what scripts/fuzz.sh needs on top of scripts/install_deps.sh: clang and its runtime
# libraries (libFuzzer, AddressSanitizer, UndefinedBehaviorSanitizer).
# Idempotent: apt-get skips packages that are already installed.
set -euo pipefail

packages=(
  clang                 # the compiler; libFuzzer is clang's
  libclang-rt-14-dev    # libFuzzer and the sanitizer runtimes for Debian's clang 14
)

source "$(dirname "$0")/apt_install.sh"
apt_install install_fuzz_deps.sh "${packages[@]}"
