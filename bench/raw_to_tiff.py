#!/usr/bin/env python3
"""Writes a raw 8-bit volume as one multi-page TIFF: uncompressed, one strip a page, the way
ImageJ saves a stack. For the benchmarks' TIFF rows; no library needed beyond Python's own.

    bench/raw_to_tiff.py VOLUME.raw WIDTH HEIGHT DEPTH OUT.tif
"""
import struct
import sys


def ifd(width, height, data_offset, next_ifd):
    """One little-endian directory of a grey 8-bit page stored as one strip at data_offset."""
    entries = [  # (tag, type, count, value): types 3 SHORT, 4 LONG
        (256, 4, 1, width),          # ImageWidth
        (257, 4, 1, height),         # ImageLength
        (258, 3, 1, 8),              # BitsPerSample
        (259, 3, 1, 1),              # Compression: none
        (262, 3, 1, 1),              # PhotometricInterpretation: min-is-black
        (273, 4, 1, data_offset),    # StripOffsets
        (277, 3, 1, 1),              # SamplesPerPixel
        (278, 4, 1, height),         # RowsPerStrip
        (279, 4, 1, width * height),  # StripByteCounts
    ]
    out = struct.pack("<H", len(entries))
    for tag, kind, count, value in entries:
        packed = struct.pack("<H", value) + b"\0\0" if kind == 3 else struct.pack("<I", value)
        out += struct.pack("<HHI", tag, kind, count) + packed
    return out + struct.pack("<I", next_ifd)


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__.strip())
    source, width, height, depth, target = sys.argv[1], *map(int, sys.argv[2:5]), sys.argv[5]
    page = width * height
    with open(source, "rb") as f:
        volume = f.read()
    if len(volume) < page * depth:
        sys.exit(f"{source}: {len(volume)} bytes, fewer than {width}x{height}x{depth}")
    ifd_bytes = 2 + 9 * 12 + 4
    with open(target, "wb") as out:
        out.write(b"II*\0" + struct.pack("<I", 8))
        offset = 8
        for z in range(depth):
            data_offset = offset + ifd_bytes
            next_ifd = data_offset + page if z + 1 < depth else 0
            out.write(ifd(width, height, data_offset, next_ifd))
            out.write(volume[z * page:(z + 1) * page])
            offset = data_offset + page


if __name__ == "__main__":
    main()
