#!/usr/bin/python3
"""mvox's Python module against vtkFlyingEdges3D and scikit-image's marching_cubes, each called
the way a Python user calls it: a numpy volume in, numpy arrays out, in one process, one thread
each, on the paper's three datasets.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_side_by_side.py [--runs N]
        [--datasets DIR] [--extract-once PATH]

Needs Debian's python3-vtk9 and python3-skimage (scripts/install_bench_deps.sh), hence
/usr/bin/python3, the module `mvox` on PYTHONPATH and build/bench/mvox_bench_extract_once (only
for its dataset table, bench/paper_datasets.cpp, so that there is one copy of it).

Each dataset is read once (bench/peers_io.py) into a [z, y, x] array of its own dtype; every
timed call starts from that array, and nothing is prepared for any tool beforehand:
- mvox: mvox.extract(volume, D); its vertices, polygon_offsets and polygon_indices are numpy.
- vtkFlyingEdges3D: a vtkImageData on the array's own memory (numpy_to_vtk, deep=False), the
  filter at D - 0.5 with normals, gradients and scalars off (as compare_peers.py), Update(), then
  points and triangles as numpy (vtk_to_numpy of the points and of the polys' connectivity).
- skimage.measure.marching_cubes(volume, level=D - 0.5, method="lewiner",
  allow_degenerate=True): compare_peers.py's call (it passes only the level, and these are the
  defaults), except that here the float32 conversion it does inside is timed, as a user pays it.
D - 0.5 on integer samples puts exactly the voxels >= D inside, mvox's classification.

Timing as compare_peers.py: one untimed round, then N rounds with the order rotated each round;
in each round every tool runs 3 times back to back and its fastest run counts. Ratios are taken
per round (peer / mvox), then their median and range; times are medians over rounds.
"""
import argparse
import os
import statistics
import sys

import numpy as np
import skimage
import vtk
from skimage.measure import marching_cubes
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import mvox
import peers_io
from compare_peers import (
    force_one_vtk_thread,
    kBackToBack,
    kOtherThreadsCpuMaxS,
    other_threads_cpu_s,
    time_tools,
    timed,
)

CHECKOUT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The targets: peer time / mvox time, median over rounds.
TARGETS = {"vtkFlyingEdges3D": 5.0, "skimage": 20.0}


def mvox_call(volume, threshold):
    mesh = mvox.extract(volume, threshold)
    return len(mesh.polygon_offsets) - 1, mesh


def vtk_call(volume, iso):
    depth, height, width = volume.shape
    image = vtk.vtkImageData()
    image.SetDimensions(width, height, depth)  # numpy [z, y, x] is VTK's x-fastest order
    image.GetPointData().SetScalars(numpy_to_vtk(volume.ravel(), deep=False))
    contour = vtk.vtkFlyingEdges3D()
    contour.SetInputData(image)
    contour.SetValue(0, iso)
    contour.ComputeNormalsOff()
    contour.ComputeGradientsOff()
    contour.ComputeScalarsOff()
    contour.Update()
    output = contour.GetOutput()
    points = vtk_to_numpy(output.GetPoints().GetData())
    triangles = vtk_to_numpy(output.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    # The numpy arrays are views of VTK's memory: `output` goes with them to keep it alive.
    return len(triangles), (points, triangles, output)


def skimage_call(volume, iso):
    vertices, faces, normals, values = marching_cubes(
        volume, level=iso, method="lewiner", allow_degenerate=True
    )
    return len(faces), (vertices, faces, normals, values)


# Each tool's CPU time outside the main thread, so that a second thread can be pinned on one.
elsewhere_by_tool = {}


def best_of_back_to_back(name, call):
    """(fastest wall seconds of kBackToBack calls, face count). The result of each call is
    dropped only after its timing, so no tool's freeing of its arrays is timed."""

    def run():
        best, counts = float("inf"), set()
        for _ in range(kBackToBack):
            before = other_threads_cpu_s()
            wall, _, (faces, _) = timed(call)
            elsewhere = other_threads_cpu_s() - before
            elsewhere_by_tool[name] = elsewhere_by_tool.get(name, 0) + elsewhere
            best, counts = min(best, wall), counts | {faces}
        if len(counts) != 1:
            raise RuntimeError(f"{name} gave different face counts: {counts}")
        return best, counts.pop()

    return run


def compare_dataset(dataset, volume, runs):
    threshold = dataset["threshold"]
    if not np.issubdtype(volume.dtype, np.integer):
        raise ValueError(f"{dataset['name']}: {volume.dtype} samples, D - 0.5 needs integers")
    iso = threshold - 0.5
    results = time_tools(
        {
            "mvox": best_of_back_to_back("mvox", lambda: mvox_call(volume, threshold)),
            "vtkFlyingEdges3D": best_of_back_to_back(
                "vtkFlyingEdges3D", lambda: vtk_call(volume, iso)
            ),
            "skimage": best_of_back_to_back("skimage", lambda: skimage_call(volume, iso)),
        },
        runs,
    )
    median_ms = {
        name: statistics.median(wall for wall, _ in rounds) * 1e3
        for name, rounds in results.items()
    }
    faces = {name: rounds[0][1] for name, rounds in results.items()}
    ratios = {
        peer: [p[0] / m[0] for p, m in zip(results[peer], results["mvox"])] for peer in TARGETS
    }
    return median_ms, faces, ratios


def ratio_cell(per_round):
    return f"{statistics.median(per_round):.2f}x ({min(per_round):.2f} .. {max(per_round):.2f})"


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=9, help="interleaved rounds (median)")
    parser.add_argument(
        "--datasets",
        default=os.path.join(os.path.dirname(CHECKOUT), "shared", "datasets"),
        help="the datasets folder (default: ../shared/datasets beside the checkout)",
    )
    parser.add_argument(
        "--extract-once",
        default=os.path.join(CHECKOUT, "build", "bench", "mvox_bench_extract_once"),
        help="mvox_bench_extract_once, for the dataset table",
    )
    args = parser.parse_args()
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    return args


