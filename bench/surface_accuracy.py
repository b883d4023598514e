#!/usr/bin/python3
"""How close a mesh lies to the surface it stands for: a sphere of radius 37.3 voxels in a
100^3 volume, centred off the grid, sampled two ways (a grey partial-volume sphere, each voxel
the fraction of a one-voxel ramp across the boundary as a scanner records it, u8 0..255; and the
binary 0/255 sphere a segmentation gives), turned into meshes by mvox in each of its vertex
placements and, when VTK is installed, by vtkFlyingEdges3D with and without the smoothing 3D
Slicer applies on export. For each mesh:

- mean distance of the vertices to the true sphere, in voxels;
- the area-weighted mean angle between each face's normal and the radial direction at its
  centre, in degrees (what flat shading and a print show).

    PYTHONPATH=build/python /usr/bin/python3 bench/surface_accuracy.py [--mvox build/src/mvox]

Needs the module `mvox` on PYTHONPATH and numpy; the mvox executable for the --smooth rows (the
module does not smooth); VTK (python3-vtk9, scripts/install_bench_deps.sh) for its rows.
"""
import argparse
import os
import subprocess
import tempfile

import numpy as np

import mvox

SIZE, RADIUS = 100, 37.3
CENTRE = np.array([49.6, 50.3, 49.8])  # x, y, z, off the grid


def spheres():
    z, y, x = np.mgrid[0:SIZE, 0:SIZE, 0:SIZE].astype(np.float64)
    distance = np.sqrt((x - CENTRE[0]) ** 2 + (y - CENTRE[1]) ** 2 + (z - CENTRE[2]) ** 2)
    grey = np.clip(0.5 + (RADIUS - distance), 0.0, 1.0)
    return {
        "grey partial-volume sphere": np.round(grey * 255).astype(np.uint8),
        "binary (0/255) sphere": np.where(distance <= RADIUS, 255, 0).astype(np.uint8),
    }


def measures(vertices, offsets, indices):
    """(mean vertex distance to the sphere, area-weighted face-normal angle to radial)."""
    distance = np.abs(np.linalg.norm(vertices - CENTRE, axis=1) - RADIUS).mean()
    sizes = np.diff(offsets)
    total_area, total_angle = 0.0, 0.0
    for size in np.unique(sizes):
        rows = np.nonzero(sizes == size)[0]
        corners = vertices[indices[offsets[rows][:, None] + np.arange(size)]]  # (F, size, 3)
        # A polygon's vector area: half the sum of its corners' cross products (Newell).
        area_vector = 0.5 * np.cross(corners, np.roll(corners, -1, axis=1)).sum(axis=1)
        area = np.linalg.norm(area_vector, axis=1)
        keep = area > 0
        normal = area_vector[keep] / area[keep, None]
        radial = corners[keep].mean(axis=1) - CENTRE
        radial /= np.linalg.norm(radial, axis=1)[:, None]
        angle = np.degrees(np.arccos(np.clip((normal * radial).sum(axis=1), -1.0, 1.0)))
        total_area += area[keep].sum()
        total_angle += (angle * area[keep]).sum()
    return distance, total_angle / total_area


def mvox_rows(volume):
    for label, options in (("mvox (midpoints)", {}),
                           ("mvox --interpolate", {"interpolate": True}),
                           ("mvox --method cubes", {"method": "cubes"})):
        mesh = mvox.extract(volume, 128, **options)
        yield label, measures(mesh.vertices.astype(np.float64), mesh.polygon_offsets,
                              mesh.polygon_indices.astype(np.int64))


def read_binary_ply(path):
    """(vertices float64 (N, 3), offsets, indices) of mvox's binary PLY without normals."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    vertex_count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    face_count = next(int(line.split()[2]) for line in header if line.startswith("element face"))
    vertices = np.frombuffer(data, "<f4", 3 * vertex_count, end).reshape(-1, 3).astype(np.float64)
    at, offsets, indices = end + 12 * vertex_count, [0], []
    for _ in range(face_count):
        size = data[at]
        indices.append(np.frombuffer(data, "<i4", size, at + 1))
        offsets.append(offsets[-1] + size)
        at += 1 + 4 * size
    return vertices, np.array(offsets), np.concatenate(indices).astype(np.int64)


def smooth_rows(volume, binary_path):
    with tempfile.TemporaryDirectory() as scratch:
        raw = os.path.join(scratch, "v.raw")
        volume.tofile(raw)
        for label, options in (("mvox --smooth 5", ["--smooth", "5"]),
                               ("mvox --smooth 10", ["--smooth", "10"]),
                               ("mvox --smooth 20", ["--smooth", "20"]),
                               ("mvox --interpolate --smooth 10", ["--interpolate", "--smooth", "10"])):
            mesh = os.path.join(scratch, "m.ply")
            subprocess.run([binary_path, "extract", raw, "--raw", f"{SIZE}x{SIZE}x{SIZE}:u8", "-t", "128",
                            "-o", mesh, "-q"] + options, check=True)
            yield label, measures(*read_binary_ply(mesh))


def vtk_rows(volume):
    try:
        import vtk
        from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    except ImportError:
        return
    image = vtk.vtkImageData()
    image.SetDimensions(SIZE, SIZE, SIZE)
    image.GetPointData().SetScalars(numpy_to_vtk(volume.ravel(), deep=True))
    contour = vtk.vtkFlyingEdges3D()
    contour.SetInputData(image)
    contour.SetValue(0, 127.5)  # exactly the voxels >= 128 inside, mvox's classification
    contour.ComputeNormalsOff()
    contour.Update()
    smoother = vtk.vtkWindowedSincPolyDataFilter()
    smoother.SetInputData(contour.GetOutput())
    smoother.SetNumberOfIterations(20)
    smoother.SetPassBand(0.01)
    smoother.NormalizeCoordinatesOn()
    smoother.Update()
    for label, output in (("vtkFlyingEdges3D", contour.GetOutput()),
                          ("vtkFlyingEdges3D + vtkWindowedSincPolyDataFilter (20, pass band 0.01)",
                           smoother.GetOutput())):
        points = vtk_to_numpy(output.GetPoints().GetData()).astype(np.float64)
        polys = output.GetPolys()
        yield label, measures(points, vtk_to_numpy(polys.GetOffsetsArray()).astype(np.int64),
                              vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--mvox", default=os.path.join(root, "build", "src", "mvox"))
    arguments = parser.parse_args()
    print(f"Sphere of radius {RADIUS} voxels, centre {tuple(CENTRE)}, in a {SIZE}^3 u8 volume; "
          "threshold 128.\n")
    print("| volume | mesh | mean distance to the sphere (voxels) | "
          "area-weighted face-normal error vs radial |")
    print("|---|---|---|---|")
    for name, volume in spheres().items():
        rows = list(mvox_rows(volume)) + list(smooth_rows(volume, arguments.mvox)) + list(vtk_rows(volume))
        for label, (distance, angle) in rows:
            print(f"| {name} | {label} | {distance:.3f} | {angle:.1f} deg |")


if __name__ == "__main__":
    main()
