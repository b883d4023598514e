"""mvox.open and mvox.extract_file: the command line's readers from Python. The slices are the
file's samples, the surface is the one `mvox extract` writes for the same input, bit for bit,
placed by the input's own spacing and origin, and a bad input raises mvox.Error with the very
line the command line prints."""
import numpy as np
import pytest

import mvox
from conftest import read_ply, run_mvox
from test_extract import blobs

import subprocess


def write_nrrd(path, volume, spacing=(0.5, 0.75, 2.0), origin=(10.0, -4.0, 3.5)):
    depth, height, width = volume.shape
    kind = {np.uint8: "uchar", np.uint16: "ushort", np.int16: "short", np.float32: "float"}[
        volume.dtype.type]
    header = (
        f"NRRD0004\ntype: {kind}\ndimension: 3\nsizes: {width} {height} {depth}\n"
        f"encoding: raw\nendian: little\nspace: left-posterior-superior\n"
        f"space directions: ({spacing[0]},0,0) (0,{spacing[1]},0) (0,0,{spacing[2]})\n"
        f"space origin: ({origin[0]},{origin[1]},{origin[2]})\n\n")
    path.write_bytes(header.encode("ascii") + volume.astype(volume.dtype.newbyteorder("<")).tobytes())


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.float32])
def test_a_nrrd_file_gives_its_samples_and_placement(tmp_path, dtype):
    volume = blobs(dtype)
    write_nrrd(tmp_path / "v.nrrd", volume)
    opened = mvox.open(tmp_path / "v.nrrd")
    assert opened.shape == volume.shape and opened.dtype == volume.dtype
    assert opened.spacing == (0.5, 0.75, 2.0) and opened.origin == (10.0, -4.0, 3.5)
    assert np.array_equal(np.stack(list(opened)), volume)


@pytest.mark.parametrize("options", [{}, {"triangulate": True, "normals": True}])
def test_extract_file_is_the_command_lines_mesh(tmp_path, mvox_binary, options):
    volume = blobs(np.uint16)
    write_nrrd(tmp_path / "v.nrrd", volume)
    arguments = ["extract", str(tmp_path / "v.nrrd"), "-t", "20000", "-o", str(tmp_path / "m.ply"),
                 "-q"] + (["--triangulate", "--normals"] if options else [])
    run_mvox(mvox_binary, *arguments)
    vertices, normals, offsets, indices = read_ply(tmp_path / "m.ply")
    mesh = mvox.extract_file(tmp_path / "v.nrrd", 20000, **options)
    assert mesh.vertices.tobytes() == vertices.tobytes()
    assert np.array_equal(mesh.polygon_offsets, offsets)
    assert np.array_equal(mesh.polygon_indices, indices)
    if options:
        assert mesh.normals.tobytes() == normals.tobytes()


def test_a_png_stack_and_a_raw_volume_read_as_the_command_line_reads_them(tmp_path, mvox_binary):
    run_mvox(mvox_binary, "phantom", "torus", "-o", str(tmp_path / "stack"), "--size", "24x20x16",
             "-q")
    run_mvox(mvox_binary, "extract", str(tmp_path / "stack"), "-t", "128", "-o",
             str(tmp_path / "m.ply"), "-q")
    vertices, _, offsets, indices = read_ply(tmp_path / "m.ply")
    mesh = mvox.extract_file(str(tmp_path / "stack"), 128)
    assert mesh.vertices.tobytes() == vertices.tobytes()
    assert np.array_equal(mesh.polygon_indices, indices)
    # The same samples as a raw volume, with raw= as --raw.
    stack = np.stack(list(mvox.open(str(tmp_path / "stack"))))
    assert stack.shape == (16, 20, 24)
    (tmp_path / "v.raw").write_bytes(stack.tobytes())
    raw = mvox.extract_file(tmp_path / "v.raw", 128, raw="24x20x16:u8")
    assert raw.vertices.tobytes() == vertices.tobytes()