def main():
    args = parse_arguments()
    backend, threads = force_one_vtk_thread()
    print(
        f"mvox module {mvox.__file__}; VTK {vtk.vtkVersion.GetVTKVersion()} (vtkSMPTools"
        f" backend {backend}, {threads} thread); scikit-image {skimage.__version__}"
        f" (method 'lewiner', allow_degenerate=True); numpy {np.__version__}. Median of"
        f" {args.runs} interleaved rounds, each the fastest of {kBackToBack} back-to-back calls;"
        " ms per call, array in, numpy arrays out. Ratios: peer time / mvox time per round,"
        " median (min .. max)."
    )
    print()
    print(
        "| dataset | mvox.extract | vtkFlyingEdges3D | skimage | VTK/mvox (range)"
        " | skimage/mvox (range) | mvox polygons | VTK triangles | skimage triangles |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    verdicts, compared = [], 0
    for dataset in peers_io.list_datasets(args.extract_once, args.datasets):
        if not dataset["present"]:
            verdicts.append(f"- {dataset['name']}: skipped, {dataset['inputs'][0]} not found")
            continue
        volume = peers_io.load_volume(dataset)
        ms, faces, ratios = compare_dataset(dataset, volume, args.runs)
        depth, height, width = volume.shape
        print(
            f"| {dataset['name']} ({width}x{height}x{depth} {volume.dtype},"
            f" >= {dataset['threshold']:g})"
            f" | {ms['mvox']:.1f} | {ms['vtkFlyingEdges3D']:.1f} | {ms['skimage']:.1f}"
            f" | {ratio_cell(ratios['vtkFlyingEdges3D'])} | {ratio_cell(ratios['skimage'])}"
            f" | {faces['mvox']:,} | {faces['vtkFlyingEdges3D']:,} | {faces['skimage']:,} |",
            flush=True,
        )
        compared += 1
        for peer, target in TARGETS.items():
            speedup = statistics.median(ratios[peer])
            verdict = "met" if speedup >= target else "**not met**"
            verdicts.append(
                f"- {dataset['name']}: >= {target:g}x {peer}: {speedup:.2f}x, {verdict}"
            )
    print("\nTargets (median of the per-round ratios):")
    print("\n".join(verdicts))
    elsewhere = other_threads_cpu_s()
    by_tool = ", ".join(f"{name} {s:.3f} s" for name, s in elsewhere_by_tool.items())
    single = elsewhere < kOtherThreadsCpuMaxS
    print(
        f"\nCPU time outside the main thread: {elsewhere:.3f} s in all (during the timed calls:"
        f" {by_tool})"
        + (": every tool ran on one thread." if single else ": NOT single-threaded, invalid.")
    )
    return 0 if compared and single else 1


if __name__ == "__main__":
    sys.exit(main())
