#!/usr/bin/python3
"""Two builds of the Python module side by side: mvox.extract on one of the paper's datasets,
each build in processes of its own, alternating, so that a slow moment of this shared machine
slows both alike. For changes on mvox.extract's path that must be measured within a few percent.

    /usr/bin/python3 bench/module_ab.py BEFORE_DIR AFTER_DIR [--dataset engine] [--rounds 8]
        [--calls 15] [--datasets DIR] [--extract-once PATH]

BEFORE_DIR and AFTER_DIR each hold a built module (mvox.cpython-*.so, say copied from
build/python before and after a change). Each round starts one process per build, in turn
(the order alternates from round to round); a process loads the dataset (bench/peers_io.py),
calls mvox.extract 10 times untimed, then takes the fastest of 3 calls, `--calls` times, and
reports their median. Prints each build's median over rounds and the median (and range) of
the per-round ratios BEFORE / AFTER: above 1, the second build is faster.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

import peers_io

# What one process runs: argv = module directory, bench directory, dataset (JSON), calls.
ONE_PROCESS = r"""
import json, statistics, sys, time
sys.path.insert(0, sys.argv[1])
sys.path.insert(0, sys.argv[2])
import mvox, peers_io
dataset = json.loads(sys.argv[3])
volume = peers_io.load_volume(dataset)
threshold = dataset["threshold"]
for _ in range(10):
    mvox.extract(volume, threshold)
best = []
for _ in range(int(sys.argv[4])):
    fastest = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        mvox.extract(volume, threshold)
        fastest = min(fastest, time.perf_counter() - start)
    best.append(fastest)
print(json.dumps({"ms": statistics.median(best) * 1e3, "module": mvox.__file__}))
"""


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(here)
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--dataset", default="engine")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--calls", type=int, default=15)
    parser.add_argument("--datasets", default=os.path.join(repo, "..", "shared", "datasets"))
    parser.add_argument("--extract-once",
                        default=os.path.join(repo, "build", "bench", "mvox_bench_extract_once"))
    args = parser.parse_args()
    datasets = {d["name"]: d for d in peers_io.list_datasets(args.extract_once, args.datasets)}
    dataset = datasets.get(args.dataset)
    if dataset is None or not dataset["present"]:
        sys.exit(f"{sys.argv[0]}: dataset {args.dataset!r} not found under {args.datasets}")
    builds = [os.path.abspath(args.before), os.path.abspath(args.after)]
    times = {build: [] for build in builds}
    for round_number in range(args.rounds):
        for build in builds if round_number % 2 == 0 else builds[::-1]:
            run = subprocess.run(
                [sys.executable, "-c", ONE_PROCESS, build, here, json.dumps(dataset),
                 str(args.calls)],
                capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"{sys.argv[0]}: the process for {build} failed:\n{run.stderr}")
            result = json.loads(run.stdout)
            if os.path.dirname(result["module"]) != build:
                sys.exit(f"{sys.argv[0]}: {build}: imported {result['module']} instead")
            times[build].append(result["ms"])
    ratios = [b / a for b, a in zip(times[builds[0]], times[builds[1]])]
    print(f"mvox.extract on {args.dataset}, {args.rounds} alternating rounds, "
          f"each the median of {args.calls} fastest-of-3 calls in one process:")
    for label, build in zip(("before", "after"), builds):
        print(f"  {label}: {statistics.median(times[build]):.3f} ms  ({build})")
    print(f"  before / after: {statistics.median(ratios):.3f} "
          f"(range {min(ratios):.3f}-{max(ratios):.3f})")


if __name__ == "__main__":
    main()
