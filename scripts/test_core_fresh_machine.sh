#!/usr/bin/env bash
# The core on a fresh Debian machine: builds a minimal Debian 12 (bookworm) chroot with
# debootstrap, installs in it only a compiler, CMake, GLM and GoogleTest
# (g++ cmake make libglm-dev googletest libgtest-dev, --no-install-recommends), checks that
# the host libraries (OpenCV, GDCM, libtiff, libjpeg, zlib, CLI11) are truly absent there,
# copies the working tree's tracked files into it (uncommitted edits included) and runs
#
#   cmake -S . -B build-core -DMVOX_BUILD_HOST=OFF -DMVOX_BUILD_CLI=OFF
#   cmake --build build-core && ctest --test-dir build-core -L core
#
# inside it, with the same "no host library was looked for" check as test_core_only.sh.
# Prints the ctest summary; exits non-zero on any failure.
#
# Needs root (debootstrap, chroot, mount) and Debian's package mirror. Takes about 2 minutes
# the first time on 2 cores (debootstrap ~30 s and the packages ~10 s with a fast mirror, longer
# with a slow one; build and tests ~1 min) and about 1 minute when the chroot is reused (an
# existing chroot skips debootstrap). The chroot takes about 800 MB.
#
#   sudo scripts/test_core_fresh_machine.sh [CHROOT_DIR]   # default: /tmp/mvox-fresh-chroot
#
# Environment: MVOX_DEBIAN_MIRROR (default http://deb.debian.org/debian),
# MVOX_DEBIAN_SECURITY_MIRROR (default http://deb.debian.org/debian-security),
# MVOX_JOBS (default: nproc), MVOX_WITH_UNTRACKED=1 to copy untracked, not ignored files too
# (new files not yet `git add`ed).
set -euo pipefail

