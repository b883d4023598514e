#!/usr/bin/python3
"""Checks a mesh file with VTK, an independent reader: is the surface closed, manifold and
consistently wound? Usage: scripts/check_mesh_vtk.py MESH.ply|MESH.stl|MESH.obj [...]

Reads with vtkPLYReader, vtkSTLReader (which merges the triangles' repeated vertices) or
vtkOBJReader by extension, counts boundary and non-manifold edges with vtkFeatureEdges, and checks
the winding itself: every directed edge must appear once and its reverse once. Prints one line
per file and exits 1 if any file is open or inconsistently wound. Needs Debian's python3-vtk9 and
python3-numpy (scripts/install_bench_deps.sh)."""
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


READERS = {".ply": vtk.vtkPLYReader, ".stl": vtk.vtkSTLReader, ".obj": vtk.vtkOBJReader}


def check(path):
    extension = path[path.rfind(".") :].lower()
    if extension not in READERS:
        return False, f"{path}: not .ply, .stl or .obj"
    reader = READERS[extension]()
    reader.SetFileName(path)
    reader.Update()
    mesh = reader.GetOutput()
    if mesh.GetNumberOfPoints() == 0:
        return False, f"{path}: VTK read no points"

    features = vtk.vtkFeatureEdges()
    features.SetInputData(mesh)
    features.BoundaryEdgesOn()
    features.NonManifoldEdgesOff()
    features.FeatureEdgesOff()
    features.ManifoldEdgesOff()
    features.Update()
    boundary = features.GetOutput().GetNumberOfLines()
    features.BoundaryEdgesOff()
    features.NonManifoldEdgesOn()
    features.Update()
    non_manifold = features.GetOutput().GetNumberOfLines()

    # Polygons as (count, i0, i1, ...) runs; directed edges (a, b) around each.
    cells = vtk_to_numpy(mesh.GetPolys().GetData()).astype(np.int64)
    points = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64)
    heads, tails, volume, sizes = [], [], 0.0, {}
    i = 0
    while i < len(cells):
        n = int(cells[i])
        poly = cells[i + 1 : i + 1 + n]
        sizes[n] = sizes.get(n, 0) + 1
        heads.append(poly)
        tails.append(np.roll(poly, -1))
        p0 = points[poly[0]]
        for k in range(1, n - 1):  # fan: signed volume of the enclosed solid
            volume += np.dot(p0, np.cross(points[poly[k]], points[poly[k + 1]])) / 6.0
        i += n + 1
    a = np.concatenate(heads)
    b = np.concatenate(tails)
    key = a * mesh.GetNumberOfPoints() + b
    reverse = b * mesh.GetNumberOfPoints() + a
    unique_keys, counts = np.unique(key, return_counts=True)
    repeated = int(np.sum(counts > 1))
    unmatched = int(np.sum(~np.isin(key, reverse)))
    edges = (len(unique_keys) + unmatched) // 2
    euler = mesh.GetNumberOfPoints() - edges - 0 + mesh.GetNumberOfPolys()

    connectivity = vtk.vtkPolyDataConnectivityFilter()
    connectivity.SetInputData(mesh)
    connectivity.SetExtractionModeToAllRegions()
    connectivity.Update()
    components = connectivity.GetNumberOfExtractedRegions()

    ok = boundary == 0 and non_manifold == 0 and repeated == 0 and unmatched == 0 and volume > 0
    sizes_text = ", ".join(f"{n}:{c}" for n, c in sorted(sizes.items()))
    return ok, (
        f"{path}: {'OK' if ok else 'NOT CLOSED/CONSISTENT'} ({reader.GetClassName()}): "
        f"{mesh.GetNumberOfPoints()} points, "
        f"{mesh.GetNumberOfPolys()} polygons ({sizes_text}), boundary edges {boundary}, "
        f"non-manifold edges {non_manifold}, repeated directed edges {repeated}, "
        f"edges without their reverse {unmatched}, Euler characteristic {euler}, "
        f"components {components}, signed volume {volume:.6g}"
    )


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    all_ok = True
    for path in sys.argv[1:]:
        ok, line = check(path)
        print(line)
        all_ok &= ok
    return 0 if all_ok else 1


if __name__ == "__main__":
    sys.exit(main())
