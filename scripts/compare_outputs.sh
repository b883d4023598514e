#!/usr/bin/env bash
# Byte-for-byte check for refactors that must not change any output: runs the same set of
# `mvox extract` commands with two binaries (say, one built before a change and one after) on the
# same inputs, and compares everything each command left: the mesh in every format, the picture,
# the frames, standard output, standard error, the exit code, and the --stats report less the
# lines that differ from run to run (times, memory). Prints one line per case that differs and a
# closing count; exits 1 when any case differs.
#
#   cp build/src/mvox /tmp/mvox-before     # before the change
#   ...change, rebuild...
#   scripts/compare_outputs.sh /tmp/mvox-before build/src/mvox [DATASETS_DIR]
#
# The inputs are made here with the first binary's `mvox phantom` and from /dev/urandom (random
# bytes are the hardest case for a mesher: a surface almost everywhere), so both binaries read
# the very same files. Shapes cover the per-slice paths: many 1x1 and 4x4 slices, larger ones,
# 16-bit and float samples with byte swaps, a pipe, a file cut short and a pipe too long or too
# short (the error must come at the same slice, with the same message), and PNG stacks. The
# paper's datasets are added when DATASETS_DIR (default ../shared/datasets) holds them.
#
# AFTER_ARGS, when set, is added to every `extract` the second binary runs: the same binary on
# both sides with AFTER_ARGS='--threads 3 --slab-slices 4' checks that slab-parallel runs write
# what one thread writes, on every case.
#   AFTER_ARGS='--threads 3 --slab-slices 4' scripts/compare_outputs.sh build/src/mvox build/src/mvox
set -uo pipefail

