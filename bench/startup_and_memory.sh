#!/usr/bin/env bash
# Start-up and memory of whole `mvox` processes, side by side with C++ hello-worlds: a plain
# one, and the same linked to Debian's OpenCV image codecs or to GDCM alone, the libraries mvox
# loads only when an input needs them. Prints a Markdown table of medians over RUNS runs: wall
# time (hyperfine, no shell) and peak resident memory (/usr/bin/time), for one binary or for two
# side by side (say, before and after a change).
#   bench/startup_and_memory.sh MVOX [MVOX_BEFORE] [RUNS] [DATASETS_DIR]
# Inputs: the paper's engine (raw, 256x256x128 u8, and the same written as a multi-page TIFF by
# bench/raw_to_tiff.py) and MRbrain (a PNG stack), CThead (raw slices), the tooth (NRRD) and a
# DICOM series from DATASETS_DIR (default ../shared/datasets); rows whose data are absent are
# left out.
set -euo pipefail
after=$(realpath "$1")
before=${2:+$(realpath "$2")}
runs=${3:-10}
repo=$(cd "$(dirname "$0")/.." && pwd)
datasets=${4:-$repo/../shared/datasets}
for tool in hyperfine /usr/bin/time g++ python3; do
  command -v "$tool" > /dev/null || { echo "$0: needs $tool" >&2; exit 1; }
done
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"

# The hello-worlds: what a process costs before it does anything.
# The C++ one with iostream, as textbooks write it; the stdio one is the floor of a process that
# links libstdc++.
cat > hello.cpp << 'EOF'
#include <iostream>
int main() { std::cout << "hello\n"; }
EOF
cat > hello_stdio.cpp << 'EOF'
#include <cstdio>
int main() { std::puts("hello"); }
EOF
g++ -O2 hello.cpp -o hello
g++ -O2 hello_stdio.cpp -o hello_stdio
g++ -O2 hello.cpp -o hello_imgcodecs -Wl,--no-as-needed -lopencv_imgcodecs -lopencv_core
g++ -O2 hello.cpp -o hello_gdcm -Wl,--no-as-needed -lgdcmMSFF

# Median of the numbers on standard input.
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }

# Runs before each timed run (and is not timed): set by a row whose command leaves what would
# make the next run fail.
prepare="true"
# wall_ms COMMAND...: median wall time in milliseconds.
wall_ms() {
  hyperfine -N --warmup 2 --runs "$runs" --prepare "$prepare" --export-json t.json "$*" \
    > /dev/null 2>&1
  python3 -c 'import json, statistics; print("%.1f" % (1000 * statistics.median(json.load(open("t.json"))["results"][0]["times"])))'
}
# peak_mib COMMAND...: median peak resident memory in MiB.
peak_mib() {
  for _ in $(seq "$runs"); do
    $prepare
    /usr/bin/time -f %M -o m.txt "$@" > /dev/null 2>&1 || true
    cat m.txt
  done | median | awk '{ printf "%.1f", $1 / 1024 }'
}
row() {
  local title=$1 shown=$2
  shift 2
  local cells="$(wall_ms "$@") ms | $(peak_mib "$@") MiB"
  if [ -n "$before" ] && [ "$1" = "$after" ]; then
    local old=("$before" "${@:2}")
    cells="$(wall_ms "${old[@]}") ms | $(peak_mib "${old[@]}") MiB | $cells"
  elif [ -n "$before" ]; then
    cells="| | $cells"
  fi
  printf '| %s | `%s` | %s |\n' "$title" "$shown" "$cells"
}

if [ -n "$before" ]; then
  echo "| what | command | wall, before | peak, before | wall | peak |"
  echo "|---|---|---|---|---|---|"
else
  echo "| what | command | wall | peak |"
  echo "|---|---|---|---|"
fi
row "C++ hello-world (iostream)" "hello" ./hello
row "C++ hello-world (stdio)" "hello_stdio" ./hello_stdio
row "the same, linked to OpenCV's imgcodecs" "hello_imgcodecs" ./hello_imgcodecs
row "the same, linked to GDCM's MSFF" "hello_gdcm" ./hello_gdcm
row "mvox --help" "mvox --help" "$after" --help
prepare="rm -rf s"
row "mvox phantom (PNG slices)" "mvox phantom sphere -o s --size 64x64x64" \
  "$after" phantom sphere -o s --size 64x64x64 -q
prepare="true"
row "mvox demo (PLY and PNG)" "mvox demo --size 64" "$after" demo --size 64 -o d.ply --image d.png -q
engine=$datasets/engine/engine_256x256x128_uint8.raw
if [ -f "$engine" ]; then
  # Start-up alone: the headers read, the memory planned, nothing extracted.
  row "engine, raw, --dry-run (start-up)" "mvox extract engine.raw --raw 256x256x128:u8 -t 100 -o e.ply --dry-run" \
    "$after" extract "$engine" --raw 256x256x128:u8 -t 100 -o e.ply --dry-run
  row "engine, raw -> PLY" "mvox extract engine.raw --raw 256x256x128:u8 -t 100 -o e.ply" \
    "$after" extract "$engine" --raw 256x256x128:u8 -t 100 -o e.ply -q
  row "engine, raw -> PLY + PNG" "... --image e.png" \
    "$after" extract "$engine" --raw 256x256x128:u8 -t 100 -o e.ply --image e.png -q
  # The same volume as one multi-page TIFF (uncompressed, as ImageJ saves a stack).
  python3 "$repo/bench/raw_to_tiff.py" "$engine" 256 256 128 engine.tif
  row "engine, TIFF, --dry-run (start-up)" "mvox extract engine.tif -t 100 -o e.ply --dry-run" \
    "$after" extract engine.tif -t 100 -o e.ply --dry-run
  row "engine, TIFF -> PLY" "mvox extract engine.tif -t 100 -o e.ply" \
    "$after" extract engine.tif -t 100 -o e.ply -q
fi
if [ -d "$datasets/cthead" ]; then
  row "CThead, raw slices -> PLY" "mvox extract cthead/CThead.* --raw 256x256:u16be -t 600 -o c.ply" \
    "$after" extract "$datasets/cthead/CThead.*" --raw 256x256:u16be -t 600 -o c.ply -q
fi
if [ -f "$datasets/tooth/tooth.nrrd" ]; then
  row "tooth, NRRD, --dry-run (start-up)" "mvox extract tooth.nrrd -t 100 -o t.ply --dry-run" \
    "$after" extract "$datasets/tooth/tooth.nrrd" -t 100 -o t.ply --dry-run
  row "tooth, NRRD -> PLY" "mvox extract tooth.nrrd -t 100 -o t.ply" \
    "$after" extract "$datasets/tooth/tooth.nrrd" -t 100 -o t.ply -q
fi
if [ -d "$datasets/mrbrain8bit" ]; then
  row "MRbrain, PNG stack -> PLY" "mvox extract 'mrbrain-8bit*.png' -t 50 -o b.ply" \
    "$after" extract "$datasets/mrbrain8bit/mrbrain-8bit*.png" -t 50 -o b.ply -q
fi
if [ -d "$datasets/dicom_mr_bbmri_6slices" ]; then
  row "DICOM series (6 MR slices) -> PLY" "mvox extract dicom_mr_bbmri_6slices -t 300 -o m.ply" \
    "$after" extract "$datasets/dicom_mr_bbmri_6slices" -t 300 -o m.ply -q
fi
echo
echo "Medians of $runs runs each; hyperfine -N (no shell) for wall time, /usr/bin/time for peak"
echo "resident memory; $(nproc) cores, $(date -u +%Y-%m-%d)."
