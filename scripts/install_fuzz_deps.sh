#!/usr/bin/env bash
# Installs what scripts/fuzz.sh needs on top of scripts/install_deps.sh: clang and its runtime
# libraries (libFuzzer, AddressSanitizer, UndefinedBehaviorSanitizer).
# Idempotent: apt-get skips packages that are already installed.
set -euo pipefail

packages=(
  clang                 # the compiler; libFuzzer is clang's
  libclang-rt-14-dev    # libFuzzer and the sanitizer runtimes for Debian's clang 14
)

if [ "$(id -u)" -eq 0 ]; then
  sudo_cmd=()
elif command -v sudo >/dev/null 2>&1; then
  sudo_cmd=(sudo)
else
  echo "install_fuzz_deps.sh: need root or sudo to run apt-get" >&2
  exit 1
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_fuzz_deps.sh: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install_fuzz_deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
