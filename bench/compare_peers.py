#!/usr/bin/python3
"""Side by side with today's tools: mvox, VTK and scikit-image extracting the same surfaces from
the paper's three datasets, in one run, one thread each, extraction only, in memory.

    /usr/bin/python3 bench/compare_peers.py [--runs N] [--mvox-build DIR] [--datasets DIR]
                                            [--no-check-vertices]

Needs Debian's python3-vtk9 and python3-skimage (scripts/install_bench_deps.sh), hence
/usr/bin/python3, and build/bench/mvox_bench_extract_once and build/src/mvox.

Tools, each timed on the same volume in the same process run after run:
- mvox, in memory: mvox_bench_extract_once, the fast engine on slices already decoded into
  memory, into a sink that only counts (loading and a warm-up run are not timed).
- mvox, end to end: the wall time of `mvox extract FILES -t D -o tmp.ply`, a whole process:
  start-up, reading the files (from the page cache), extracting, writing binary PLY.
- vtkFlyingEdges3D, vtkMarchingCubes: Update() on a vtkImageData built beforehand from the
  numpy volume, iso value D - 0.5 on integer data so that exactly the voxels >= D are inside.
- vtkDiscreteFlyingEdges3D: the same on the 0/1 mask (volume >= D), label 1.
- skimage.measure.marching_cubes(volume, D - 0.5), default method ('lewiner'), on a float32
  copy of the volume made beforehand (the function converts to float32 itself otherwise).

Every tool runs once untimed first (page cache, first-call costs), then N times interleaved,
with the order rotated each run so that a noisy shared machine biases none of them; medians are
reported. Then the vertex-set check (peer_vertex_check.py) compares mvox's vertices with VTK's
on the 0/1 masks. The script exits 1 when they differ, or when any work in this process ran
outside its main thread (so some tool was not single-threaded after all).
"""
import argparse
import collections
import gc
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import skimage
import vtk
from skimage.measure import marching_cubes

import peer_vertex_check
import peers_io
from peer_vertex_check import vtk_contour, vtk_image

CHECKOUT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

Run = collections.namedtuple("Run", "wall_s cpu_s polygons vertices")

# More CPU time than this outside the main thread means some tool used a second thread. With
# VTK's Sequential backend it is 0; TBB's or STDThread's workers take tenths of a second.
kOtherThreadsCpuMaxS = 0.01


def force_one_vtk_thread():
    """VTK's filters run in parallel through vtkSMPTools (Debian's default backend is TBB with
    one thread per core); the Sequential backend runs them on the calling thread only."""
    smp = vtk.vtkSMPTools
    smp.SetBackend("Sequential")
    smp.Initialize(1)
    if smp.GetBackend() != "Sequential" or smp.GetEstimatedNumberOfThreads() != 1:
        sys.exit(
            f"compare_peers.py: VTK runs {smp.GetEstimatedNumberOfThreads()} threads"
            f" with the {smp.GetBackend()} backend, not one"
        )
    return smp.GetBackend(), smp.GetEstimatedNumberOfThreads()


def other_threads_cpu_s():
    """CPU seconds this process has spent outside its main thread since it started, threads that
    have exited included. 0 proves that VTK (or anything else) never ran work on another thread:
    with VTK's TBB or STDThread backends their workers show up here."""
    return max(0.0, time.process_time() - time.thread_time())


def timed(call):
    """(wall seconds, this process's CPU seconds over all its threads, call's result).
    CPU close to wall means one thread worked; two busy threads would give twice the wall."""
    gc.collect()
    gc.disable()  # no collector pause inside a timed call
    try:
        wall, cpu = time.perf_counter(), time.process_time()
        result = call()
        return time.perf_counter() - wall, time.process_time() - cpu, result
    finally:
        gc.enable()


# Each round, every in-memory tool runs this many times back to back and its fastest run counts:
# the steady state, with caches, branch predictors and the clock warmed alike for every tool
# (mvox's first run in a fresh process is 10-15% slower than its third).
kBackToBack = 3


def fastest(runs):
    return min(runs, key=lambda run: run.wall_s)


