#!/usr/bin/env bash
# Renders the example pictures in docs/images/ from the paper's datasets (../shared/datasets)
# and the demo phantom, with the commands the README quotes. Needs a built build/src/mvox.
#   scripts/render_examples.sh [path/to/mvox]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
mvox=${1:-$root/build/src/mvox}
data=$root/../shared/datasets
out=$root/docs/images
size=256  # small enough to commit; the paper's pictures are 512x512 (the default)
mkdir -p "$out"

# CThead stores its slices from the top of the head down, hence the roll of 180 degrees.
"$mvox" extract "$data/cthead/CThead.*" --raw 256x256:u16be -t 600 --spacing 1,1,2 \
  --image "$out/cthead.png" --view -30,-10,180 --image-size $size -q
"$mvox" extract "$data/engine/engine_256x256x128_uint8.raw" --raw 256x256x128:u8 -t 100 \
  --image "$out/engine.png" --view 30,30 --image-size $size -q
# MRbrain's slices are sagittal, 2 units apart: looking along z shows the side of the head.
"$mvox" extract "$data/mrbrain8bit/mrbrain-8bit*.png" -t 50 --spacing 1,1,2 \
  --image "$out/mrbrain.png" --view 0,-90 --image-size $size -q
# The mesh itself, each face shaded flat by its own normal as a mesh viewer or a print shows it:
# CThead's skin with vertices at the midpoints (terraces), with --interpolate, with --smooth 10
# and with --interpolate --decimate 0.1.
tmp_meshes=$(mktemp -d)
for placement in midpoints interpolated smoothed decimated; do
  extra=()
  [ "$placement" = interpolated ] && extra=(--interpolate)
  [ "$placement" = smoothed ] && extra=(--smooth 10)
  [ "$placement" = decimated ] && extra=(--interpolate --decimate 0.1)
  "$mvox" extract "$data/cthead/CThead.*" --raw 256x256:u16be -t 600 --spacing 1,1,2 \
    -o "$tmp_meshes/$placement.ply" "${extra[@]}" -q
  "$mvox" render "$tmp_meshes/$placement.ply" -o "$out/cthead_$placement.png" --flat --cull \
    --view -30,-10,180 --image-size $size -q
done
rm -rf "$tmp_meshes"
# The demo phantom (no data needed): mvox demo writes demo.ply and demo.png, by default a
# cutaway (--view -30,55 --cut 0.45) that shows the bright ellipsoids inside the skull.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && "$mvox" demo -q --image "$out/demo.png" --image-size $size)
ls -l "$out"