root=${1:-/tmp/mvox-fresh-chroot}
repo=$(cd "$(dirname "$0")/.." && pwd)
mirror=${MVOX_DEBIAN_MIRROR:-http://deb.debian.org/debian}
security_mirror=${MVOX_DEBIAN_SECURITY_MIRROR:-http://deb.debian.org/debian-security}
jobs=${MVOX_JOBS:-$(nproc)}
packages=(g++ cmake make libglm-dev googletest libgtest-dev)
absent=(libopencv-dev libgdcm-dev libtiff-dev libjpeg-dev zlib1g-dev libcli11-dev)
# Headers the absent packages would bring: none may be in the chroot by any other way either.
absent_headers=(usr/include/opencv4 usr/include/gdcm-3.0 usr/include/tiffio.h
                usr/include/jpeglib.h usr/include/zlib.h usr/include/CLI/CLI.hpp)
marker=.mvox-fresh-chroot-ready
me=test_core_fresh_machine.sh

say() { printf '\n== %s: %s (%ds)\n' "$me" "$*" "$SECONDS"; }
die() { echo "$me: $*" >&2; exit 1; }

[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot, mount): run it with sudo"
root=$(mkdir -p "$root" && cd "$root" && pwd)
[ "$root" != / ] || die "refusing to use / as the chroot"

in_chroot() {
  chroot "$root" /usr/bin/env -i HOME=/root LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin "$@"
}

cleanup() {
  if mountpoint -q "$root/proc" 2>/dev/null; then
    umount "$root/proc" || umount -l "$root/proc" || true
  fi
}
trap cleanup EXIT

# 1. The chroot: a minimal bookworm, made once and reused while its marker is there. -----------
if [ -f "$root/$marker" ]; then
  say "reusing the chroot in $root"
else
  if [ -n "$(ls -A "$root")" ]; then
    die "$root is not empty and holds no finished chroot ($marker missing): remove it or name another directory"
  fi
  if ! command -v debootstrap > /dev/null; then
    say "installing debootstrap on this machine"
    apt-get update -qq
    apt-get install -y -qq debootstrap > /dev/null
  fi
  say "debootstrap --variant=minbase bookworm $root $mirror"
  nice debootstrap --variant=minbase bookworm "$root" "$mirror" > "$root.debootstrap.log" 2>&1 \
    || { tail -n 30 "$root.debootstrap.log" >&2; die "debootstrap failed (log: $root.debootstrap.log)"; }
  cat > "$root/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
deb $security_mirror bookworm-security main
EOF
  touch "$root/$marker"
fi

# Name resolution for apt inside the chroot.
cp -L /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
mountpoint -q "$root/proc" || mount -t proc proc "$root/proc"

# 2. Only the compiler, CMake, GLM and GoogleTest. --------------------------------------------
say "apt-get update and install ${packages[*]} in the chroot"
in_chroot apt-get update -qq
in_chroot nice apt-get install -y -qq --no-install-recommends "${packages[@]}" > "$root.apt.log" 2>&1 \
  || { tail -n 30 "$root.apt.log" >&2; die "apt-get install failed in the chroot (log: $root.apt.log)"; }
installed=$(in_chroot dpkg -l | grep -c '^ii' || true)
echo "packages installed in the chroot: $installed ('dpkg -l | wc -l': $(in_chroot dpkg -l | wc -l) lines)"

# 3. The host libraries are truly absent. ------------------------------------------------------
present=()
for p in "${absent[@]}"; do
  if in_chroot dpkg -s "$p" > /dev/null 2>&1; then present+=("$p"); fi
done
for h in "${absent_headers[@]}"; do
  if [ -e "$root/$h" ]; then present+=("/$h"); fi
done
[ ${#present[@]} -eq 0 ] || die "the chroot is not bare: ${present[*]} present"
echo "absent, as they should be: ${absent[*]}"

# 4. The working tree's tracked files (uncommitted edits included; deleted files skipped). ------
ls_opts=(--cached)
what="tracked files"
if [ "${MVOX_WITH_UNTRACKED:-0}" = 1 ]; then
  ls_opts+=(--others --exclude-standard)
  what="tracked and untracked, not ignored files"
fi
say "copying $repo's $what to $root/mvox"
rm -rf "$root/mvox"
mkdir -p "$root/mvox"
git -c safe.directory="$repo" -C "$repo" ls-files -z "${ls_opts[@]}" \
  | (cd "$repo" && while IFS= read -r -d '' f; do
       if [ -e "$f" ] || [ -L "$f" ]; then printf '%s\0' "$f"; fi
     done) \
  | tar -C "$repo" --null --no-recursion -T - -cf - \
  | tar -C "$root/mvox" -xf -
echo "copied $(find "$root/mvox" -type f | wc -l) files"
if [ "${MVOX_WITH_UNTRACKED:-0}" != 1 ]; then
  untracked=$(git -c safe.directory="$repo" -C "$repo" ls-files --others --exclude-standard | wc -l)
  if [ "$untracked" -gt 0 ]; then
    echo "note: $untracked untracked files were not copied (git add them, or MVOX_WITH_UNTRACKED=1 copies them)"
  fi
fi

# 5. Configure, build, test the core inside the chroot. ---------------------------------------
say "configure, build and ctest -L core in the chroot (-j$jobs)"
cat > "$root/mvox-run.sh" <<EOF
set -euo pipefail
cd /mvox
cmake -S . -B build-core -DMVOX_BUILD_HOST=OFF -DMVOX_BUILD_CLI=OFF
looked_up=\$(grep -E '^(GDCM_DIR|OpenCV_DIR|MVOX_OPENCV_[A-Za-z_]*|TIFF_[A-Z_]*|JPEG_[A-Z_]*|ZLIB_[A-Z_]*|CLI11_DIR)[:=]' \\
  build-core/CMakeCache.txt || true)
if [ -n "\$looked_up" ]; then
  echo "the core's build looked for host libraries:" >&2
  echo "\$looked_up" >&2
  exit 1
fi
nice cmake --build build-core -j$jobs
nice ctest --test-dir build-core -L core --output-on-failure -j$jobs
EOF
log="$root.build.log"
status=0
in_chroot bash /mvox-run.sh > "$log" 2>&1 || status=$?
if [ "$status" -ne 0 ]; then
  tail -n 60 "$log" >&2
  die "configure, build or a core test failed in the chroot (exit $status; full log: $log)"
fi

say "done"
grep -E 'tests passed|tests failed|Total Test time' "$log" || true
echo "full log: $log"