def vtk_tool(filter_class, image, value):
    contour = vtk_contour(filter_class, image, value)

    def once():
        contour.Modified()  # otherwise Update() returns the previous output without working
        wall, cpu, _ = timed(contour.Update)
        output = contour.GetOutput()
        return Run(wall, cpu, output.GetNumberOfPolys(), output.GetNumberOfPoints())

    return lambda: fastest([once() for _ in range(kBackToBack)])


def skimage_tool(volume, level):
    samples = np.ascontiguousarray(volume, dtype=np.float32)

    def once():
        wall, cpu, (vertices, faces, _, _) = timed(lambda: marching_cubes(samples, level))
        return Run(wall, cpu, len(faces), len(vertices))

    return lambda: fastest([once() for _ in range(kBackToBack)])


def mvox_in_memory_tool(extract_once, dataset, root, method="voxels"):
    command = [extract_once, "--dataset", dataset["name"], "--datasets", root]
    command += ["--runs", str(kBackToBack), "--method", method]

    def run():
        figures = json.loads(
            subprocess.run(command, check=True, capture_output=True, text=True).stdout
        )
        runs = [
            Run(wall_ms / 1e3, cpu_ms / 1e3, figures["polygons"], figures["vertices"])
            for wall_ms, cpu_ms in zip(figures["times_ms"], figures["cpu_ms"])
        ]
        return fastest(runs)

    return run


def mvox_end_to_end_tool(mvox, dataset, output):
    raw = ["--raw", dataset["raw"]] if dataset["raw"] else []
    threshold = f"{dataset['threshold']:g}"
    command = [mvox, "extract", *dataset["inputs"], *raw, "-t", threshold, "-o", output, "-q"]

    def run():
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall, _, _ = timed(lambda: subprocess.run(command, check=True))
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        vertices, faces = peers_io.read_ply(output)
        return Run(wall, cpu, faces, len(vertices))

    return run


def process_start_s(mvox, runs):
    """Median wall time of `mvox --help`: what starting the process costs (mostly loading the
    shared libraries Debian's OpenCV pulls in), part of every end-to-end time."""
    return statistics.median(
        timed(lambda: subprocess.run([mvox, "--help"], check=True, capture_output=True))[0]
        for _ in range(max(runs, 5))
    )


def time_tools(tools, runs):
    """{name: [Run, ...]}: one untimed round, then `runs` rounds, each in a rotated order."""
    names = list(tools)
    for name in names:
        tools[name]()
    results = {name: [] for name in names}
    for round_index in range(runs):
        shift = round_index % len(names)
        for name in names[shift:] + names[:shift]:
            results[name].append(tools[name]())
    return results


