#!/usr/bin/env bash
# Sourced by the install_*deps.sh scripts: apt_install NAME PACKAGE... installs the Debian
# packages that are missing (apt-get update first, only when something is missing), as root or
# through sudo. NAME prefixes the script's messages. Idempotent.
apt_install() {
  local name=$1
  shift
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "$name: all $# packages already installed"
    return 0
  fi
  local sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null 2>&1; then
      echo "$name: need root or sudo to run apt-get" >&2
      return 1
    fi
    sudo_cmd=(sudo)
  fi
  echo "$name: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
}
