#!/usr/bin/env bash
# An installed mvox finds its modules where `cmake --install` put them (PREFIX/lib/mvox), with
# no MVOX_MODULE_PATH and no build tree to fall back on: it extracts a PGM stack (OpenCV's
# module) and writes a .tif picture, then extracts that picture as a one-page TIFF stack (the
# TIFF module), from a prefix given only at install time.
#   installed_modules_test.sh PREFIX
set -euo pipefail
prefix=$1
mvox=$prefix/bin/mvox
[ -x "$mvox" ] || { echo "no installed mvox at $mvox" >&2; exit 1; }
for module in libmvox_image_codecs.so libmvox_dicom_codecs.so libmvox_tiff_codecs.so; do
  [ -f "$prefix/lib/mvox/$module" ] || { echo "$module is not in $prefix/lib/mvox" >&2; exit 1; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/pgm"
for z in 0 1 2; do
  { printf 'P5\n8 6\n255\n'; head -c 48 /dev/zero | tr '\0' "$([ $z = 1 ] && echo '\310' || echo '\0')"; } \
    > "$work/pgm/s$z.pgm"
done
cd "$work"
env -u MVOX_MODULE_PATH "$mvox" extract pgm -t 100 -o m.ply --image p.tif -q
[ -s m.ply ] && [ -s p.tif ] || { echo "the installed mvox wrote no mesh or picture" >&2; exit 1; }
env -u MVOX_MODULE_PATH "$mvox" extract p.tif -t 100 -o t.ply -q
[ -s t.ply ] || { echo "the installed mvox wrote no mesh from a TIFF" >&2; exit 1; }
echo "installed mvox at $prefix found its modules in $prefix/lib/mvox"
