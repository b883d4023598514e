"""The vertex-set check behind bench/compare_peers.py: on a 0/1 volume, mvox's vertices and
VTK's must be the same set of points.

On 0/1 data at iso value 0.5 every marching-cubes vertex lies at the midpoint of an edge between
an inner and an outer voxel, and so does every marching-voxels vertex (docs/design.md section 2): the
two methods must find exactly the same points, each once. The check thresholds a dataset to a
0/1 mask, lets `mvox extract` read it as a raw volume and write a PLY file, and compares that
file's vertices with the points of vtkFlyingEdges3D, vtkMarchingCubes and
vtkDiscreteFlyingEdges3D on the same mask.

mvox treats the voxels outside the volume as outer, so its surfaces close at the volume's
border; VTK's stop there, open. VTK therefore gets the mask inside one layer of zeros, with
its origin moved to -1 so that the coordinates stay those of the unpadded volume.
"""
import os
import subprocess

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import peers_io


def vtk_image(volume, origin=(0.0, 0.0, 0.0)):
    """A vtkImageData holding a copy of `volume`. numpy's axes are (z, y, x) with x fastest in
    memory, which is VTK's point order for dimensions (x, y, z)."""
    depth, height, width = volume.shape
    image = vtk.vtkImageData()
    image.SetDimensions(width, height, depth)
    image.SetOrigin(*origin)
    image.SetSpacing(1.0, 1.0, 1.0)
    image.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(volume).ravel(), deep=True))
    return image


def vtk_contour(filter_class, image, value):
    """An iso-surface filter on `image` that produces only the surface: no normals, gradients or
    scalars (mvox computes none of them either unless asked)."""
    contour = filter_class()
    contour.SetInputData(image)
    contour.SetValue(0, value)
    contour.ComputeNormalsOff()
    contour.ComputeGradientsOff()
    contour.ComputeScalarsOff()
    return contour


def doubled_points(points, what):
    """Points with coordinates on the half-integer grid, doubled into exact integers."""
    doubled = np.asarray(points, dtype=np.float64) * 2
    rounded = np.rint(doubled)
    if not np.array_equal(doubled, rounded):
        raise ValueError(f"{what}: a vertex is not at an edge midpoint")
    return rounded.astype(np.int64)


def point_keys(doubled, shape):
    """One integer per doubled point (coordinates from -1 to twice the size, inclusive), sorted
    and distinct, and how many points there were in all."""
    sizes = 2 * np.array(shape[::-1], dtype=np.int64) + 1  # x, y, z
    x, y, z = (doubled + 1).T
    keys = (z * sizes[1] + y) * sizes[0] + x
    return np.unique(keys), len(keys)


def check_dataset(name, volume, threshold, mvox, scratch):
    """Runs the check on `volume` thresholded at `threshold` with the `mvox` program, writing
    scratch files into the directory `scratch`. Returns whether every set and count agrees, the
    report as lines, and mvox's (vertex, polygon) counts on the mask."""
    mask = (volume >= threshold).astype(np.uint8)
    depth, height, width = mask.shape
    raw = os.path.join(scratch, f"{name}_mask.raw")
    ply = os.path.join(scratch, f"{name}_mask.ply")
    mask.tofile(raw)  # slice after slice, rows packed: mvox's raw volume layout
    subprocess.run(
        [mvox, "extract", raw, "--raw", f"{width}x{height}x{depth}:u8", "-t", "1", "-o", ply, "-q"],
        check=True,
    )
    mvox_vertices, mvox_faces = peers_io.read_ply(ply)
    mvox_set, mvox_count = point_keys(doubled_points(mvox_vertices, f"{name}: mvox"), mask.shape)
    os.remove(raw)
    os.remove(ply)

    border = mask.copy()
    border[1:-1, 1:-1, 1:-1] = 0
    padded = vtk_image(np.pad(mask, 1), origin=(-1.0, -1.0, -1.0))
    ok = mvox_count == len(mvox_set)
    lines = [
        f"{name}: mask of {int(mask.sum()):,} inner voxels"
        f" ({'touching' if border.any() else 'not touching'} the volume's border);"
        f" mvox: {mvox_count:,} vertices ({len(mvox_set):,} distinct), {mvox_faces:,} polygons"
    ]
    for filter_class, value in [
        (vtk.vtkFlyingEdges3D, 0.5),
        (vtk.vtkMarchingCubes, 0.5),
        (vtk.vtkDiscreteFlyingEdges3D, 1),
    ]:
        contour = vtk_contour(filter_class, padded, value)
        contour.Update()
        output = contour.GetOutput()
        points = vtk_to_numpy(output.GetPoints().GetData())
        doubled = doubled_points(points, f"{name}: {filter_class.__name__}")
        vtk_set, vtk_count = point_keys(doubled, mask.shape)
        same_set = np.array_equal(mvox_set, vtk_set)
        ok = ok and same_set and vtk_count == mvox_count
        difference = (
            ""
            if same_set
            else f" ({len(np.setdiff1d(mvox_set, vtk_set)):,} only in mvox's,"
            f" {len(np.setdiff1d(vtk_set, mvox_set)):,} only in VTK's)"
        )
        lines.append(
            f"  {filter_class.__name__} (value {value}): {vtk_count:,} points"
            f" ({len(vtk_set):,} distinct), {output.GetNumberOfPolys():,} triangles;"
            f" vertex set {'EQUAL' if same_set else 'DIFFERENT'}{difference},"
            f" vertex count {'equal' if vtk_count == mvox_count else 'DIFFERENT'}"
        )
    return ok, lines, (mvox_count, mvox_faces)
