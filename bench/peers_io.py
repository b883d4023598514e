"""Reading what mvox reads and writes, for the comparison with VTK and scikit-image
(bench/compare_peers.py): the paper's datasets as numpy arrays, decoded the way mvox decodes
them, and the vertices of the binary PLY files mvox writes.

The dataset table (inputs, raw format, threshold) comes from mvox_bench_extract_once --list, so
there is one copy of it, in bench/paper_datasets.cpp.
"""
import glob
import json
import os
import re
import subprocess

import numpy as np

# mvox's raw sample types (README, `--raw WxH:TYPE`) as numpy dtypes.
RAW_TYPES = {
    "u8": "u1",
    "u16le": "<u2",
    "u16be": ">u2",
    "i16le": "<i2",
    "i16be": ">i2",
    "f32le": "<f4",
}


def list_datasets(extract_once, root):
    """The paper's datasets as dicts: name, present, inputs, raw, threshold."""
    lines = subprocess.run(
        [extract_once, "--list", "--datasets", root],
        check=True,
        capture_output=True,
        text=True,
    ).stdout.splitlines()
    return [json.loads(line) for line in lines]


def natural_key(path):
    """Natural order, as mvox sorts its inputs: slice2 before slice10."""
    return [int(run) if run.isdigit() else run for run in re.split(r"(\d+)", path)]


def input_files(inputs):
    """The files named by `inputs` (files or glob patterns), in natural order."""
    files = []
    for item in inputs:
        matches = glob.glob(item) if glob.has_magic(item) else [item]
        files += [path for path in matches if os.path.isfile(path)]
    if not files:
        raise FileNotFoundError(f"no file matches {' '.join(inputs)}")
    return sorted(files, key=natural_key)


def parse_raw(spec):
    """'256x256:u16be' -> (256, 256, None, dtype); 'WxHxD:TYPE' gives D too."""
    match = re.fullmatch(r"(\d+)x(\d+)(?:x(\d+))?:(\w+)", spec)
    if not match or match.group(4) not in RAW_TYPES:
        raise ValueError(f"bad raw format {spec!r}")
    width, height = int(match.group(1)), int(match.group(2))
    depth = int(match.group(3)) if match.group(3) else None
    return width, height, depth, np.dtype(RAW_TYPES[match.group(4)])


def read_exact(path, dtype, count):
    """`count` samples of `dtype` from `path`, which must hold exactly that many."""
    data = np.fromfile(path, dtype=dtype)
    if data.size != count:
        raise ValueError(f"{path}: {data.size} samples, expected {count}")
    return data


def load_volume(dataset):
    """The dataset as a (slices, rows, columns) array in native byte order."""
    files = input_files(dataset["inputs"])
    if dataset["raw"]:
        width, height, depth, dtype = parse_raw(dataset["raw"])
        if depth is not None:  # one volume file
            if len(files) != 1:
                raise ValueError(f"{dataset['raw']} needs one file, got {len(files)}")
            volume = read_exact(files[0], dtype, width * height * depth)
            volume = volume.reshape(depth, height, width)
        else:  # one file per slice
            slices = [read_exact(path, dtype, width * height) for path in files]
            volume = np.stack(slices).reshape(len(files), height, width)
    else:
        volume = np.stack([read_grayscale_image(path) for path in files])
    return volume.astype(volume.dtype.newbyteorder("="), copy=False)


def read_grayscale_image(path):
    # Pillow comes with python3-skimage; mvox's OpenCV reads the same 8- or 16-bit samples.
    from PIL import Image

    with Image.open(path) as image:
        if image.mode not in ("L", "I;16"):
            raise ValueError(f"{path}: {image.mode} image, expected 8- or 16-bit grayscale")
        return np.array(image)


def read_ply(path):
    """Vertices (N x 3 float32) and face count of a binary little-endian PLY whose vertices are
    exactly `float x, y, z`, as `mvox extract` writes it without --normals. Strict: anything
    else raises ValueError rather than being misread."""
    with open(path, "rb") as ply:
        if ply.readline() != b"ply\n":
            raise ValueError(f"{path}: not a PLY file")
        header = []
        while True:
            line = ply.readline()
            if not line:
                raise ValueError(f"{path}: header has no end_header")
            line = line.decode("ascii").strip()
            if line == "end_header":
                break
            if not line.startswith(("comment", "obj_info")):
                header.append(line)
        vertex_match = re.fullmatch(
            r"format binary_little_endian 1\.0\|element vertex (\d+)\|"
            r"property float x\|property float y\|property float z\|"
            r"element face (\d+)\|property list uchar int vertex_indices",
            "|".join(header),
        )
        if not vertex_match:
            raise ValueError(f"{path}: unexpected PLY header: {header}")
        vertex_count, face_count = int(vertex_match.group(1)), int(vertex_match.group(2))
        vertices = np.fromfile(ply, dtype="<f4", count=3 * vertex_count)
    if vertices.size != 3 * vertex_count:
        raise ValueError(f"{path}: file ends inside the vertex list")
    return vertices.reshape(vertex_count, 3), face_count
