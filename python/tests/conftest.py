"""Where the tests find the module and the mvox command line they compare it with."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import mvox  # noqa: F401  (PYTHONPATH points at the build's python/ folder; see CMakeLists.txt)


@pytest.fixture(scope="session")
def mvox_binary():
    path = os.environ.get("MVOX_BINARY")
    if not path or not os.access(path, os.X_OK):
        pytest.fail("MVOX_BINARY must name the built mvox executable (ctest sets it)")
    return path


def read_ply(path):
    """A binary little-endian PLY as mvox writes it: (vertices (N, 3) float32, normals or None,
    offsets, indices) read with numpy alone, independently of the module under test."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    vertex_count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    face_count = next(int(line.split()[2]) for line in header if line.startswith("element face"))
    fields = 6 if any(line == "property float nx" for line in header) else 3
    vertex_bytes = vertex_count * fields * 4
    records = np.frombuffer(data, dtype="<f4", count=vertex_count * fields, offset=end)
    records = records.reshape(vertex_count, fields)
    faces = data[end + vertex_bytes:]
    offsets = [0]
    indices = []
    at = 0
    for _ in range(face_count):
        count = faces[at]
        indices.extend(np.frombuffer(faces, dtype="<i4", count=count, offset=at + 1))
        offsets.append(offsets[-1] + count)
        at += 1 + 4 * count
    assert at == len(faces), "bytes left after the faces"
    normals = records[:, 3:6] if fields == 6 else None
    return records[:, :3], normals, np.array(offsets, np.int64), np.array(indices, np.int32)


def run_mvox(binary, *arguments):
    result = subprocess.run([binary, *arguments], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return result