@pytest.mark.parametrize("case", ["missing", "cut", "raw-with-header"])
def test_errors_carry_the_command_lines_line(tmp_path, mvox_binary, case):
    volume = blobs(np.uint8)
    write_nrrd(tmp_path / "v.nrrd", volume)
    data = (tmp_path / "v.nrrd").read_bytes()
    (tmp_path / "cut.nrrd").write_bytes(data[:-100])
    path, raw = {"missing": (tmp_path / "nothing.nrrd", None),
                 "cut": (tmp_path / "cut.nrrd", None),
                 "raw-with-header": (tmp_path / "v.nrrd", "13x11x9:u8")}[case]
    arguments = [mvox_binary, "extract", str(path), "-t", "100", "-o", str(tmp_path / "m.ply")]
    if raw:
        arguments += ["--raw", raw]
    cli = subprocess.run(arguments, capture_output=True, text=True)
    line = cli.stderr.splitlines()[0]
    assert cli.returncode in (1, 2) and line.startswith("mvox: error: ")
    with pytest.raises(mvox.Error) as raised:
        mvox.extract_file(path, 100, raw=raw)
    assert "mvox: error: " + str(raised.value) == line


def test_paths_may_come_from_a_generator(tmp_path):
    volume = blobs(np.uint8)
    (tmp_path / "v.raw").write_bytes(volume.tobytes())
    mesh = mvox.extract_file((p for p in [tmp_path / "v.raw"]), 100, raw="13x11x9:u8")
    assert mesh.vertices.tobytes() == mvox.extract(volume, 100).vertices.tobytes()


@pytest.mark.parametrize("options", [{}, {"triangulate": True, "normals": True}])
def test_threads_give_the_same_mesh(tmp_path, options):
    # Noise, so that the surface crosses every slab boundary; 300 slices of 24x20 make 3 slabs.
    volume = np.random.default_rng(5).integers(0, 256, size=(300, 20, 24), dtype=np.uint8)
    (tmp_path / "v.raw").write_bytes(volume.tobytes())
    one = mvox.extract_file(tmp_path / "v.raw", 128, raw="24x20x300:u8", **options)
    assert len(one.polygon_offsets) > 1000
    for threads in (2, 3):
        many = mvox.extract_file(tmp_path / "v.raw", 128, raw="24x20x300:u8", threads=threads,
                                 **options)
        assert many.vertices.tobytes() == one.vertices.tobytes()
        assert np.array_equal(many.polygon_offsets, one.polygon_offsets)
        assert np.array_equal(many.polygon_indices, one.polygon_indices)
        if options:
            assert many.normals.tobytes() == one.normals.tobytes()
            assert np.array_equal(many.faces, one.faces)
    with pytest.raises(ValueError, match="threads"):
        mvox.extract_file(tmp_path / "v.raw", 128, raw="24x20x300:u8", threads=0)


def write_nifti_gz(path, volume, spacing=(0.5, 0.75, 2.0), origin=(10.0, -4.0, 3.5)):
    """A NIfTI-1 .nii.gz placed by its sform: header fields packed at nifti1.h's offsets."""
    import gzip
    import struct
    depth, height, width = volume.shape
    code, bits = {np.uint8: (2, 8), np.int16: (4, 16), np.uint16: (512, 16),
                  np.float32: (16, 32)}[volume.dtype.type]
    header = bytearray(352)
    struct.pack_into("<i", header, 0, 348)
    struct.pack_into("<8h", header, 40, 3, width, height, depth, 1, 1, 1, 1)
    struct.pack_into("<hh", header, 70, code, bits)
    struct.pack_into("<8f", header, 76, 1, *spacing, 1, 1, 1, 1)
    struct.pack_into("<f", header, 108, 352)
    header[123] = 2  # millimetres
    struct.pack_into("<h", header, 254, 1)  # sform_code
    struct.pack_into("<12f", header, 280, spacing[0], 0, 0, origin[0], 0, spacing[1], 0, origin[1],
                     0, 0, spacing[2], origin[2])
    header[344:348] = b"n+1\0"
    with gzip.open(path, "wb") as out:
        out.write(bytes(header) + volume.astype(volume.dtype.newbyteorder("<")).tobytes())


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.float32])
def test_a_nifti_file_gives_its_samples_and_placement(tmp_path, dtype):
    volume = blobs(dtype)
    write_nifti_gz(tmp_path / "v.nii.gz", volume)
    opened = mvox.open(tmp_path / "v.nii.gz")
    assert opened.shape == volume.shape and opened.dtype == volume.dtype
    assert opened.spacing == pytest.approx((0.5, 0.75, 2.0))
    assert opened.origin == pytest.approx((10.0, -4.0, 3.5))
    assert np.array_equal(np.stack(list(opened)), volume)