if [ $# -lt 2 ]; then
  echo "usage: $0 MVOX_BEFORE MVOX_AFTER [DATASETS_DIR]" >&2
  exit 2
fi
before=$(realpath "$1")
after=$(realpath "$2")
repo=$(cd "$(dirname "$0")/.." && pwd)
datasets=${3:-$repo/../shared/datasets}
for binary in "$before" "$after"; do
  [ -x "$binary" ] || { echo "$0: $binary is not an executable" >&2; exit 2; }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
inputs=$work/inputs
mkdir -p "$inputs"

# --- inputs -----------------------------------------------------------------------------------
random_file() { head -c "$2" /dev/urandom > "$inputs/$1"; }
random_file line.raw 20000                 # 1x1x20000 u8
random_file thin4.raw $((4 * 4 * 20000))   # 4x4x20000 u8
random_file odd.raw $((3 * 5 * 3000 * 2))  # 3x5x3000 16-bit
random_file float.raw $((2 * 3 * 2000 * 4))  # 2x3x2000 f32le
random_file mid.raw $((64 * 64 * 300))     # 64x64x300 u8
random_file big.raw $((300 * 200 * 6))     # 300x200x6 u8: slices larger than any small batch
head -c 12345 "$inputs/line.raw" > "$inputs/short_line.raw"  # cut short
mkdir -p "$inputs/per_slice"
head -c 800 "$inputs/thin4.raw" | (cd "$inputs/per_slice" && split -b 4 -a 3 -d - s)  # 200 of 2x2
"$before" phantom sphere -o "$inputs/sphere" --size 8x8x3000 -q
"$before" phantom blobs -o "$inputs/blobs" --size 40x30x60 --bits 16 -q
"$before" phantom torus -o "$inputs/torus" --size 64x64x64 -q
random_file small.raw $((24 * 20 * 50))    # 24x20x50 u8
# small.raw with oriented axes, rotated and mirrored (determinant -1), spacing and an origin: the
# writers' general placement, and mirrored winding.
cat > "$inputs/small_mirrored.nhdr" << 'NRRD'
NRRD0004
type: uint8
dimension: 3
sizes: 24 20 50
space: right-anterior-superior
space directions: (0,-0.5,0) (-0.75,0,0) (0,0.1,1.5)
space origin: (10.25,-20,3.5)
encoding: raw
data file: small.raw
NRRD

# --- cases ------------------------------------------------------------------------------------
# Each case is a shell command run in a directory of its own, with $MVOX the binary and $IN the
# inputs. Outputs are written there under relative names.
names=()
commands=()
add() { names+=("$1"); commands+=("$2"); }

add line-ply '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --stats s.json -q'
add line-all '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --normals --image p.png --stats s.json -q'
add line-ascii '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --ascii -q'
add line-stl '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.stl --image p.png --flat -q'
add line-obj '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.obj --normals -q'
add small-stl-placed '$MVOX extract $IN/small.raw --raw 24x20x50:u8 -t 128 -o m.stl --spacing 0.3,0.7,2.5 --origin -12.5,3.25,0.001 -q'
add small-stl-mirrored '$MVOX extract $IN/small_mirrored.nhdr -t 128 -o m.stl -q'
add small-ascii-mirrored '$MVOX extract $IN/small_mirrored.nhdr -t 128 -o m.ply --ascii --normals -q'
add small-tri-mirrored '$MVOX extract $IN/small_mirrored.nhdr -t 128 -o m.ply --triangulate --normals -q'
add line-tri '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --triangulate --spacing 1,2,0.5 -q'
add line-cubes '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --method cubes --normals --stats s.json -q'
add line-literal '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --engine literal --stats s.json -q'
add line-table1 '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o m.ply --surface paper-table1 -q'
add line-frames '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 --image p.png --frames f --every 2500 -q'
add line-stdout '$MVOX extract $IN/line.raw --raw 1x1x20000:u8 -t 128 -o - -q'
add line-pipe 'cat $IN/line.raw | $MVOX extract /dev/stdin --raw 1x1x20000:u8 -t 128 -o m.ply --stats s.json -q'
add line-2d '$MVOX extract $IN/line.raw --raw 100x100x2:u8 -t 128 -o m.ply -q'  # two slices: one cube layer
add line-short '$MVOX extract $IN/short_line.raw --raw 1x1x20000:u8 -t 128 -o m.ply -q'
add pipe-short 'cat $IN/short_line.raw | $MVOX extract /dev/stdin --raw 1x1x20000:u8 -t 128 -o m.ply -q'
add pipe-long 'cat $IN/line.raw $IN/line.raw | $MVOX extract /dev/stdin --raw 1x1x20000:u8 -t 128 -o m.ply -q'
add pipe-slow '(head -c 7000 $IN/line.raw; sleep 0.3; tail -c +7001 $IN/line.raw) | $MVOX extract /dev/stdin --raw 1x1x20000:u8 -t 128 -o m.ply --image p.png --normals -q'
add thin4 '$MVOX extract $IN/thin4.raw --raw 4x4x20000:u8 -t 128 -o m.ply --stats s.json -q'
add thin4-all '$MVOX extract $IN/thin4.raw --raw 4x4x20000:u8 -t 128 -o m.ply --normals --image p.png --stats s.json -q'
add thin4-obj '$MVOX extract $IN/thin4.raw --raw 4x4x20000:u8 -t 100 -o m.obj --view 30,20 --image p.png -q'
add odd-u16be '$MVOX extract $IN/odd.raw --raw 3x5x3000:u16be -t 30000 -o m.ply --normals --image p.png --stats s.json -q'
add odd-i16le '$MVOX extract $IN/odd.raw --raw 3x5x3000:i16le -t 100 -o m.ply --stats s.json -q'
add odd-pipe 'cat $IN/odd.raw | $MVOX extract /dev/stdin --raw 3x5x3000:u16be -t 30000 -o m.ply -q'
add float '$MVOX extract $IN/float.raw --raw 2x3x2000:f32le -t 0 -o m.ply --normals --stats s.json -q'
add mid '$MVOX extract $IN/mid.raw --raw 64x64x300:u8 -t 128 -o m.ply --normals --image p.png --stats s.json -q'
add mid-obj '$MVOX extract $IN/mid.raw --raw 64x64x300:u8 -t 128 -o m.obj --normals --spacing 0.3,0.7,2.5 --origin -12.5,3.25,0.001 -q'
add mid-ascii '$MVOX extract $IN/mid.raw --raw 64x64x300:u8 -t 128 -o m.ply --ascii --normals -q'
add mid-pipe 'cat $IN/mid.raw | $MVOX extract /dev/stdin --raw 64x64x300:u8 -t 128 -o m.ply -q'
add big '$MVOX extract $IN/big.raw --raw 300x200x6:u8 -t 128 -o m.ply --image p.png --stats s.json -q'
add sphere '$MVOX extract $IN/sphere -t 128 -o m.ply --normals --image p.png --stats s.json -q'
add sphere-frames '$MVOX extract $IN/sphere -t 128 --image p.png --frames f --every 700 -q'
add blobs '$MVOX extract $IN/blobs -t 30000 -o m.obj --normals --image p.png --stats s.json -q'
add torus '$MVOX extract $IN/torus -t 128 -o m.stl --image p.png --perspective --stats s.json -q'
add per-slice '$MVOX extract "$IN/per_slice/s*" --raw 2x2:u8 -t 128 -o m.ply --image p.png --stats s.json -q'
if [ -d "$datasets/cthead" ]; then
  add cthead '$MVOX extract "$DATA/cthead/CThead.*" --raw 256x256:u16be -t 600 --spacing 1,1,2 -o m.ply --image p.png --stats s.json -q'
fi
if [ -d "$datasets/engine" ]; then
  add engine '$MVOX extract $DATA/engine/engine_256x256x128_uint8.raw --raw 256x256x128:u8 -t 100 -o m.ply --normals --image p.png --stats s.json -q'
  add engine-obj '$MVOX extract $DATA/engine/engine_256x256x128_uint8.raw --raw 256x256x128:u8 -t 100 -o m.obj --normals --spacing 0.9,0.9,1.3 -q'
fi
if [ -d "$datasets/mrbrain8bit" ]; then
  add mrbrain '$MVOX extract "$DATA/mrbrain8bit/mrbrain-8bit*.png" -t 50 --spacing 1,1,2 -o m.ply --image p.png --stats s.json -q'
fi

# --- runs -------------------------------------------------------------------------------------
# run_all SIDE BINARY: every case into $work/SIDE/NAME.
run_all() {
  local side=$1 binary=$2 i dir
  for i in "${!names[@]}"; do
    dir=$work/$side/${names[$i]}
    mkdir -p "$dir"
    (
      cd "$dir" || exit 1
      MVOX=$binary IN=$inputs DATA=$datasets bash -c "${commands[$i]}" > stdout 2> stderr
      echo $? > exit_code
    )
    # Messages name the binary: make that the same word on both sides.
    sed -i "s|$binary|mvox|g" "$dir/stderr"
    # The report less what differs between runs of one binary, and with AFTER_ARGS the
    # renderer's work counters (triangles drawn or hidden, fragments written): they count what
    # the drawing order made it do, and slab workers draw in another order (the picture is the
    # same; README, Threads).
    # The chunks a slab worker took depend on how far ahead of the writer it got.
    local varying='time_seconds|extract_mvoxels_per_second|start_memory_bytes|peak_memory_bytes|job_memory_bytes|memory_plan|slab_chunks_taken'
    [ -n "${AFTER_ARGS:-}" ] && varying="$varying|render"
    if [ -f "$dir/s.json" ]; then
      grep -v -E "\"($varying)\"" "$dir/s.json" > "$dir/s.counters"
      rm "$dir/s.json"
    fi
    # With AFTER_ARGS, only the last frame: slab workers' frames grow slab by slab and may show
    # a few slabs more than one engine's of the same name (docs/scaling.md); the last frame is
    # the picture. Every frame's name is still compared.
    if [ -n "${AFTER_ARGS:-}" ] && [ -d "$dir/f" ]; then
      ls "$dir/f" > "$dir/frame_names"
      ls "$dir/f" | head -n -1 | while read -r frame; do rm "$dir/f/$frame"; done
    fi
  done
}
run_all before "$before"
if [ -n "${AFTER_ARGS:-}" ]; then
  # A wrapper that adds the arguments to `extract` runs; messages still name the binary.
  wrapper=$work/after_with_args
  printf '#!/usr/bin/env bash\nif [ "$1" = extract ]; then exec "%s" "$@" %s; fi\nexec "%s" "$@"\n' \
    "$after" "$AFTER_ARGS" "$after" > "$wrapper"
  chmod +x "$wrapper"
  after=$wrapper
fi
run_all after "$after"

passed=0
failed=0
for name in "${names[@]}"; do
  if diff -r "$work/before/$name" "$work/after/$name" > "$work/diff_$name" 2>&1; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "DIFFERS: $name"
    head -n 20 "$work/diff_$name" | sed 's/^/  /'
  fi
done
files=$(find "$work/before" -type f | wc -l)
echo "compared $files files of ${#names[@]} cases byte for byte"
echo "compare_outputs: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