def compare_dataset(dataset, volume, args, scratch):
    """Times every tool on `volume`, the samples of `dataset`; returns the table rows, mvox's
    in-memory (vertex, polygon) counts, and whether the classification is exactly mvox's."""
    threshold = dataset["threshold"]
    # Integer samples: any value strictly between D - 1 and D classifies exactly as ">= D".
    exact = np.issubdtype(volume.dtype, np.integer)
    iso = threshold - 0.5 if exact else threshold
    mask = (volume >= threshold).astype(np.uint8)
    image, mask_image = vtk_image(volume), vtk_image(mask)
    at_least = f">= {threshold:g}"
    end_to_end_ply = os.path.join(scratch, "end_to_end.ply")
    tools = {  # name: (what the tool is given, how to run it once)
        "mvox, in memory": (
            at_least,
            mvox_in_memory_tool(args.extract_once, dataset, args.datasets),
        ),
        "mvox, end to end": (at_least, mvox_end_to_end_tool(args.mvox, dataset, end_to_end_ply)),
        "mvox --method cubes, in memory": (
            at_least,
            mvox_in_memory_tool(args.extract_once, dataset, args.datasets, "cubes"),
        ),
        "vtkFlyingEdges3D": (f"{iso:g}", vtk_tool(vtk.vtkFlyingEdges3D, image, iso)),
        "vtkMarchingCubes": (f"{iso:g}", vtk_tool(vtk.vtkMarchingCubes, image, iso)),
        "vtkDiscreteFlyingEdges3D": (
            f"label 1 of {at_least}",
            vtk_tool(vtk.vtkDiscreteFlyingEdges3D, mask_image, 1),
        ),
        "skimage marching_cubes": (f"{iso:g}", skimage_tool(volume, iso)),
    }
    results = time_tools({name: run for name, (_, run) in tools.items()}, args.runs)

    depth, height, width = volume.shape
    mvoxels = volume.size / 1e6
    reference = statistics.median(run.wall_s for run in results["mvox, in memory"])
    rows = []
    for name, runs in results.items():
        counts = {(run.polygons, run.vertices) for run in runs}
        if len(counts) != 1:
            raise RuntimeError(f"{dataset['name']}: {name} gave different counts: {counts}")
        polygons, vertices = counts.pop()
        wall = statistics.median(run.wall_s for run in runs)
        cpu_per_wall = statistics.median(run.cpu_s / run.wall_s for run in runs)
        first = not rows
        rows.append(
            f"| {dataset['name'] if first else ''}"
            f" | {f'{width}x{height}x{depth} {volume.dtype}' if first else ''}"
            f" | {name} | {tools[name][0]} | {wall * 1e3:.1f} | {mvoxels / wall:,.0f}"
            f" | {cpu_per_wall:.2f} | {polygons:,} | {vertices:,} | {wall / reference:.2f} |"
        )
    in_memory = results["mvox, in memory"][0]
    # The target's ratio per round, from runs close in time, so that the machine's slow swings
    # (other users' load) cancel; then the median over rounds.
    per_round = [
        peer.wall_s / mine.wall_s
        for peer, mine in zip(results["vtkFlyingEdges3D"], results["mvox, in memory"])
    ]
    return rows, (in_memory.vertices, in_memory.polygons), exact, per_round


def parse_arguments():
    parser = argparse.ArgumentParser(
        description="Time mvox, VTK and scikit-image side by side on the paper's datasets."
    )
    parser.add_argument("--runs", type=int, default=5, help="timed runs per tool (median)")
    parser.add_argument(
        "--mvox-build",
        default=os.path.join(CHECKOUT, "build"),
        help="mvox's build directory (default: build in the checkout)",
    )
    parser.add_argument(
        "--datasets",
        default=os.path.join(os.path.dirname(CHECKOUT), "shared", "datasets"),
        help="the datasets folder (default: ../shared/datasets beside the checkout)",
    )
    parser.add_argument(
        "--check-vertices",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="compare mvox's and VTK's vertex sets on 0/1 masks (default: on)",
    )
    args = parser.parse_args()
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    build = os.path.abspath(args.mvox_build)
    args.mvox = os.path.join(build, "src", "mvox")
    args.extract_once = os.path.join(build, "bench", "mvox_bench_extract_once")
    args.datasets = os.path.abspath(args.datasets)
    for program in (args.mvox, args.extract_once):
        if not os.access(program, os.X_OK):
            parser.error(f"{program} not found: build mvox and mvox_bench_extract_once first")
    return args


def check_vertices(dataset, volume, in_memory_counts, args, scratch):
    """The vertex-set check on `dataset`, plus one more line: mvox must find the same counts on
    the mask this script made as on the dataset's own files, or this script read the volume
    differently from mvox. Returns (ok, report lines)."""
    equal, lines, mask_counts = peer_vertex_check.check_dataset(
        dataset["name"], volume, dataset["threshold"], args.mvox, scratch
    )
    same_volume = mask_counts == in_memory_counts
    lines.append(
        f"  mvox on the dataset's files: {in_memory_counts[0]:,} vertices,"
        f" {in_memory_counts[1]:,} polygons; on the mask: "
        + (
            "the same, so this script read the volume as mvox does"
            if same_volume
            else "DIFFERENT: this script read another volume than mvox"
        )
    )
    return equal and same_volume, lines


def print_header(args, backend, threads):
    print(
        f"VTK {vtk.vtkVersion.GetVTKVersion()} (vtkSMPTools backend {backend}, {threads} thread;"
        " normals, gradients and scalars off), scikit-image"
        f" {skimage.__version__} (marching_cubes, method 'lewiner'), median of"
        f" {args.runs} interleaved rounds; in each round the in-memory tools run {kBackToBack}"
        " times back to back and the fastest counts. Times in ms; CPU/wall is the CPU time of the process"
        " over its wall time (1.00: one thread busy; less: the process waited for the CPU or"
        " the disk); the last column is each tool's time over mvox's in-memory time."
    )
    print()
    print(
        "| dataset | voxels | tool | threshold / iso value | ms | Mvoxel/s | CPU/wall"
        " | polygons | vertices | time / mvox in memory |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")


