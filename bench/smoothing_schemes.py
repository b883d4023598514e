#!/usr/bin/python3
"""Which smoothing can make a binary mask's surface smooth while every vertex stays on its own
voxel edge segment (issue 16's constraint: the smoothed surface still separates the same inner
and outer voxels)? An experiment in numpy on mvox's mesh of the binary sphere of
bench/surface_accuracy.py (radius 37.3 in 100^3), before any of it goes into the engine's
stream. Each scheme moves a vertex only along its edge's axis, clamped to 0.01 voxel inside the
segment between its two voxel centres; vertices against the volume's border stay put.

- Laplacian: the axis component of (mean of the neighbours - vertex), times f.
- Taubin: the same with f = lambda, mu alternating (mu < 0 undoes the shrinking).
- normal-projected Laplacian: the step along the axis that moves the vertex by the normal
  component of (mean - vertex), with the normal estimated from the faces around the vertex:
  s = f * n.(mean - p) / n[axis] (|n[axis]| taken as at least 0.2). The plain axis component
  ignores the tangential part of a neighbour's offset that a vertex on another axis could
  correct; this step asks the vertex to correct what it can of the offset across the surface.

Prints, per scheme and number of iterations, the mean distance of the vertices to the true
sphere and the area-weighted angle between face normals and the radial direction (the
measures of bench/surface_accuracy.py).

    PYTHONPATH=build/python /usr/bin/python3 bench/smoothing_schemes.py
"""
import numpy as np

import mvox
from surface_accuracy import SIZE, measures, spheres

EPSILON = 0.01  # how close to a voxel centre a vertex may come
MIN_AXIS_NORMAL = 0.2


class EdgeMesh:
    """mvox's mesh of a volume with, for each vertex, its edge: axis, lower end, fixed."""

    def __init__(self, volume, threshold):
        mesh = mvox.extract(volume, threshold)
        self.vertices = mesh.vertices.astype(np.float64)
        self.offsets = mesh.polygon_offsets
        self.indices = mesh.polygon_indices.astype(np.int64)
        half = np.abs(self.vertices - np.floor(self.vertices) - 0.5) < 1e-6
        assert (half.sum(axis=1) == 1).all(), "each midpoint has one coordinate at a half"
        self.axis = np.argmax(half, axis=1)
        self.rows = np.arange(len(self.vertices))
        self.lower = self.vertices[self.rows, self.axis] - 0.5
        self.fixed = (self.lower < 0) | (self.lower + 1 >= SIZE)
        self.sizes = np.diff(self.offsets)
        self.corners = {int(size): self.indices[self.offsets[np.nonzero(self.sizes == size)[0]]
                                                [:, None] + np.arange(size)]
                        for size in np.unique(self.sizes)}
        # Directed polygon sides both ways: every neighbour of a closed surface counted twice.
        sides = [(c.ravel(), np.roll(c, -1, axis=1).ravel()) for c in self.corners.values()]
        self.source = np.concatenate([a for a, b in sides] + [b for a, b in sides])
        self.target = np.concatenate([b for a, b in sides] + [a for a, b in sides])
        self.degree = np.bincount(self.source, minlength=len(self.vertices)).astype(np.float64)

    def laplacian(self, points):
        mean = np.stack([np.bincount(self.source, weights=points[self.target, d],
                                     minlength=len(points)) for d in range(3)], axis=1)
        return mean / self.degree[:, None] - points

    def normals(self, points):
        total = np.zeros_like(points)
        for size, corners in self.corners.items():
            at = points[corners]
            area_vector = 0.5 * np.cross(at, np.roll(at, -1, axis=1)).sum(axis=1)
            for k in range(size):
                for d in range(3):
                    total[:, d] += np.bincount(corners[:, k], weights=area_vector[:, d],
                                               minlength=len(points))
        return total / np.maximum(np.linalg.norm(total, axis=1)[:, None], 1e-12)

    def move(self, points, step):
        along = np.clip(points[self.rows, self.axis] + step, self.lower + EPSILON,
                        self.lower + 1 - EPSILON)
        along[self.fixed] = self.lower[self.fixed] + 0.5
        points[self.rows, self.axis] = along

    def smooth(self, scheme, iterations, factors):
        points = self.vertices.copy()
        for k in range(iterations):
            f = factors[k % len(factors)]
            offset = self.laplacian(points)
            if scheme == "normal-projected":
                n = self.normals(points)
                axis_normal = n[self.rows, self.axis]
                axis_normal = np.where(np.abs(axis_normal) < MIN_AXIS_NORMAL,
                                       np.copysign(MIN_AXIS_NORMAL, axis_normal), axis_normal)
                self.move(points, f * (n * offset).sum(axis=1) / axis_normal)
            else:
                self.move(points, f * offset[self.rows, self.axis])
        return measures(points, self.offsets, self.indices)


def main():
    mesh = EdgeMesh(spheres()["binary (0/255) sphere"], 128)
    distance, angle = measures(mesh.vertices, mesh.offsets, mesh.indices)
    print(f"Binary sphere, mvox's midpoints: {distance:.3f} voxels, {angle:.1f} deg.\n")
    print("| scheme | factors | iterations | mean distance (voxels) | face normals vs radial |")
    print("|---|---|---|---|---|")
    for scheme, factors in (("Laplacian", (0.5,)), ("Taubin", (0.6, -0.62)),
                            ("normal-projected", (0.3,)), ("normal-projected", (0.6,))):
        for iterations in (5, 10, 20, 40):
            distance, angle = mesh.smooth(scheme, iterations, factors)
            print(f"| {scheme} | {', '.join(map(str, factors))} | {iterations} | "
                  f"{distance:.3f} | {angle:.1f} deg |")


if __name__ == "__main__":
    main()
