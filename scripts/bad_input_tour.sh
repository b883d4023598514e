#!/usr/bin/env bash
# A tour of bad input: runs each kind once against build/src/mvox (or $MVOX) in a temporary
# directory and prints a Markdown table: case | command | exit code | the error line | files
# left. Every case asks for a mesh, a picture and a report where a previous version of each
# already exists, so "files left" shows any new file or temporary and any previous output that
# changed; "none" is the only good answer. The same cases, with assertions, are
# tests/bad_input_test.cpp.
#
#   scripts/bad_input_tour.sh            # after: cmake --build build --target mvox
set -uo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
mvox_binary=${MVOX:-$repo/build/src/mvox}
# Absolute, since every case runs in a directory of its own (MVOX=build/src/mvox works too).
case $mvox_binary in /*) ;; *) mvox_binary=$PWD/$mvox_binary ;; esac
if [ ! -x "$mvox_binary" ]; then
  echo "bad_input_tour.sh: $mvox_binary is not built; run: cmake --build build --target mvox" >&2
  exit 1
fi
# Commands are shown, and run, as a user types them.
mvox() { "$mvox_binary" "$@"; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
outputs="-o previous.ply --image previous.png --stats previous.json -q"

# make_tiff.py FILE WxH...: an uncompressed 8-bit TIFF with one page per size (Python's struct
# only, so no TIFF tool is needed).
cat > "$work/make_tiff.py" << 'EOF_PY'
import struct, sys
out = bytearray(b"II*\x00" + struct.pack("<I", 0))
link = 4
for size in sys.argv[2:]:
    w, h = map(int, size.split("x"))
    data = len(out)
    out += bytes((x * 7) % 256 for x in range(w * h))
    out += b"\x00" * (len(out) % 2)
    struct.pack_into("<I", out, link, len(out))
    tags = [(256, 4, w), (257, 4, h), (258, 3, 8), (259, 3, 1), (262, 3, 1), (273, 4, data),
            (277, 3, 1), (278, 4, h), (279, 4, w * h)]
    out += struct.pack("<H", len(tags))
    for tag, kind, value in tags:
        packed = struct.pack("<HH", value, 0) if kind == 3 else struct.pack("<I", value)
        out += struct.pack("<HHI", tag, kind, 1) + packed
    link = len(out)
    out += struct.pack("<I", 0)
open(sys.argv[1], "wb").write(out)
EOF_PY

# make_odd_tiff.py FILE KIND: 12x10 8-bit TIFFs whose headers or data lie. KIND is
# bad-checksum (8 deflate pages, the zlib checksum of page 6 wrong), huge-tiles (one 65536x65536
# tile for the 12x10 image) or huge-page (30000x30000 declared by a 17-byte deflate strip).
cat > "$work/make_odd_tiff.py" << 'EOF_PY'
import struct, sys, zlib
def tiff(pages):
    out = bytearray(b"II*\x00" + struct.pack("<I", 0))
    link = 4
    for w, h, data, tile in pages:
        offset = len(out)
        out += data + b"\x00" * (len(data) % 2)
        struct.pack_into("<I", out, link, len(out))
        tags = [(256, 4, w), (257, 4, h), (258, 3, 8), (259, 3, 8), (262, 3, 1), (277, 3, 1)]
        if tile:
            tags += [(322, 4, tile), (323, 4, tile), (324, 4, offset), (325, 4, len(data))]
        else:
            tags += [(273, 4, offset), (278, 4, h), (279, 4, len(data))]
        tags.sort()
        out += struct.pack("<H", len(tags))
        for tag, kind, value in tags:
            packed = struct.pack("<HH", value, 0) if kind == 3 else struct.pack("<I", value)
            out += struct.pack("<HHI", tag, kind, 1) + packed
        link = len(out)
        out += struct.pack("<I", 0)
    return out
kind = sys.argv[2]
if kind == "bad-checksum":
    pages = [(12, 10, bytearray(zlib.compress(bytes([200 if 1 < z < 6 else 0] * 120))), 0)
             for z in range(8)]
    pages[5][2][-1] ^= 1
elif kind == "huge-tiles":
    pages = [(12, 10, zlib.compress(bytes(200)), 65536)]
else:
    pages = [(30000, 30000, zlib.compress(bytes(1000)), 0)]
open(sys.argv[1], "wb").write(tiff(pages))
EOF_PY

# damage_jpeg.py FILE cut|junk: cuts the JPEG's scan in the middle and closes it with an
# end-of-image marker, or inserts junk restart markers (FF D5 FF D2) into the middle of it.
cat > "$work/damage_jpeg.py" << 'EOF_PY'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
at = 2
while data[at + 1] != 0xDA:
    at += 2 + (data[at + 2] << 8 | data[at + 3])
begin = at + 2 + (data[at + 2] << 8 | data[at + 3])
end = begin
while not (data[end] == 0xFF and data[end + 1] != 0 and not 0xD0 <= data[end + 1] <= 0xD7):
    end += 1
middle = (begin + end) // 2
while data[middle - 1] == 0xFF:
    middle -= 1
if sys.argv[2] == "cut":
    data = data[:middle] + b"\xff\xd9"
else:
    data[middle:middle] = b"\xff\xd5\xff\xd2"
open(sys.argv[1], "wb").write(data)
EOF_PY

# The directory every case starts from: an 8-slice 12x10 stack, and the previous outputs.
template=$work/template
mkdir -p "$template"
(
  cd "$template" || exit 1
  mvox phantom sphere -o stack --size 12x10x8 -q
  for name in previous.ply previous.png previous.json; do
    echo "the previous $name, which must survive" > "$name"
  done
) || exit 1
case_number=0

# new_case: a fresh copy of the template, as the current directory.
new_case() {
  case_number=$((case_number + 1))
  case_dir=$work/case$case_number
  cp -a "$template" "$case_dir"
  cd "$case_dir" || exit 1
}

snapshot() { ls -A | sort; md5sum previous.* 2> /dev/null; }

# What is in the directory that was not, and which previous outputs changed.
files_left() {
  local before=$1 left
  left=$(comm -13 <(echo "$before" | grep -v '  previous\.') <(ls -A | sort) | tr '\n' ' ')
  while read -r sum name; do
    [ "$(md5sum < "$name" | cut -d' ' -f1)" = "$sum" ] || left+="$name CHANGED "
  done < <(echo "$before" | grep '  previous\.')
  echo "${left:-none}"
}

escape() { sed -e 's/|/\\|/g'; }

# row CASE EXIT OUTPUT COMMAND BEFORE: one line of the table.
row() {
  local title=$1 status=$2 output=$3 command=$4 before=$5 line lines
  line=$(head -n 1 <<< "$output")
  lines=$(grep -c '' <<< "$output")
  # A usage error adds a line pointing at --help; anything more breaks the one-line rule.
  if [ "$status" = 2 ] && [ "$lines" -le 2 ]; then :; elif [ "$lines" -gt 1 ]; then
    line+=" (+$((lines - 1)) more lines!)"
  fi
  [ -n "$output" ] || line="(no message)"
  printf '| %s | `%s` | %s | %s | %s |\n' "$(escape <<< "$title")" "$(escape <<< "$command")" "$status" \
    "$(escape <<< "$line")" "$(files_left "$before")"
}

# tour CASE SETUP COMMAND: runs SETUP (unreported), then COMMAND, in a fresh case directory.
tour() {
  local title=$1 setup=$2 command=$3 before output status
  new_case
  eval "$setup" > /dev/null 2>&1
  before=$(snapshot)
  output=$(eval "$command" 2>&1)
  status=$?
  row "$title" "$status" "$output" "$command" "$before"
}

# The interrupt: mvox reads a raw volume from a FIFO that gets three 64 KiB slices, so its
# reading thread is blocked in read() with the outputs' temporaries on disk, then SIGNAL.
interrupt() {
  local signal=$1 before output status pid
  new_case
  mkfifo volume.raw
  before=$(snapshot)
  local arguments="extract volume.raw --raw 256x256x16:u8 -t 128 $outputs"
  # Job control, so that the background job does not start with SIGINT ignored; the binary
  # itself, not the mvox function, so that $! is mvox.
  set -m
  # shellcheck disable=SC2086 # the arguments are words
  "$mvox_binary" $arguments 2> errors.txt &
  pid=$!
  set +m
  exec 3> volume.raw
  head -c $((3 * 65536)) /dev/zero >&3
  for _ in $(seq 100); do ls -A | grep -q '^\.previous\.ply\.' && break; sleep 0.05; done
  kill "-$signal" "$pid"
  wait "$pid" 2> /dev/null
  status=$?
  exec 3>&-
  output=$(cat errors.txt)
  rm errors.txt
  row "SIG$signal mid-run (reader blocked on a FIFO)" "$status" "$output" \
    "mvox $arguments  # kill -$signal after 3 slices" "$before"
}

echo "Bad input tour: $("$mvox_binary" --version) at $mvox_binary"
echo
echo "| case | command | exit | error line | files left |"
echo "|---|---|---|---|---|"
tour "missing slice file" "" \
  "mvox extract stack/sphere_0000.png stack/sphere_0001.png stack/sphere_0009.png -t 128 $outputs"
tour "slice is a dangling symbolic link" \
  "rm stack/sphere_0004.png; ln -s lost.png stack/sphere_0004.png" \
  "mvox extract stack -t 128 $outputs"
tour "slice is a directory" "rm stack/sphere_0004.png; mkdir stack/sphere_0004.png" \
  "mvox extract stack -t 128 $outputs"
tour "truncated image" "truncate -s 40 stack/sphere_0005.png" "mvox extract stack -t 128 $outputs"
tour "corrupt image (garbage named .png)" "head -c 300 /dev/urandom > stack/sphere_0005.png" \
  "mvox extract stack -t 128 $outputs"
tour "corrupt image (one bit flipped)" \
  "printf '\\x55\\xaa' | dd of=stack/sphere_0005.png bs=1 seek=45 conv=notrunc" \
  "mvox extract stack -t 128 $outputs"
tour "slices of different sizes" \
  "mvox phantom sphere -o wide --size 14x10x1 -q; mv wide/sphere_0000.png stack/sphere_0008.png; rmdir wide" \
  "mvox extract stack -t 128 $outputs"
tour "slices of different bit depths" \
  "mvox phantom sphere -o deep --size 12x10x1 --bits 16 -q; mv deep/sphere_0000.png stack/sphere_0008.png; rmdir deep" \
  "mvox extract stack -t 128 $outputs"
tour "empty directory" "mkdir empty" "mvox extract empty -t 128 $outputs"
tour "directory with no images" "mkdir notes; echo hello > notes/readme.txt" \
  "mvox extract notes -t 128 $outputs"
tour "raw volume too short" "head -c 960 /dev/zero > volume.raw" \
  "mvox extract volume.raw --raw 12x10x9:u8 -t 1 $outputs"
tour "raw volume too long" "head -c 960 /dev/zero > volume.raw" \
  "mvox extract volume.raw --raw 12x10x7:u8 -t 1 $outputs"
tour "raw volume from a pipe, too short" "" \
  "head -c 960 /dev/zero | mvox extract /dev/stdin --raw 12x10x9:u8 -t 1 $outputs"
tour "raw slice of the wrong size" \
  "mkdir raw; for k in 0 1 2; do head -c 120 /dev/zero > raw/s.\$k; done; head -c 119 /dev/zero > raw/s.1" \
  "mvox extract raw --raw 12x10:u8 -t 1 $outputs"
tour "unknown --method" "" "mvox extract stack -t 128 --method foo $outputs"
tour "unknown --surface" "" "mvox extract stack -t 128 --surface foo $outputs"
tour "unknown --raw type" "" "mvox extract stack --raw 12x10:u7 -t 128 $outputs"
tour "bad --image-size" "" "mvox extract stack -t 128 --image-size 0x0 $outputs"
tour "threshold above u8" "" "mvox extract stack -t 300 $outputs"
tour "threshold at u8's minimum" "" "mvox extract stack -t 0 $outputs"
tour "no threshold" "" "mvox extract stack $outputs"
tour "output directory missing" "" "mvox extract stack -t 128 -o no/such/dir/mesh.ply"
tour "output under a regular file" "echo text > file.txt" \
  "mvox extract stack -t 128 -o file.txt/mesh.ply"
tour "output in /proc" "" "mvox extract stack -t 128 -o /proc/mesh.ply"
tour "full disk: mesh" "" "mvox extract stack -t 128 -o /dev/full --image previous.png -q"
tour "full disk: picture" "ln -s /dev/full full.png" \
  "mvox extract stack -t 128 -o previous.ply --image full.png -q"
tour "full disk: report" "" "mvox extract stack -t 128 -o previous.ply --stats /dev/full -q"
tour "file-size limit (ulimit -f 4)" "mvox phantom sphere -o big --size 40x40x30 -q" \
  "(ulimit -f 4; mvox extract big -t 128 -o previous.ply -q)"
tour "outputs that collide" "" "mvox extract stack -t 128 -o previous.ply --stats previous.ply"
# Volume files and DICOM.
tour "NRRD: data shorter than its sizes" \
  "{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 9\nencoding: raw\n\n'; head -c 960 /dev/zero; } > cut.nrrd" \
  "mvox extract cut.nrrd -t 1 $outputs"
tour "NRRD: a sample type mvox does not read" \
  "printf 'NRRD0004\ntype: double\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n\n' > double.nrrd; head -c 64 /dev/zero >> double.nrrd" \
  "mvox extract double.nrrd -t 1 $outputs"
tour "NRRD: gzip data that are not gzip" \
  "{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 8\nencoding: gzip\n\n'; head -c 500 /dev/urandom; } > bad.nrrd" \
  "mvox extract bad.nrrd -t 1 $outputs"
tour "MetaImage: data file missing" \
  "printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementDataFile = nowhere.raw\n' > head.mhd" \
  "mvox extract head.mhd -t 1 $outputs"
tour "MetaImage: --raw given as well" \
  "printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' > head.mha" \
  "mvox extract head.mha --raw 12x10x8:u8 -t 1 $outputs"
tour "TIFF stack: a page of another size" "python3 $work/make_tiff.py pages.tif 12x10 12x10 14x10" \
  "mvox extract pages.tif -t 10 $outputs"
tour "TIFF stack: deflate strip failing its checksum" \
  "python3 $work/make_odd_tiff.py stack.tif bad-checksum" "mvox extract stack.tif -t 10 $outputs"
tour "TIFF: 65536x65536 tiles for a 12x10 image (146 bytes)" \
  "python3 $work/make_odd_tiff.py tiles.tif huge-tiles" "mvox extract tiles.tif -t 10 $outputs"
tour "TIFF: a 30000x30000 page in a 140-byte deflate file" \
  "python3 $work/make_odd_tiff.py page.tif huge-page" "mvox extract page.tif -t 10 $outputs"
# JPEG slices: pictures of the sphere that mvox itself writes with OpenCV.
jpegs="mvox extract stack -t 128 -o sphere.ply --image sphere.jpg --image-size 64x48 -q; mkdir jpegs; cp sphere.jpg jpegs/slice_1.jpg; cp sphere.jpg jpegs/slice_2.jpg"
tour "JPEG slice cut mid-scan and closed with FF D9" \
  "$jpegs; python3 $work/damage_jpeg.py jpegs/slice_2.jpg cut" "mvox extract jpegs -t 128 $outputs"
tour "JPEG slice with junk restart markers in its scan" \
  "$jpegs; python3 $work/damage_jpeg.py jpegs/slice_2.jpg junk" "mvox extract jpegs -t 128 $outputs"
dicom=$repo/../shared/datasets/dicom_mr_bbmri_6slices
if [ -d "$dicom" ]; then
  tour "DICOM: a slice file cut short" \
    "mkdir scans; cp $dicom/*.dcm scans/; chmod u+w scans/*; truncate -s 100000 scans/bbmri-53323419.dcm" \
    "mvox extract scans -t 300 $outputs"
  tour "DICOM: two files at one position" \
    "mkdir scans; cp $dicom/*.dcm scans/; cp $dicom/bbmri-53323419.dcm scans/copy.dcm" \
    "mvox extract scans -t 300 $outputs"
  tour "DICOM: a slice missing from the series" \
    "mkdir scans; cp $dicom/*.dcm scans/; rm scans/bbmri-53323419.dcm" \
    "mvox extract scans -t 300 $outputs"
  tour "DICOM: --series that is not there" \
    "mkdir scans; cp $dicom/*.dcm scans/" \
    "mvox extract scans -t 300 --series 1.2.3 $outputs"
else
  echo "| DICOM cases | skipped: $dicom is absent | | | |"
fi
# Mesh formats.
tour "unknown mesh extension" "" "mvox extract stack -t 128 -o mesh.vrml -q"
tour "unknown --format" "" "mvox extract stack -t 128 -o mesh.ply --format vrml -q"
tour "--ascii with STL" "" "mvox extract stack -t 128 -o mesh.stl --ascii -q"
tour "full disk: STL" "" "mvox extract stack -t 128 -o /dev/full --format stl -q"
interrupt INT
interrupt TERM
interrupt HUP
tour "reader closes the pipe (-o - | head -c 10)" \
  "mvox phantom sphere -o big --size 96x96x64 -q" \
  "mvox extract big -t 128 -o - --image previous.png --stats previous.json -q | head -c 10 > /dev/null; exit \${PIPESTATUS[0]}"
echo
echo "Exit codes: 1 the job failed, 2 a usage error (its second line points at --help), 128 + n"
echo "killed by or interrupted with signal n (130 SIGINT, 143 SIGTERM, 129 SIGHUP, 141 SIGPIPE)."
