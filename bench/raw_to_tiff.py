#!/usr/bin/env python3
"""Writes a raw 8-bit volume as one multi-page TIFF: uncompressed, one strip a page, the way
ImageJ saves a stack, or with --deflate each page a zlib stream (TIFF's deflate compression).
For the benchmarks' TIFF rows; no library needed beyond Python's own.

    bench/raw_to_tiff.py [--deflate] VOLUME.raw WIDTH HEIGHT DEPTH OUT.tif
"""
import struct
import sys
import zlib


def ifd(width, height, compression, data_offset, data_bytes, next_ifd):
    """One little-endian directory of a grey 8-bit page stored as one strip at data_offset."""
    entries = [  # (tag, type, count, value): types 3 SHORT, 4 LONG
        (256, 4, 1, width),          # ImageWidth
        (257, 4, 1, height),         # ImageLength
        (258, 3, 1, 8),              # BitsPerSample
        (259, 3, 1, compression),    # Compression: 1 none, 8 deflate
        (262, 3, 1, 1),              # PhotometricInterpretation: min-is-black
        (273, 4, 1, data_offset),    # StripOffsets
        (277, 3, 1, 1),              # SamplesPerPixel
        (278, 4, 1, height),         # RowsPerStrip
        (279, 4, 1, data_bytes),     # StripByteCounts
    ]
    out = struct.pack("<H", len(entries))
    for tag, kind, count, value in entries:
        packed = struct.pack("<H", value) + b"\0\0" if kind == 3 else struct.pack("<I", value)
        out += struct.pack("<HHI", tag, kind, count) + packed
    return out + struct.pack("<I", next_ifd)


def main():
    arguments = sys.argv[1:]
    deflate = "--deflate" in arguments
    if deflate:
        arguments.remove("--deflate")
    if len(arguments) != 5:
        sys.exit(__doc__.strip())
    source, width, height, depth, target = arguments[0], *map(int, arguments[1:4]), arguments[4]
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
            data = volume[z * page:(z + 1) * page]
            if deflate:
                data = zlib.compress(data, 6)
            data_offset = offset + ifd_bytes
            next_ifd = data_offset + len(data) + len(data) % 2 if z + 1 < depth else 0
            out.write(ifd(width, height, 8 if deflate else 1, data_offset, len(data), next_ifd))
            out.write(data + b"\0" * (len(data) % 2))
            offset = data_offset + len(data) + len(data) % 2


if __name__ == "__main__":
    main()
