"""mvox.write: a Mesh through the command line's own writers gives the files `mvox extract`
writes (header comments aside), normals included; and the arrays convert to the conventions of
other mesh libraries with numpy alone: PyVista's padded face list, trimesh's (M, 3) faces, VTK's
offsets and connectivity."""
import numpy as np
import pytest

import mvox
from conftest import read_ply, run_mvox
from test_extract import blobs


@pytest.fixture
def volume_and_cli(tmp_path, mvox_binary):
    volume = blobs(np.uint8, shape=(10, 12, 14), seed=11)
    (tmp_path / "v.raw").write_bytes(volume.tobytes())

    def cli(name, *extra):
        run_mvox(mvox_binary, "extract", str(tmp_path / "v.raw"), "--raw", "14x12x10:u8", "-t",
                 "100", "-o", str(tmp_path / name), "-q", *extra)
        return tmp_path / name
    return volume, cli


def test_ply_polygons_and_triangles(tmp_path, volume_and_cli):
    volume, cli = volume_and_cli
    for triangulate in (False, True):
        mesh = mvox.extract(volume, 100, triangulate=triangulate)
        mvox.write(mesh, str(tmp_path / "py.ply"))
        theirs = read_ply(cli("cli.ply", *(["--triangulate"] if triangulate else [])))
        ours = read_ply(tmp_path / "py.ply")
        assert ours[0].tobytes() == theirs[0].tobytes()
        assert np.array_equal(ours[2], theirs[2]) and np.array_equal(ours[3], theirs[3])


def test_stl_records_are_the_command_lines(tmp_path, volume_and_cli):
    volume, cli = volume_and_cli
    mvox.write(mvox.extract(volume, 100, triangulate=True), str(tmp_path / "py.stl"))
    ours = (tmp_path / "py.stl").read_bytes()
    theirs = cli("cli.stl").read_bytes()
    assert ours[80:] == theirs[80:]  # the 80-byte header holds a comment; count and triangles
    with pytest.raises(ValueError, match="triangles only"):
        mvox.write(mvox.extract(volume, 100), str(tmp_path / "polygons.stl"))


def test_obj_lines_are_the_command_lines(tmp_path, volume_and_cli):
    volume, cli = volume_and_cli
    mvox.write(mvox.extract(volume, 100), str(tmp_path / "py.obj"))

    # The command line interleaves v and f lines as the engine's layers complete; a mesh in
    # memory has all its vertices first. Each kind of line comes in the same order.
    def lines(path, kind):
        return [line for line in path.read_text().splitlines() if line.startswith(kind + " ")]
    theirs = cli("cli.obj")
    for kind in ("v", "f"):
        assert lines(tmp_path / "py.obj", kind) == lines(theirs, kind)


def test_unknown_formats_and_broken_faces_are_refused(tmp_path):
    mesh = mvox.extract(blobs(np.uint8), 100)
    with pytest.raises(ValueError, match="format"):
        mvox.write(mesh, str(tmp_path / "mesh.vrml"))
    assert not list(tmp_path.iterdir()), "nothing is written for a refused mesh"


def test_the_arrays_in_other_libraries_conventions():
    mesh = mvox.extract(blobs(np.uint8), 100)
    offsets, indices = mesh.polygon_offsets, mesh.polygon_indices
    sizes = np.diff(offsets)
    # PyVista / VTK legacy: each face as its size followed by its indices.
    padded = np.insert(indices.astype(np.int64), offsets[:-1], sizes)
    assert len(padded) == len(indices) + len(sizes)
    at = 0
    for i, size in enumerate(sizes):
        assert padded[at] == size
        assert np.array_equal(padded[at + 1:at + 1 + size], indices[offsets[i]:offsets[i + 1]])
        at += 1 + size
    # trimesh: triangles as (M, 3) rows; the triangulated mesh gives them directly, and covers
    # the same surface: the same vertices and twice the triangles per polygon less two each.
    triangles = mvox.extract(blobs(np.uint8), 100, triangulate=True)
    assert triangles.faces.shape[1] == 3
    assert len(triangles.faces) == int((sizes - 2).sum())
    assert triangles.vertices.tobytes() == mesh.vertices.tobytes()


def test_meshes_it_cannot_write_are_refused_before_any_byte(tmp_path):
    mesh = mvox.extract(blobs(np.uint8), 100)
    mesh.polygon_offsets[1:] += 1 << 40  # the caller's arrays are writable
    with pytest.raises(ValueError, match="polygon_offsets"):
        mvox.write(mesh, str(tmp_path / "broken.ply"))
    assert not list(tmp_path.iterdir())


def test_normals_are_written_where_the_format_has_room(tmp_path, volume_and_cli):
    volume, cli = volume_and_cli
    mesh = mvox.extract(volume, 100, normals=True)
    mvox.write(mesh, str(tmp_path / "py.ply"))
    ours, theirs = read_ply(tmp_path / "py.ply"), read_ply(cli("cli.ply", "--normals"))
    assert ours[1] is not None
    for mine, cli_array in zip(ours, theirs):
        assert mine.tobytes() == cli_array.tobytes()

    # OBJ: the v, vn and f lines the command line writes, each kind in the same order.
    mvox.write(mesh, str(tmp_path / "py.obj"))
    theirs_obj = cli("cli.obj", "--normals")

    def lines(path, kind):
        return [line for line in path.read_text().splitlines() if line.startswith(kind + " ")]
    for kind in ("v", "vn", "f"):
        assert lines(tmp_path / "py.obj", kind) == lines(theirs_obj, kind), kind
        assert lines(theirs_obj, kind)

    # STL has face normals only: the mesh's vertex normals change nothing there.
    triangles = mvox.extract(volume, 100, triangulate=True, normals=True)
    mvox.write(triangles, str(tmp_path / "py.stl"))
    assert (tmp_path / "py.stl").read_bytes()[80:] == cli("cli.stl").read_bytes()[80:]


def test_meshio_reads_the_files_as_the_arrays_are(tmp_path):
    """meshio (Debian's python3-meshio), a reader of many mesh formats, finds in mvox.write's
    files the mesh the arrays hold: PLY and OBJ face by face (meshio cuts the faces into runs of
    one size, in order), STL triangle by triangle."""
    meshio = pytest.importorskip("meshio", reason="python3-meshio (scripts/install_deps.sh)")
    mesh = mvox.extract(blobs(np.uint8, shape=(10, 12, 14), seed=3), 100)
    sizes = np.diff(mesh.polygon_offsets)
    assert set(sizes) >= {3, 4}, "the case needs faces of more than one size"
    for name in ("m.ply", "m.obj"):
        mvox.write(mesh, str(tmp_path / name))
        read = meshio.read(tmp_path / name)
        assert read.points.astype(np.float32).tobytes() == mesh.vertices.tobytes(), name
        assert np.array_equal(np.concatenate([[len(row)] * len(block.data) for block in read.cells
                                              for row in block.data[:1]]), sizes), name
        assert np.array_equal(np.concatenate([block.data.ravel() for block in read.cells]),
                              mesh.polygon_indices), name

    triangles = mvox.extract(blobs(np.uint8, shape=(10, 12, 14), seed=3), 100, triangulate=True)
    mvox.write(triangles, str(tmp_path / "m.stl"))
    read = meshio.read(tmp_path / "m.stl")
    ours = triangles.vertices[triangles.faces]  # (M, 3 corners, 3)
    theirs = read.points[np.concatenate([block.data for block in read.cells])]
    assert np.array_equal(theirs.astype(np.float32), ours)
