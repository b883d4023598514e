"""mvox.extract on numpy arrays: the surface `mvox extract` writes for the same samples, bit for
bit, for every sample type and option; the arrays' layout; refusals of arrays it cannot read."""
import numpy as np
import pytest

import mvox
from conftest import read_ply, run_mvox

RAW_TYPES = {np.uint8: "u8", np.uint16: "u16le", np.int16: "i16le", np.float32: "f32le"}


def blobs(dtype, shape=(9, 11, 13), seed=1):
    """A volume of random blobs: odd, different sizes on every axis, so that a swapped axis or
    a flip shows; values spread over the type's range."""
    rng = np.random.default_rng(seed)
    z, y, x = np.meshgrid(*[np.arange(n) for n in shape], indexing="ij")
    density = np.zeros(shape)
    for _ in range(4):
        c = rng.uniform(0, 1, 3) * np.array(shape)
        r = rng.uniform(2, 4)
        density += np.exp(-((z - c[0]) ** 2 + (y - c[1]) ** 2 + (x - c[2]) ** 2) / r**2)
    if dtype == np.float32:
        return (density * 100 - 20).astype(np.float32)
    scale = {np.uint8: 200, np.uint16: 50000, np.int16: 30000}[dtype]
    offset = -10000 if dtype == np.int16 else 0
    return (density * scale + offset).clip(np.iinfo(dtype).min, np.iinfo(dtype).max).astype(dtype)


def threshold_of(dtype):
    return {np.uint8: 100, np.uint16: 20000, np.int16: 3000, np.float32: 30.5}[dtype]


@pytest.mark.parametrize("dtype", list(RAW_TYPES))
@pytest.mark.parametrize("options", [
    {},
    {"triangulate": True},
    {"normals": True},
    {"method": "cubes"},
    {"spacing": (0.5, 2.0, 1.25), "origin": (-3.0, 4.5, 100.0)},
    {"interpolate": True, "normals": True},
])
def test_the_same_surface_as_the_command_line(tmp_path, mvox_binary, dtype, options):
    volume = blobs(dtype)
    (tmp_path / "v.raw").write_bytes(volume.tobytes())
    depth, height, width = volume.shape
    arguments = [
        "extract", str(tmp_path / "v.raw"), "--raw", f"{width}x{height}x{depth}:{RAW_TYPES[dtype]}",
        "-t", repr(threshold_of(dtype)), "-o", str(tmp_path / "m.ply"), "-q",
    ]
    if options.get("triangulate"):
        arguments.append("--triangulate")
    if options.get("normals"):
        arguments.append("--normals")
    if "method" in options:
        arguments += ["--method", options["method"]]
    if options.get("interpolate"):
        arguments.append("--interpolate")
    if "spacing" in options:
        arguments += ["--spacing", ",".join(map(repr, options["spacing"])),
                      "--origin", ",".join(map(repr, options["origin"]))]
    run_mvox(mvox_binary, *arguments)
    vertices, normals, offsets, indices = read_ply(tmp_path / "m.ply")

    mesh = mvox.extract(volume, threshold_of(dtype), **options)
    assert mesh.vertices.dtype == np.float32 and mesh.vertices.shape == vertices.shape
    assert mesh.vertices.tobytes() == vertices.tobytes(), "vertices differ from the CLI's"
    assert np.array_equal(mesh.polygon_offsets, offsets)
    assert np.array_equal(mesh.polygon_indices, indices)
    if options.get("normals"):
        assert mesh.normals.tobytes() == normals.tobytes()
    else:
        assert mesh.normals is None
    if options.get("triangulate"):
        assert mesh.faces.shape == (len(offsets) - 1, 3)
        assert np.array_equal(mesh.faces.ravel(), indices)
    assert mesh.counters["vertices"] == len(vertices) > 0


def test_arrays_follow_vtk_cell_array_layout():
    mesh = mvox.extract(blobs(np.uint8), 100)
    offsets, indices = mesh.polygon_offsets, mesh.polygon_indices
    assert offsets.dtype == np.int64 and indices.dtype == np.int32
    assert offsets[0] == 0 and offsets[-1] == len(indices)
    sizes = np.diff(offsets)
    assert sizes.min() >= 3 and sizes.max() <= 7
    assert len(sizes) == mesh.counters["polygons"]
    by_size = {size: int((sizes == size).sum()) for size in range(3, 8)}
    assert by_size == mesh.counters["polygons_by_size"]
    assert indices.max() < len(mesh.vertices)
    # Closed: every edge is used by exactly two faces, once in each direction.
    edges = {}
    for face in np.split(indices, offsets[1:-1]):
        for a, b in zip(face, np.roll(face, -1)):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    assert all(count == 1 and edges.get((b, a)) == 1 for (a, b), count in edges.items())


def test_triangles_come_as_rows_of_three_sharing_the_indices():
    mesh = mvox.extract(blobs(np.uint16), 20000, triangulate=True)
    assert mesh.faces.shape == (len(mesh.polygon_offsets) - 1, 3)
    assert np.array_equal(np.diff(mesh.polygon_offsets), np.full(len(mesh.faces), 3))
    assert np.shares_memory(mesh.faces, mesh.polygon_indices)