def print_notes(notes, elsewhere_s, start_s):
    print()
    print(
        "Vertex and polygon counts differ between mvox and the marching-cubes tools where the"
        " object touches the volume's border: mvox treats voxels outside the volume as outer and"
        " closes the surface there; the others leave it open. mvox's polygons have 3 to 7"
        " vertices, the others output triangles. *mvox, end to end* is a whole `mvox extract`"
        " process (start-up, reading, extracting, writing PLY), not comparable with in-memory"
        " extraction; it is there to show what a user waits for. Starting the process alone"
        f" (`mvox --help`) takes {start_s * 1e3:.0f} ms."
    )
    print()
    for note in notes:
        print(f"- {note}")
    print(
        f"- CPU time this script spent outside its main thread: {elsewhere_s:.3f} s"
        + (
            ": VTK and scikit-image ran on one thread."
            if elsewhere_s < kOtherThreadsCpuMaxS
            else ": NOT single-threaded, these figures are not valid."
        )
    )


def print_checks(checks, all_equal):
    print()
    print(
        "Vertex sets on 0/1 input (mvox extract on the mask written as a raw volume, -t 1;"
        " VTK on the mask with one layer of zeros around it, iso 0.5 or label 1; both put"
        " every vertex at an edge midpoint):"
    )
    print()
    print("```")
    print("\n".join(checks))
    print("```")
    print()
    print("Vertex sets: " + ("all EQUAL" if all_equal else "DIFFERENT"))


def print_target(speedups):
    """The issue's target: mvox's in-memory extraction at least 5x vtkFlyingEdges3D's speed,
    as the median over rounds of each round's ratio."""
    print(
        "\nTarget, mvox in memory at least 5x as fast as vtkFlyingEdges3D (one thread each;"
        " vtkFlyingEdges3D time / mvox time per round, median and range over rounds):"
    )
    for name, per_round in speedups:
        speedup = statistics.median(per_round)
        verdict = "met" if speedup >= 5 else "**not met**"
        print(f"- {name}: {speedup:.2f}x ({min(per_round):.1f} .. {max(per_round):.1f}), {verdict}")


def main():
    args = parse_arguments()
    print_header(args, *force_one_vtk_thread())
    notes, checks, all_equal, compared, speedups = [], [], True, 0, []
    with tempfile.TemporaryDirectory(prefix="compare_peers_") as scratch:
        for dataset in peers_io.list_datasets(args.extract_once, args.datasets):
            if not dataset["present"]:
                notes.append(f"{dataset['name']}: skipped, {dataset['inputs'][0]} not found")
                continue
            try:
                volume = peers_io.load_volume(dataset)
            except (OSError, ValueError) as error:
                notes.append(f"{dataset['name']}: skipped, {error}")
                continue
            rows, in_memory_counts, exact, speedup = compare_dataset(dataset, volume, args, scratch)
            print("\n".join(rows), flush=True)
            speedups.append((dataset["name"], speedup))
            compared += 1
            if not exact:
                notes.append(f"{dataset['name']}: not integer data; iso value = threshold")
            if args.check_vertices:
                ok, lines = check_vertices(dataset, volume, in_memory_counts, args, scratch)
                all_equal = all_equal and ok
                checks += lines
    elsewhere_s = other_threads_cpu_s()
    print_target(speedups)
    print_notes(notes, elsewhere_s, process_start_s(args.mvox, args.runs))
    if not compared:
        print(
            f"compare_peers.py: no dataset could be compared under {args.datasets}", file=sys.stderr
        )
        return 1
    if args.check_vertices:
        print_checks(checks, all_equal)
    return 0 if all_equal and elsewhere_s < kOtherThreadsCpuMaxS else 1


if __name__ == "__main__":
    sys.exit(main())
