"""mvox.Extractor: slices pushed one at a time give the whole-volume surface, piece by piece, in
memory that does not grow with the number of slices, even for a volume larger than the process
may hold."""
import os
import resource
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import mvox
from test_extract import blobs, threshold_of


def stream(volume, threshold, **options):
    depth, height, width = volume.shape
    extractor = mvox.Extractor(width, height, threshold, **options)
    pieces = [extractor.push(volume[z]) for z in range(depth)] + [extractor.finish()]
    return pieces, extractor.counters


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.int16, np.float32])
@pytest.mark.parametrize("options", [{}, {"triangulate": True}, {"method": "cubes"},
                                     {"spacing": (0.5, 2.0, 1.25), "origin": (-3.0, 4.5, 1.0)},
                                     {"interpolate": True}])
def test_pieces_joined_are_the_whole_volume_surface(dtype, options):
    volume = blobs(dtype, shape=(17, 11, 13), seed=5)
    whole = mvox.extract(volume, threshold_of(dtype), **options)
    pieces, counters = stream(volume, threshold_of(dtype), **options)
    vertices = np.concatenate([piece[0] for piece in pieces])
    assert vertices.tobytes() == whole.vertices.tobytes()
    # Offsets count from each piece's first index; indices from the volume's first vertex.
    indices = np.concatenate([piece[2] for piece in pieces])
    sizes = np.concatenate([np.diff(piece[1]) for piece in pieces])
    assert np.array_equal(indices, whole.polygon_indices)
    assert np.array_equal(sizes, np.diff(whole.polygon_offsets))
    assert counters == whole.counters
    # A layer's polygons leave with the slice that completes it: not all at the end.
    assert sum(len(piece[1]) - 1 for piece in pieces[:-1]) > 0


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.int16, np.float32])
@pytest.mark.parametrize("options", [{}, {"triangulate": True},
                                     {"spacing": (0.5, 2.0, 1.25), "origin": (-3.0, 4.5, 1.0)}])
def test_normals_pieces_joined_are_the_whole_volume_normals(dtype, options):
    volume = blobs(dtype, shape=(17, 11, 13), seed=5)
    whole = mvox.extract(volume, threshold_of(dtype), normals=True, **options)
    pieces, counters = stream(volume, threshold_of(dtype), normals=True, **options)
    assert all(len(piece) == 4 for piece in pieces)
    for column, expected in ((0, whole.vertices), (3, whole.normals)):
        joined = np.concatenate([piece[column] for piece in pieces])
        assert joined.shape == expected.shape and joined.tobytes() == expected.tobytes()
    assert np.array_equal(np.concatenate([piece[2] for piece in pieces]), whole.polygon_indices)
    assert counters == whole.counters
    # Each piece has a normal for each of its vertices, and the first slice completes nothing
    # yet: the engine takes a slice once the one after it has arrived.
    assert all(len(piece[3]) == len(piece[0]) for piece in pieces)
    assert len(pieces[0][0]) == 0


def test_normals_need_one_dtype_for_every_slice():
    extractor = mvox.Extractor(13, 11, 100, normals=True)
    extractor.push(np.zeros((11, 13), np.uint8))
    with pytest.raises(TypeError, match="first slice"):
        extractor.push(np.zeros((11, 13), np.uint16))


def test_a_piece_refers_only_to_vertices_already_returned():
    volume = blobs(np.uint8, shape=(12, 11, 13), seed=7)
    pieces, _ = stream(volume, 100)
    returned = 0
    for vertices, offsets, indices in pieces:
        returned += len(vertices)
        assert len(indices) == 0 or indices.max() < returned


def test_slices_of_the_wrong_shape_or_type_are_refused():
    extractor = mvox.Extractor(13, 11, 100)
    with pytest.raises(ValueError, match="shape"):
        extractor.push(np.zeros((11, 12), np.uint8))
    with pytest.raises(TypeError):
        extractor.push(np.zeros((11, 13), np.int32))
    extractor.finish()
    with pytest.raises(ValueError, match="after finish"):
        extractor.push(np.zeros((11, 13), np.uint8))


def test_a_volume_larger_than_the_process_may_hold(tmp_path):
    """A 1 GiB volume on disk (512x512x4096 u8, a ball in its middle slices), streamed from
    numpy.memmap views under an address-space limit of 512 MiB: the process could not even map
    the whole volume, and its peak memory stays far below the volume's size."""
    path = tmp_path / "big.raw"
    width, height, depth = 512, 512, 4096
    with open(path, "wb") as f:
        f.truncate(width * height * depth)  # sparse: zeros cost no disk
        y, x = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
        f.seek(width * height * 2000)
        for z in range(64):
            disc = ((x - 256) ** 2 + (y - 256) ** 2 + (z - 32) ** 2) < 30 ** 2
            f.write((disc.astype(np.uint8) * 200).tobytes())
    script = textwrap.dedent(f"""
        import resource, numpy as np, mvox
        limit = 512 << 20
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        try:
            np.memmap({str(path)!r}, dtype=np.uint8, mode="r", shape=({depth}, {height}, {width}))
            raise SystemExit("the whole volume could be mapped: the limit proves nothing")
        except (OSError, MemoryError, ValueError):
            pass
        extractor = mvox.Extractor({width}, {height}, 100)
        slice_bytes = {width * height}
        vertices = polygons = 0
        for z in range({depth}):
            view = np.memmap({str(path)!r}, dtype=np.uint8, mode="r", offset=z * slice_bytes,
                             shape=({height}, {width}))
            v, offsets, _ = extractor.push(view)
            vertices += len(v); polygons += len(offsets) - 1
            del view
        v, offsets, _ = extractor.finish()
        vertices += len(v); polygons += len(offsets) - 1
        # VmHWM: this process's peak resident memory (ru_maxrss would carry the parent's peak
        # over the fork).
        status = open("/proc/self/status").read()
        peak_mib = int(status.split("VmHWM:")[1].split()[0]) / 1024
        print(vertices, polygons, extractor.counters["slices"], round(peak_mib))
    """)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            env=dict(os.environ))
    assert result.returncode == 0, result.stderr + result.stdout
    vertices, polygons, slices, peak_mib = map(int, result.stdout.split())
    assert slices == depth and vertices > 10000 and polygons > 10000
    # The volume is 1024 MiB; the process (Python, numpy, the module, the engine) stays small.
    assert peak_mib < 200, f"peak {peak_mib} MiB"
    print(f"1 GiB volume streamed under a 512 MiB address-space limit: peak {peak_mib} MiB, "
          f"{vertices} vertices, {polygons} polygons")


def test_two_threads_on_one_extractor_get_an_error_not_a_crash():
    script = textwrap.dedent("""
        import threading, numpy as np, mvox
        ex = mvox.Extractor(512, 512, 100)
        slice_ = np.random.default_rng(2).integers(0, 255, (512, 512), dtype=np.uint8)
        errors = []
        def push():
            for _ in range(100):
                try:
                    ex.push(slice_)
                except RuntimeError as e:
                    errors.append(str(e))
        threads = [threading.Thread(target=push) for _ in range(2)]
        for t in threads: t.start()
        for t in threads: t.join()
        assert all("in use by another thread" in e for e in errors), errors[:3]
        ex.finish()
        print("ok", len(errors))
    """)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("ok")
