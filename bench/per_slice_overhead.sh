#!/usr/bin/env bash
# End-to-end `mvox extract` times on volumes of many small slices, where a fixed cost per slice
# (a thread handoff, a system call, clock readings) shows, and on the paper's datasets, where it
# must not: two binaries side by side, RUNS runs of every case, the binaries interleaved, and a
# Markdown table of the medians (wall clock, and user + system CPU seconds).
#   bench/per_slice_overhead.sh MVOX_BEFORE MVOX_AFTER [RUNS] [DATASETS_DIR]
# Inputs are made in a scratch directory with python3 (seeded, so the same on every machine):
# 1x1x5000000 and 1x1x200000 random bytes, 4x4x200000 random bytes, a 64x64x100000 tube whose
# radius varies along z (400 MB), and an 8x8x20000 PNG stack (`mvox phantom sphere`).
set -euo pipefail
before=$(realpath "$1")
after=$(realpath "$2")
runs=${3:-5}
repo=$(cd "$(dirname "$0")/.." && pwd)
datasets=${4:-$repo/../shared/datasets}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

python3 - "$scratch" << 'EOF_PY'
import math, random, sys
out = sys.argv[1]
rng = random.Random(11)
for name, size in [("line5m.raw", 5000000), ("line200k.raw", 200000), ("thin4.raw", 16 * 200000)]:
    with open(f"{out}/{name}", "wb") as f:
        f.write(rng.randbytes(size))
side = 64
discs = {}
def disc(radius):
    key = round(radius * 4)
    if key not in discs:
        r = key / 4
        discs[key] = bytes(max(0, min(255, int(128 + 40 * (r - math.hypot(x - 31.5, y - 31.5)))))
                           for y in range(side) for x in range(side))
    return discs[key]
with open(f"{out}/tube.raw", "wb") as f:
    for z in range(100000):
        f.write(disc(14 + 10 * math.sin(z / 37.0) + 4 * math.sin(z / 5.3)))
EOF_PY
"$before" phantom sphere -o "$scratch/sphere" --size 8x8x20000 -q

names=()
commands=()
add() { names+=("$1"); commands+=("$2"); }
add "1x1x5000000 raw" 'extract $S/line5m.raw --raw 1x1x5000000:u8 -t 128 -o $S/out.ply'
add "1x1x200000 raw" 'extract $S/line200k.raw --raw 1x1x200000:u8 -t 128 -o $S/out.ply'
add "1x1x200000 raw, --image --normals" 'extract $S/line200k.raw --raw 1x1x200000:u8 -t 128 -o $S/out.ply --image $S/out.png --normals'
add "4x4x200000 raw" 'extract $S/thin4.raw --raw 4x4x200000:u8 -t 128 -o $S/out.ply'
add "4x4x200000 raw, --image --normals" 'extract $S/thin4.raw --raw 4x4x200000:u8 -t 128 -o $S/out.ply --image $S/out.png --normals'
add "64x64x100000 raw" 'extract $S/tube.raw --raw 64x64x100000:u8 -t 128 -o $S/out.ply'
add "8x8x20000 PNG stack" 'extract $S/sphere -t 128 -o $S/out.ply'
add "8x8x20000 PNG stack, --image" 'extract $S/sphere -t 128 -o $S/out.ply --image $S/out.png'
if [ -d "$datasets/cthead" ]; then
  add "CThead 256x256x113 (raw slices)" 'extract "$D/cthead/CThead.*" --raw 256x256:u16be -t 600 --spacing 1,1,2 -o $S/out.ply --image $S/out.png'
fi
if [ -d "$datasets/engine" ]; then
  add "engine 256x256x128 (raw volume)" 'extract $D/engine/engine_256x256x128_uint8.raw --raw 256x256x128:u8 -t 100 -o $S/out.ply --image $S/out.png'
fi
if [ -d "$datasets/mrbrain8bit" ]; then
  add "MRbrain 256x256x99 (PNG)" 'extract "$D/mrbrain8bit/mrbrain-8bit*.png" -t 50 --spacing 1,1,2 -o $S/out.ply --image $S/out.png'
fi

for run in $(seq "$runs"); do
  for i in "${!names[@]}"; do
    for side in before after; do
      binary=$([ "$side" = before ] && echo "$before" || echo "$after")
      S=$scratch D=$datasets /usr/bin/time -f "%e %U %S" -o "$scratch/time" \
        bash -c "\"$binary\" ${commands[$i]} -q"
      echo "$(cat "$scratch/time")" >> "$scratch/$side.$i"
    done
  done
done

median() { sort -n | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }
echo "| case | before: wall (CPU) | after: wall (CPU) | speed-up (wall) |"
echo "|---|---|---|---|"
for i in "${!names[@]}"; do
  bw=$(awk '{print $1}' "$scratch/before.$i" | median)
  bc=$(awk '{print $2 + $3}' "$scratch/before.$i" | median)
  aw=$(awk '{print $1}' "$scratch/after.$i" | median)
  ac=$(awk '{print $2 + $3}' "$scratch/after.$i" | median)
  awk -v n="${names[$i]}" -v bw="$bw" -v bc="$bc" -v aw="$aw" -v ac="$ac" \
    'BEGIN { printf "| %s | %.2f s (%.2f s) | %.2f s (%.2f s) | %.1fx |\n", n, bw, bc, aw, ac, bw / aw }'
done
echo
echo "Medians of $runs runs, interleaved; CPU is user + system seconds."
