#!/usr/bin/env bash
# A tour of bad input: runs each kind once against build/src/mvox (or $MVOX) in a temporary
# directory and prints a Markdown table: case | command | exit code | the error line | files
# left | peak memory. Most cases ask for a mesh, a picture and a report where a previous version
# of each already exists, so "files left" shows any new file or temporary, and any file that
# changed, inputs included; "none" is the only good answer (but for the cases meant to succeed,
# whose outputs are listed). Peak memory is the largest resident size of the mvox processes of
# the case (/usr/bin/time). The same cases, with assertions, are tests/cli/bad_input_*_test.cpp,
# tests/cli/output_targets_test.cpp, tests/cli/lying_headers_test.cpp and
# tests/cli/memory_plan_test.cpp.
#
#   scripts/bad_input_tour.sh            # after: cmake --build build --target mvox
set -uo pipefail
# Bytes, not characters: some cases name files with bytes that are not UTF-8.
export LC_ALL=C

repo=$(cd "$(dirname "$0")/.." && pwd)
mvox_binary=${MVOX:-$repo/build/src/mvox}
# Each case runs in a directory of its own: a relative $MVOX is made absolute first.
case $mvox_binary in /*) ;; *) mvox_binary=$PWD/$mvox_binary ;; esac
if [ ! -x "$mvox_binary" ]; then
  echo "bad_input_tour.sh: $mvox_binary is not built; run: cmake --build build --target mvox" >&2
  exit 1
fi
# Commands are shown, and run, as a user types them; each run's peak memory (KiB) is noted.
peak_file=/dev/null
# With standard output closed, time's own file would take descriptor 1 and so become mvox's
# standard output: such runs go untimed.
mvox() {
  if { true 3>&1; } 2> /dev/null; then
    /usr/bin/time -f %M -a -o "$peak_file" "$mvox_binary" "$@"
  else
    "$mvox_binary" "$@"
  fi
}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
outputs="-o previous.ply --image previous.png --stats previous.json -q"

# make_tiff.py FILE KIND [WxH...]: 8-bit TIFFs written with Python's struct only, so no TIFF tool
# is needed. KIND is sizes (one uncompressed page per WxH), bad-checksum (8 deflate 12x10 pages,
# the zlib checksum of page 6 wrong), huge-tiles (one 65536x65536 tile for a 12x10 image) or
# huge-page (30000x30000 declared by a 17-byte deflate strip), or loop (3 uncompressed 12x10
# pages, the last one's link to a next directory leading back to the first).
cat > "$work/make_tiff.py" << 'EOF_PY'
import struct, sys, zlib
def tiff(pages, compression=8):
    out = bytearray(b"II*\x00" + struct.pack("<I", 0))
    link = 4
    for w, h, data, tile in pages:
        offset = len(out)
        out += data + b"\x00" * (len(data) % 2)
        struct.pack_into("<I", out, link, len(out))
        tags = [(256, 4, w), (257, 4, h), (258, 3, 8), (259, 3, compression), (262, 3, 1),
                (277, 3, 1)]
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
if sys.argv[2] == "sizes":
    sizes = [tuple(map(int, size.split("x"))) for size in sys.argv[3:]]
    pages = [(w, h, bytes((x * 7) % 256 for x in range(w * h)), 0) for w, h in sizes]
    open(sys.argv[1], "wb").write(tiff(pages, compression=1))
    sys.exit(0)
if sys.argv[2] == "loop":
    out = tiff([(12, 10, bytes(120), 0)] * 3, compression=1)
    first = struct.unpack_from("<I", out, 4)[0]
    struct.pack_into("<I", out, len(out) - 4, first)  # the last page's link
    open(sys.argv[1], "wb").write(out)
    sys.exit(0)
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

# Every entry under the case directory with a checksum of each file (size and time for files
# over 64 MiB, sparse stand-ins for huge scans; a type letter for the rest).
snapshot() {
  find . -mindepth 1 -print0 | sort -z | while IFS= read -r -d '' entry; do
    local shown=${entry//$'\n'/\\n}  # one line per entry, whatever its name
    if [ -f "$entry" ] && [ ! -L "$entry" ]; then
      if [ "$(stat -c %s "$entry")" -gt $((64 << 20)) ]; then
        echo "$(stat -c %s.%Y "$entry") $shown"
      else
        echo "$(md5sum < "$entry" | cut -d' ' -f1) $shown"
      fi
    else
      echo "$(stat -c %F "$entry" | tr ' ' _) $shown"
    fi
  done
}

# What is in the directory that was not, and what changed or went.
files_left() {
  local before=$1 left="" sum name
  local -A then now
  while read -r sum name; do [ -n "$name" ] && then[$name]=$sum; done <<< "$before"
  while read -r sum name; do [ -n "$name" ] && now[$name]=$sum; done <<< "$(snapshot)"
  for name in "${!now[@]}"; do
    if [ -z "${then[$name]+set}" ]; then
      left+="${name#./} "
    elif [ "${then[$name]}" != "${now[$name]}" ]; then
      left+="${name#./} CHANGED "
    fi
  done
  for name in "${!then[@]}"; do [ -n "${now[$name]+set}" ] || left+="${name#./} GONE "; done
  echo "${left:-none}"
}

# The largest peak of the case's mvox runs, or "-" when none was timed.
peak_memory() {
  local kib
  kib=$(grep -E '^[0-9]+$' "$peak_file" 2> /dev/null | sort -n | tail -n 1)
  if [ -n "$kib" ]; then echo "$((kib / 1024)) MiB"; else echo "-"; fi
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
  printf '| %s | `%s` | %s | %s | %s | %s |\n' "$(escape <<< "$title")" "$(escape <<< "$command")" \
    "$status" "$(escape <<< "$line")" "$(files_left "$before" | escape)" "$(peak_memory)"
}

# tour CASE SETUP COMMAND: runs SETUP (unreported), then COMMAND, in a fresh case directory.
tour() {
  local title=$1 setup=$2 command=$3 before output status
  new_case
  eval "$setup" > /dev/null 2>&1
  peak_file=$work/peak$case_number
  : > "$peak_file"
  before=$(snapshot)
  output=$(eval "$command" 2>&1)
  status=$?
  row "$title" "$status" "$output" "$command" "$before"
  peak_file=/dev/null
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
echo "| case | command | exit | error line | files left | peak memory |"
echo "|---|---|---|---|---|---|"
tour "missing slice file" "" \
  "mvox extract stack/sphere_0000.png stack/sphere_0001.png stack/sphere_0009.png -t 128 $outputs"
# Names holding control characters: printed escaped, so the error stays one line.
tour "input named with a newline" "" \
  "mvox extract \"\$(printf 'no\\nsuch')\" -t 128 $outputs"
tour "--method value with a newline" "" \
  "mvox extract stack -t 128 --method \"\$(printf 'cubes\\nfoo')\" $outputs"
tour "--stats of an input named with \\xff and a newline (the report, parsed)" \
  "mkdir odd; mv stack \"odd/\$(printf 'st\\377ck\\nx')\"" \
  "mvox extract \"odd/\$(printf 'st\\377ck\\nx')\" -t 128 -o /dev/null --stats /dev/stdout -q | python3 -c 'import json, sys; print(\"valid JSON, input:\", ascii(json.loads(sys.stdin.buffer.read().decode())[\"input\"]))'"
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
  "head -c 960 /dev/zero | mvox extract - --raw 12x10x9:u8 -t 1 $outputs"
tour "a pipe without --raw" "" \
  "head -c 960 /dev/zero | mvox extract - -t 1 $outputs"
tour "a FIFO without --raw, with no writer (mvox must not wait for one)" "mkfifo scan.nii" \
  "mvox extract scan.nii -t 1 $outputs"
tour "raw slice of the wrong size" \
  "mkdir raw; for k in 0 1 2; do head -c 120 /dev/zero > raw/s.\$k; done; head -c 119 /dev/zero > raw/s.1" \
  "mvox extract raw --raw 12x10:u8 -t 1 $outputs"
tour "unknown --method" "" "mvox extract stack -t 128 --method foo $outputs"
tour "unknown --surface" "" "mvox extract stack -t 128 --surface foo $outputs"
# Slab threads (a mesh without a picture): workers decode their own slabs in parallel, and the
# first bad slice in the stack is the one named, as with one thread.
tour "bad slices in two slabs, 8 threads" \
  "head -c 300 /dev/urandom > stack/sphere_0002.png; truncate -s 40 stack/sphere_0005.png" \
  "mvox extract stack -t 128 -o previous.ply --stats previous.json -q --threads 8 --slab-slices 4"
tour "--threads 0" "" "mvox extract stack -t 128 --threads 0 $outputs"
# mvox-mpi, when built and mpirun is there: 4 ranks of 2 slices each. The lowest bad slice is
# named, once, by the rank that read it, and no file is left.
mpi_binary=$(dirname "$mvox_binary")/mvox-mpi
if [ -x "$mpi_binary" ] && command -v mpirun > /dev/null; then
  mvox-mpi() {
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
      mpirun --quiet --oversubscribe -np 4 "$mpi_binary" "$@"
  }
  tour "mvox-mpi on 4 ranks: bad slices at ranks 1 and 2" \
    "head -c 300 /dev/urandom > stack/sphere_0002.png; truncate -s 40 stack/sphere_0005.png" \
    "mvox-mpi extract stack -t 128 $outputs"
  tour "mvox-mpi on 4 ranks: a pipe" "" \
    "head -c 960 /dev/zero | mvox-mpi extract /dev/stdin --raw 12x10x8:u8 -t 1 $outputs"
else
  echo "| mvox-mpi cases | skipped: $mpi_binary is not built or mpirun is absent | | | | |"
fi
tour "unknown --raw type" "" "mvox extract stack --raw 12x10:u7 -t 128 $outputs"
tour "bad --image-size" "" "mvox extract stack -t 128 --image-size 0x0 $outputs"
# Numbers that are not what they seem (NaN passes a range check, sscanf and strtoull wrap).
tour "--view NaN" "" "mvox extract stack -t 128 --view nan,0 $outputs"
tour "--fov NaN" "" "mvox extract stack -t 128 --perspective --fov nan $outputs"
tour "--image-size with an exponent" "" "mvox extract stack -t 128 --image-size 1e3 $outputs"
tour "--image-size past 32 bits" "" "mvox extract stack -t 128 --image-size 4294967808 $outputs"
tour "--spacing 0" "" "mvox extract stack -t 128 --spacing 0,1,1 $outputs"
tour "--spacing past float's range" "" "mvox extract stack -t 128 --spacing 1,1,1e300 $outputs"
tour "--every with an exponent" "" "mvox extract stack -t 128 --every 1e3 --frames f $outputs"
tour "phantom --seed -1" "" "mvox phantom sphere -o more --seed -1 -q"
# Coordinates at the ends of float's range: pictures are drawn in the box's own frame (they
# were black), and a mesh whose floats would underflow is refused with the usable range.
# Millions of thin slices: the fixed cost per slice was ~14 us (~75 s for this run); the time
# is now mostly writing its 15 million polygons.
tour "5,000,000 slices of 1x1 (whole run, seconds)" "head -c 5000000 /dev/urandom > line.raw" \
  "mvox extract line.raw --raw 1x1x5000000:u8 -t 128 -o line.ply --stats /dev/stdout -q | python3 -c 'import json, sys; t = json.load(sys.stdin)[\"time_seconds\"]; print(\"seconds: total %.1f, extract %.1f, write %.1f\" % (t[\"total\"], t[\"extract\"], t[\"write\"]))'"
tour "--spacing 1e-37 (the picture, drawn)" "" \
  "mvox extract stack -t 128 --spacing 1e-37,1e-37,1e-37 --image tiny.png --stats /dev/stdout -q | python3 -c 'import json, sys; print(\"triangles drawn:\", json.load(sys.stdin)[\"render\"][\"triangles_drawn\"])'"
tour "--spacing 1e-46 (the mesh's floats would be 0)" "" \
  "mvox extract stack -t 128 --spacing 1e-46,1e-46,1e-46 $outputs"
cube_ply="ply\\nformat ascii 1.0\\nelement vertex 8\\nproperty float x\\nproperty float y\\nproperty float z\\nelement face 6\\nproperty list uchar int vertex_indices\\nend_header\\n"
cube_faces="4 0 2 3 1\\n4 4 5 7 6\\n4 0 1 5 4\\n4 2 6 7 3\\n4 0 4 6 2\\n4 1 3 7 5\\n"
for ends in "-3e38 3e38" "0 1.1e-44"; do
  set -- $ends
  tour "render a cube from $1 to $2" \
    "{ printf '$cube_ply'; for c in 0 1 2 3 4 5 6 7; do echo \$(( c & 1 ? 1 : 0 )) \$(( c & 2 ? 1 : 0 )) \$(( c & 4 ? 1 : 0 )) | sed 's/0/$1/g; s/1/$2/g'; done; printf '$cube_faces'; } > cube.ply" \
    "mvox render cube.ply -o cube.png --view 30,20"
done
tour "render an endless device (not read whole)" "" "mvox render /dev/zero -o cube.png"
tour "render a PLY that holds more than its header says" \
  "{ printf '$cube_ply' | sed 's/ascii/binary_little_endian/'; head -c 100000000 /dev/zero; } > big.ply" \
  "mvox render big.ply -o cube.png"
tour "threshold above u8" "" "mvox extract stack -t 300 $outputs"
tour "threshold at u8's minimum" "" "mvox extract stack -t 0 $outputs"
tour "no threshold" "" "mvox extract stack $outputs"
tour "output directory missing" "" "mvox extract stack -t 128 -o no/such/dir/mesh.ply"
tour "output under a regular file" "echo text > file.txt" \
  "mvox extract stack -t 128 -o file.txt/mesh.ply"
tour "output in /proc" "" "mvox extract stack -t 128 -o /proc/mesh.ply"
# A display that accepts connections and never answers (a socket nobody reads): --show warns
# after 3 s and the run goes on, writing its picture.
tour "--show with a display that never answers" "" \
  "python3 -c 'import socket, time; s = socket.socket(socket.AF_UNIX); s.bind(\"\\0/tmp/.X11-unix/X59321\"); s.listen(8); time.sleep(6)' > /dev/null 2>&1 & sleep 0.5; DISPLAY=:59321 mvox extract stack -t 128 --image shown.png --show -q"
tour "full disk: mesh" "" "mvox extract stack -t 128 -o /dev/full --image previous.png -q"
tour "full disk: picture" "ln -s /dev/full full.png" \
  "mvox extract stack -t 128 -o previous.ply --image full.png -q"
tour "full disk: report" "" "mvox extract stack -t 128 -o previous.ply --stats /dev/full -q"
tour "file-size limit (ulimit -f 4)" "mvox phantom sphere -o big --size 40x40x30 -q" \
  "(ulimit -f 4; mvox extract big -t 128 -o previous.ply -q)"
tour "outputs that collide" "" "mvox extract stack -t 128 -o previous.ply --stats previous.ply"
# Outputs that would destroy an input, or each other: compared by identity, before anything runs.
raw_volume="head -c 24000 /dev/urandom > vol.raw"
tour "the mesh onto the raw scan it reads" "$raw_volume" \
  "mvox extract vol.raw --raw 40x30x20:u8 -t 100 --format ply -o vol.raw"
tour "the mesh onto a slice of the input stack" "" \
  "mvox extract stack -t 128 --format ply -o stack/sphere_0000.png"
tour "the mesh through a symbolic link to the input" "$raw_volume; ln -s vol.raw link.ply" \
  "mvox extract vol.raw --raw 40x30x20:u8 -t 100 -o link.ply"
tour "the report through a hard link to the input" "$raw_volume; ln vol.raw hard.json" \
  "mvox extract vol.raw --raw 40x30x20:u8 -t 100 -o mesh.ply --stats hard.json"
tour "a NRRD's detached data file as the picture" \
  "$raw_volume; printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 40 30 20\nencoding: raw\ndata file: vol.raw\n' > vol.nhdr" \
  "mvox extract vol.nhdr -t 100 --image vol.raw"
tour "frames onto input slices named like frames" \
  "mkdir scans; for z in 0 1 2 3 4 5 6 7; do cp stack/sphere_000\$z.png scans/frame_000\$z.png; done" \
  "mvox extract scans -t 128 --frames scans --every 2 $outputs"
tour "mesh and report as one file by two spellings" "" "mvox extract stack -t 128 -o x.ply --stats ./x.ply"
tour "mesh and report both on standard output (out.txt: the shell's)" "" \
  "mvox extract stack -t 128 -o - --stats - > out.txt"
tour "picture into a frame's place" "" "mvox extract stack -t 128 --frames f --every 4 --image f/frame_0008.png"
tour "/dev/stdout redirected to a file (written through)" "" \
  "mvox extract stack -t 128 -o /dev/stdout -q > mesh.ply; ls -l /dev/stdout | cut -c1"
tour "standard output closed (-o - >&-)" "" "mvox extract stack -t 128 -o - -q >&-"
tour "an immutable report: the mesh must not be replaced either" "chattr +i previous.json" \
  "mvox extract stack -t 128 $outputs; status=\$?; chattr -i previous.json; exit \$status"
tour "another user's report in a sticky directory" \
  "chmod 777 .; mkdir -m 1777 shared; echo theirs > shared/r.json; chown 65534 shared/r.json; echo mine > shared/m.ply; chown 65533 shared/m.ply" \
  "setpriv --reuid=65533 --regid=65533 --clear-groups $mvox_binary extract stack -t 128 -o shared/m.ply --stats shared/r.json -q"
tour "the mesh beside the input, another name (fine)" "" "mvox extract stack -t 128 -o stack/mesh.ply -q"
tour "an output name of 255 bytes (fine)" "" \
  "mvox extract stack -t 128 -q -o \$(printf 'm%.0s' \$(seq 251)).ply"
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
# NIfTI-1 files written field by field: nifti FILE DIMS DATATYPE BITPIX SAMPLE_BYTES [MAGIC].
nifti() {
  python3 - "$@" <<'PY'
import struct, sys
path, dims, datatype, bitpix, data = sys.argv[1], [int(d) for d in sys.argv[2].split(",")], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
magic = (sys.argv[6] if len(sys.argv) > 6 else "n+1").encode() + b"\0"
h = bytearray(352)
struct.pack_into("<i", h, 0, 348)
struct.pack_into("<8h", h, 40, len(dims), *(dims + [1] * (7 - len(dims))))
struct.pack_into("<hh", h, 70, datatype, bitpix)
struct.pack_into("<8f", h, 76, 1, 1, 1, 1, 1, 1, 1, 1)
struct.pack_into("<f", h, 108, 352)
h[344:348] = magic[:4]
open(path, "wb").write(bytes(h) + bytes(data))
PY
}
tour "NIfTI: a 4-D image (time series)" \
  "nifti four.nii 12,10,8,5 2 8 4800" \
  "mvox extract four.nii -t 1 $outputs"
tour "NIfTI: data shorter than its dims" \
  "nifti cut.nii 12,10,8 4 16 1000" \
  "mvox extract cut.nii -t 1 $outputs"
tour "NIfTI: an RGB image" \
  "nifti rgb.nii 12,10,8 128 24 2880" \
  "mvox extract rgb.nii -t 1 $outputs"
tour "NIfTI: an Analyze 7.5 header (no NIfTI magic)" \
  "nifti old.hdr 12,10,8 2 8 0 xyz" \
  "mvox extract old.hdr -t 1 $outputs"
tour "NIfTI: .nii.gz that is not gzip" \
  "nifti plain.nii.gz 12,10,8 2 8 960" \
  "mvox extract plain.nii.gz -t 1 $outputs"
tour "MetaImage: data file missing" \
  "printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementDataFile = nowhere.raw\n' > head.mhd" \
  "mvox extract head.mhd -t 1 $outputs"
# A detached data file that is a FIFO: refused before open(), which would wait for a writer.
tour "NRRD: data file is a FIFO" \
  "mkfifo samples.raw; printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 8\nencoding: raw\ndata file: samples.raw\n' > head.nhdr" \
  "mvox extract head.nhdr -t 1 $outputs"
tour "MetaImage: data file is a FIFO" \
  "mkfifo samples.raw; printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementDataFile = samples.raw\n' > head.mhd" \
  "mvox extract head.mhd -t 1 $outputs"
tour "MetaImage: --raw given as well" \
  "printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' > head.mha" \
  "mvox extract head.mha --raw 12x10x8:u8 -t 1 $outputs"
# Geometry that float coordinates cannot hold, or that places no volume: named with the file.
tour "NRRD: spacing 1e300" \
  "printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 8\nencoding: raw\nspacings: 1e300 1 1\n\n' > far.nrrd; head -c 960 /dev/zero >> far.nrrd" \
  "mvox extract far.nrrd -t 1 $outputs"
tour "NRRD: parallel space directions" \
  "printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 8\nencoding: raw\nspace: LPS\nspace directions: (1,0,0) (0,1,0) (0,2,0)\n\n' > flat.nrrd; head -c 960 /dev/zero >> flat.nrrd" \
  "mvox extract flat.nrrd -t 1 $outputs"
tour "MetaImage: singular TransformMatrix" \
  "printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nTransformMatrix = 1 0 0 0 1 0 1 1 0\nElementDataFile = LOCAL\n' > flat.mha; head -c 960 /dev/zero >> flat.mha" \
  "mvox extract flat.mha -t 1 $outputs"
tour "MetaImage: ElementSpacing 1e300" \
  "printf 'NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\nElementSpacing = 1 1 1e300\nElementDataFile = LOCAL\n' > far.mha; head -c 960 /dev/zero >> far.mha" \
  "mvox extract far.mha -t 1 $outputs"
# Headers that lie, and runs larger than the memory they may take: refused from the header.
tour "gzip NRRD: 23 bytes declaring a 65536x65536 slice" \
  "{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 65536 65536 1\nencoding: gzip\n\n'; head -c 10 /dev/zero | gzip -c; } > big.nrrd" \
  "mvox extract big.nrrd -t 1 $outputs"
tour "gzip NRRD: 30000x30000x3 u16 in 150 bytes, with a picture" \
  "{ printf 'NRRD0004\ntype: uint16\ndimension: 3\nsizes: 30000 30000 3\nendian: little\nencoding: gzip\n\n'; head -c 1000 /dev/zero | gzip -c; } > big.nrrd" \
  "mvox extract big.nrrd -t 1 $outputs"
tour "zlib MetaImage declaring 30000x30000x3" \
  "{ printf 'NDims = 3\nDimSize = 30000 30000 3\nElementType = MET_USHORT\nCompressedData = True\nElementDataFile = LOCAL\n'; head -c 1000 /dev/zero | python3 -c 'import sys, zlib; sys.stdout.buffer.write(zlib.compress(sys.stdin.buffer.read()))'; } > big.mha" \
  "mvox extract big.mha -t 1 $outputs"
tour "raw slices of 65536x65536 (a 4 GiB sparse file)" "truncate -s 4G huge.raw" \
  "mvox extract huge.raw --raw 65536x65536x1:u8 -t 1 $outputs"
tour "NRRD header of 65536x65536 raw slices" \
  "truncate -s 4G huge.raw; printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 65536 65536 1\nencoding: raw\ndata file: huge.raw\n' > huge.nhdr" \
  "mvox extract huge.nhdr -t 1 $outputs"
# write_png W H ROWS: a grey PNG declaring WxH whose data hold ROWS rows of zeros.
write_png() {
  python3 -c "import struct, sys, zlib
w, h, rows = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d))
c = zlib.compressobj(9)
idat = b''.join(c.compress(bytes(w + 1)) for _ in range(rows)) + c.flush()
sys.stdout.buffer.write(b'\\x89PNG\\r\\n\\x1a\\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 0, 0, 0, 0))
                        + chunk(b'IDAT', idat) + chunk(b'IEND', b''))" "$@"
}
# gzip_with_trailer N SIZE: a gzip member of N zero bytes whose trailer claims SIZE bytes.
gzip_with_trailer() {
  python3 -c "import gzip, struct, sys
d = gzip.compress(bytes(int(sys.argv[1])))
sys.stdout.buffer.write(d[:-4] + struct.pack('<I', int(sys.argv[2])))" "$@"
}
tour "PNG header of 65535x65535" \
  "mkdir big; write_png 65535 65535 1 > big/s0.png" "mvox extract big -t 1 $outputs"
tour "PNG of 20000x20000 holding one row of data" \
  "mkdir big; write_png 20000 20000 1 > big/s0.png" "mvox extract big -t 1 $outputs"
tour "a valid 30000x30000 PNG, over --max-memory 1G" \
  "mkdir big; write_png 30000 30000 30000 > big/s0.png" \
  "mvox extract big -t 1 --max-memory 1G $outputs"
tour "the same PNG, --dry-run (the plan's total line)" \
  "mkdir big; write_png 30000 30000 30000 > big/s0.png" \
  "mvox extract big -t 1 --dry-run $outputs | grep total"
tour "gzip NRRD: data short, trailer claims the full size" \
  "{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 10\nencoding: gzip\n\n'; gzip_with_trailer 1100 1200; } > t.nrrd" \
  "mvox extract t.nrrd -t 1 $outputs"
tour "gzip NRRD: data short, trailer claims less" \
  "{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 10\nencoding: gzip\n\n'; gzip_with_trailer 1100 100; } > t.nrrd" \
  "mvox extract t.nrrd -t 1 $outputs"
tour "gzip NRRD: data complete, trailer claims less" \
  "{ printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 10\nencoding: gzip\n\n'; gzip_with_trailer 1200 0; } > t.nrrd" \
  "mvox extract t.nrrd -t 1 $outputs"
tour "out of memory mid-run (ulimit -v, --max-memory none)" "truncate -s 384000000 large.raw" \
  "(ulimit -v 300000; mvox extract large.raw --raw 8000x8000x3:u16le -t 1 --max-memory none $outputs)"
tour "TIFF stack: a page of another size" "python3 $work/make_tiff.py pages.tif sizes 12x10 12x10 14x10" \
  "mvox extract pages.tif -t 10 $outputs"
tour "TIFF stack: deflate strip failing its checksum" \
  "python3 $work/make_tiff.py stack.tif bad-checksum" "mvox extract stack.tif -t 10 $outputs"
tour "TIFF: 65536x65536 tiles for a 12x10 image (146 bytes)" \
  "python3 $work/make_tiff.py tiles.tif huge-tiles" "mvox extract tiles.tif -t 10 $outputs"
tour "TIFF: a 30000x30000 page in a 140-byte deflate file" \
  "python3 $work/make_tiff.py page.tif huge-page" "mvox extract page.tif -t 10 $outputs"
tour "TIFF: directories that loop back to the first page" \
  "python3 $work/make_tiff.py loop.tif loop" "mvox extract loop.tif -t 10 $outputs"
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
  # An entry of the series' folder that is not a file: named, not taken for "no slice images".
  tour "DICOM: a FIFO beside the series" \
    "mkdir scans; cp $dicom/*.dcm scans/; mkfifo scans/pipe" \
    "mvox extract scans -t 300 $outputs"
  tour "DICOM: a dangling link beside the series" \
    "mkdir scans; cp $dicom/*.dcm scans/; ln -s gone.dcm scans/extra.dcm" \
    "mvox extract scans -t 300 $outputs"
  tour "DICOM: --series that is not there" \
    "mkdir scans; cp $dicom/*.dcm scans/" \
    "mvox extract scans -t 300 --series 1.2.3 $outputs"
else
  echo "| DICOM cases | skipped: $dicom is absent | | | | |"
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
