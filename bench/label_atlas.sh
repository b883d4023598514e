#!/usr/bin/env bash
# A label atlas of LABELS labels (default 150) through `mvox extract --labels`: a SIZE^3
# (default 256) uint16 NIfTI label map, gzipped, made here: a ball of Voronoi cells around random
# seeds, so that every cell touches several others and each slice holds dozens of labels at
# once. Prints the run's summary, the --stats memory and counts, and /usr/bin/time's wall time and
# peak memory, beside one threshold run over the same file for scale.
#   bench/label_atlas.sh build/src/mvox [LABELS] [SIZE]
set -euo pipefail
mvox=$(realpath "$1")
labels=${2:-150}
size=${3:-256}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
/usr/bin/python3 - "$labels" "$size" <<'PY'
import gzip, struct, sys
import numpy as np
labels, size = int(sys.argv[1]), int(sys.argv[2])
rng = np.random.default_rng(7)
seeds = rng.uniform(0.1 * size, 0.9 * size, (labels, 3))
y, x = np.mgrid[0:size, 0:size]
header = bytearray(352)
struct.pack_into("<i", header, 0, 348)
struct.pack_into("<8h", header, 40, 3, size, size, size, 1, 1, 1, 1)
struct.pack_into("<hh", header, 70, 512, 16)  # uint16
struct.pack_into("<8f", header, 76, 1, 1, 1, 1, 1, 1, 1, 1)
struct.pack_into("<f", header, 108, 352)
header[123] = 2
header[344:348] = b"n+1\0"
with gzip.open("atlas.nii.gz", "wb", compresslevel=1) as out:
    out.write(bytes(header))
    centre = size / 2
    for z in range(size):
        d2 = (x[..., None] - seeds[:, 0]) ** 2 + (y[..., None] - seeds[:, 1]) ** 2 + (z - seeds[:, 2]) ** 2
        cell = np.argmin(d2, axis=2).astype(np.uint16) + 1
        inside = (x - centre) ** 2 + (y - centre) ** 2 + (z - centre) ** 2 < (0.45 * size) ** 2
        out.write(np.where(inside, cell, 0).astype("<u2").tobytes())
PY
mkdir out
echo "## $labels-label atlas, ${size}^3 uint16 NIfTI (.nii.gz)"
echo
/usr/bin/time -f "wall %e s, peak memory %M KiB" "$mvox" extract atlas.nii.gz --labels \
  -o 'out/atlas_{label}.ply' --stats labels.json 2>&1
echo
/usr/bin/python3 - <<'PY'
import json
r = json.load(open("labels.json"))
polygons = sum(l["polygons"] for l in r["labels"])
print(f"labels with a surface: {len(r['labels'])}, polygons: {polygons:,}, "
      f"largest label: {max(l['polygons'] for l in r['labels']):,} polygons")
m = r["memory"]
print(f"engines at once: {m['most_engines_at_once']} x {m['bytes_per_engine']:,} bytes, "
      f"spool index {m['spool_index_bytes']:,} bytes, spool on disk {r['spool_bytes']:,} bytes")
print(f"memory at start {m['start_bytes'] / 2**20:.1f} MiB, peak {m['peak_bytes'] / 2**20:.1f} MiB")
s = r["seconds"]
print(f"read {s['read']:.2f} s, extract {s['extract']:.2f} s, write {s['write']:.2f} s, total {s['total']:.2f} s")
PY
echo
echo "For scale, one threshold over the same file (every label >= 1: the ball's surface):"
/usr/bin/time -f "wall %e s, peak memory %M KiB" "$mvox" extract atlas.nii.gz -t 1 -o one.ply 2>&1 | tail -3