def test_strided_slices_and_rows_are_read_in_place():
    # A view of every other slice and row of a larger array: rows contiguous, so no copy.
    big = blobs(np.uint8, shape=(18, 22, 13), seed=3)
    view = big[::2, ::2, :]
    assert not view.flags.c_contiguous
    assert mvox.extract(view, 100).vertices.tobytes() == \
        mvox.extract(np.ascontiguousarray(view), 100).vertices.tobytes()


@pytest.mark.parametrize("bad", [np.int32, np.float64, np.int8, np.uint32, bool])
def test_other_dtypes_are_a_type_error(bad):
    with pytest.raises(TypeError, match="mvox reads uint8, uint16, int16 and float32"):
        mvox.extract(np.zeros((3, 4, 5), dtype=bad), 1)


def test_big_endian_samples_are_a_type_error():
    with pytest.raises(TypeError):
        mvox.extract(np.zeros((3, 4, 5), dtype=">u2"), 1)


def test_rows_that_are_not_contiguous_are_copied_only_when_asked():
    volume = blobs(np.uint8, shape=(9, 11, 26))[:, :, ::2]
    with pytest.raises(ValueError, match="rows are not contiguous"):
        mvox.extract(volume, 100)
    copied = mvox.extract(volume, 100, copy=True)
    assert copied.vertices.tobytes() == mvox.extract(np.ascontiguousarray(volume), 100).vertices.tobytes()


def test_bad_shapes_methods_and_placements_are_value_errors():
    with pytest.raises(ValueError, match="3 dimensions"):
        mvox.extract(np.zeros((4, 5), np.uint8), 1)
    with pytest.raises(ValueError, match="empty"):
        mvox.extract(np.zeros((0, 5, 5), np.uint8), 1)
    with pytest.raises(ValueError, match="method"):
        mvox.extract(np.zeros((3, 4, 5), np.uint8), 1, method="tetrahedra")
    with pytest.raises(mvox.Error, match="spacing"):
        mvox.extract(np.zeros((3, 4, 5), np.uint8), 1, spacing=(0, 1, 1))


def test_a_dtype_that_came_through_pickle_is_read():
    import pickle
    volume = pickle.loads(pickle.dumps(blobs(np.uint16)))
    assert mvox.extract(volume, 20000).vertices.tobytes() == \
        mvox.extract(blobs(np.uint16), 20000).vertices.tobytes()


def test_a_deep_volume_with_its_surface_in_the_first_slices_reserves_little():
    """The arrays grow to what the share of slices done predicts: a surface in the first 3 of
    20,000 slices must not make that prediction reserve gigabytes."""
    def vm_peak_kib():
        status = open("/proc/self/status").read()
        return int(status.split("VmPeak:")[1].split()[0])
    volume = np.zeros((20000, 64, 64), np.uint8)
    volume[:3] = np.random.default_rng(1).integers(0, 255, (3, 64, 64), dtype=np.uint8)
    before = vm_peak_kib()
    mesh = mvox.extract(volume, 128)
    assert mesh.counters["vertices"] > 1000
    assert vm_peak_kib() - before < 512 * 1024, "more than 512 MiB of address space reserved"


def test_interpolated_vertices_keep_the_polygons_and_move_along_their_edges():
    volume = blobs(np.float32)
    midpoints = mvox.extract(volume, threshold_of(np.float32))
    moved = mvox.extract(volume, threshold_of(np.float32), interpolate=True)
    assert np.array_equal(moved.polygon_offsets, midpoints.polygon_offsets)
    assert np.array_equal(moved.polygon_indices, midpoints.polygon_indices)
    shift = moved.vertices - midpoints.vertices
    # One coordinate a vertex, by at most half a voxel; most vertices move.
    assert np.all(np.count_nonzero(shift, axis=1) <= 1)
    assert np.all(np.abs(shift) <= 0.5)
    assert np.count_nonzero(shift) > len(shift) // 2


def test_indices_turn_int64_past_2_to_31_vertices_and_stay_whole_past_2_to_32(tmp_path):
    """A mesh of more than 2^31 vertices gets int64 indices, never wrapped ones. The engine
    numbers from just below each limit (mvox._extract_numbered_from, the common case's own
    sink), so the indices pass it without billions of vertices; they must be the ones numbered
    from 0, moved. mvox.write takes the int64 arrays (and refuses these, whose indices point
    past the vertices the mesh holds, as it refuses any such face)."""
    volume = np.random.default_rng(7).integers(0, 255, (20, 30, 40), dtype=np.uint8)
    reference = mvox.extract(volume, 128)
    assert reference.polygon_indices.dtype == np.int32
    assert len(reference.vertices) > 20000
    from_zero = mvox._extract_numbered_from(volume, 128, 0)
    assert from_zero.polygon_indices.dtype == np.int32
    assert np.array_equal(from_zero.polygon_indices, reference.polygon_indices)
    for first in (2**31 - 10000, 2**32 - 10000):
        mesh = mvox._extract_numbered_from(volume, 128, first)
        assert mesh.polygon_indices.dtype == np.int64
        assert np.array_equal(mesh.polygon_offsets, reference.polygon_offsets)
        assert np.array_equal(mesh.polygon_indices, reference.polygon_indices.astype(np.int64) + first)
        assert mesh.polygon_indices.max() > first + 10000, "no index passed the limit"
        with pytest.raises(ValueError, match="refers to vertex"):
            mvox.write(mesh, str(tmp_path / "wide.ply"))
        assert not (tmp_path / "wide.ply").exists()
