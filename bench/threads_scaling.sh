#!/usr/bin/env bash
# Slab-parallel scaling on this machine (docs/scaling.md): the paper's engine resampled to
# 256x256xDEPTH (default 1024), extracted
#   - in memory, by one engine and by 1..MAX_THREADS slab workers (mvox_bench_threads), and
#   - end to end, raw file to binary PLY (replacing the previous run's file, and written afresh)
#     and to STL, by `mvox extract --threads N` (hyperfine, one run of each command a round,
#     medians of the rounds and of their ratios);
# a PNG stack of the same size (mvox phantom blobs), where each worker decodes its own slabs;
# the picture (--image) drawn by 1..MAX_THREADS, alone and with a frame every 10 slices;
# slices of 1024x1024 and 2048x2048 (in memory, to PLY, peak memory); mvox-mpi on
# 1..MAX_RANKS (default 4) ranks, oversubscribed, when it is built; and the peak
# memory of each end-to-end run on the volume and on one 4x as deep, to show it is flat in
# depth. Prints Markdown.
#   bench/threads_scaling.sh BUILD_DIR [RUNS] [DEPTH] [MAX_THREADS] [DATASETS_DIR]
set -euo pipefail
build=$(realpath "$1")
runs=${2:-5}
depth=${3:-1024}
max_threads=${4:-2}
repo=$(cd "$(dirname "$0")/.." && pwd)
datasets=${5:-$repo/../shared/datasets}
engine=$datasets/engine/engine_256x256x128_uint8.raw
[ -f "$engine" ] || { echo "$0: $engine not found (the paper's engine dataset)" >&2; exit 2; }
mvox=$build/src/mvox
for program in "$mvox" "$build/bench/mvox_bench_threads" "$build/bench/mvox_bench_resample"; do
  [ -x "$program" ] || { echo "$0: $program not built" >&2; exit 2; }
done
command -v hyperfine > /dev/null || { echo "$0: hyperfine not installed (scripts/install_bench_deps.sh)" >&2; exit 2; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

deep=$((4 * depth))
"$build/bench/mvox_bench_resample" "$engine" 256x256x128 "$scratch/volume.raw" "256x256x$depth"
"$build/bench/mvox_bench_resample" "$engine" 256x256x128 "$scratch/deep.raw" "256x256x$deep"

# A Markdown table of interleaved rounds (hyperfine JSON files, one a round, each with one run
# of every command): NAMES in order, medians, and the median of the per-round ratios to the
# first, so that a slow moment of this shared machine slows every command of its round alike.
table() {
  python3 - "$@" <<'EOF'
import glob, json, statistics, sys
rounds = [json.load(open(f))["results"] for f in sorted(glob.glob(sys.argv[1] + ".round*.json"))]
names = sys.argv[2:]
print(f"| run | wall (median of {len(rounds)}) | vs --threads 1 (median of the rounds' ratios; range) |")
print("|---|---|---|")
for k, name in enumerate(names):
    times = [r[k]["times"][0] for r in rounds]
    ratios = [r[0]["times"][0] / r[k]["times"][0] for r in rounds]
    print(f"| {name} | {statistics.median(times) * 1e3:.0f} ms | "
          f"{statistics.median(ratios):.2f}x ({min(ratios):.2f}-{max(ratios):.2f}) |")
EOF
}

# The median of the numbers on standard input, one a line.
median() { sort -n | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }

echo "## In memory"
echo
"$build/bench/mvox_bench_threads" "$scratch/volume.raw" "256x256x$depth:u8" 100 "$max_threads" "$runs"
echo

# compare_runs NAME: RUNS interleaved rounds of the array `commands`, each round one hyperfine
# run of every command in order, after one warm-up round (a Markdown table of medians and
# ratios to the first), then checks that the files of the array `outputs` are all the first
# one, byte for byte. With `fresh=1`, each command's output is removed before each of its runs,
# outside the timing.
fresh=0
compare_runs() {
  local name=$1 output round
  local prepares=()
  if [ "$fresh" = 1 ]; then
    for output in "${outputs[@]}"; do prepares+=(--prepare "rm -f $output"); done
  fi
  hyperfine --style none --runs 1 "${prepares[@]}" "${commands[@]}" > /dev/null  # warm-up
  for round in $(seq -w "$runs"); do
    hyperfine --style none --runs 1 "${prepares[@]}" --export-json \
      "$scratch/$name.round$round.json" "${commands[@]}" > /dev/null
  done
  table "$scratch/$name" "${names[@]}"
  for output in "${outputs[@]:1}"; do
    cmp -s "${outputs[0]}" "$output" ||
      { echo "$0: $name: $output is not ${outputs[0]}" >&2; exit 1; }
  done
  echo
  echo "Every output above is the same file, byte for byte."
  echo
}

# thread_runs NAME INPUT OPTION EXTENSION [ahead]: `mvox extract INPUT -q OPTION FILE` (FILE:
# NAME-N.EXTENSION) with one thread and with 2..MAX_THREADS slab workers, and with "ahead" also
# with one engine and a reading thread (one slab).
thread_runs() {
  local name=$1 input=$2 option=$3 extension=$4 ahead=${5:-} threads
  commands=("$mvox extract $input -q $option $scratch/$name-1.$extension --threads 1")
  names=("--threads 1 (one thread)")
  outputs=("$scratch/$name-1.$extension")
  if [ "$ahead" = ahead ]; then
    commands+=("$mvox extract $input -q $option $scratch/$name-ahead.$extension --threads 2 --slab-slices $depth")
    names+=("one engine and a reading thread")
    outputs+=("$scratch/$name-ahead.$extension")
  fi
  for threads in $(seq 2 "$max_threads"); do
    commands+=("$mvox extract $input -q $option $scratch/$name-$threads.$extension --threads $threads")
    names+=("--threads $threads")
    outputs+=("$scratch/$name-$threads.$extension")
  done
  compare_runs "$name"
}

raw="$scratch/volume.raw --raw 256x256x$depth:u8 -t 100"

echo "## End to end: raw file to binary PLY"
echo
thread_runs raw "$raw" -o ply ahead

echo "## End to end: raw file to binary PLY, written afresh"
echo
echo "The same runs with each output removed before each run, outside the timing: above, every"
echo "run also pays for removing the file it replaces (the kernel frees its page cache then)."
echo
fresh=1
thread_runs fresh "$raw" -o ply
fresh=0

echo "## End to end: raw file to binary STL (each worker formats its slabs' triangles)"
echo
thread_runs stl "$raw" -o stl

echo "## End to end: PNG stack to binary PLY (each worker decodes its own slabs)"
echo
"$mvox" phantom blobs --size "256x256x$depth" -o "$scratch/stack" -q
thread_runs png "$scratch/stack -t 128" -o ply ahead

echo "## End to end: raw file to a picture (--image), each worker drawing a layer of its own"
echo
thread_runs picture "$raw" --image png

echo "## End to end: raw file to a picture and a frame every 10 slices (--frames)"
echo
echo "Each worker composites its layer into the picture when it has drawn a slab, and writes the"
echo "frames the slabs drawn so far complete. The frames of all runs go to one directory."
echo
thread_runs frames "$raw" "--every 10 --frames $scratch/frames --image" png

# Large slices, as micro-CT stacks have: the same engine resampled to 1024x1024x256 and
# 2048x2048x64 (256 MiB each). Slabs of 8 slices here emit about 5 and 40 MB, more than a
# worker's first four chunks hold: a worker ahead grows its chunks rather than wait
# (most_chunks_per_worker), and the peak memory shows what that takes.
echo "## Large slices: in memory, and raw file to binary PLY"
echo
for size in 1024x1024x256 2048x2048x64; do
  width=${size%%x*}
  slices=${size##*x}
  "$build/bench/mvox_bench_resample" "$engine" 256x256x128 "$scratch/large.raw" "$size"
  echo "### $size"
  echo
  "$build/bench/mvox_bench_threads" "$scratch/large.raw" "$size:u8" 100 "$max_threads" "$runs"
  echo
  thread_runs "large$width" "$scratch/large.raw --raw $size:u8 -t 100" -o ply
  echo "| run | peak memory (median of $runs) |"
  echo "|---|---|"
  for threads in $(seq 1 "$max_threads"); do
    for run in $(seq "$runs"); do
      /usr/bin/time -f "%M" -o "$scratch/rss" "$mvox" extract "$scratch/large.raw" \
        --raw "$size:u8" -t 100 -q -o "$scratch/m.ply" --threads "$threads"
      cat "$scratch/rss"
    done > "$scratch/rss_all"
    echo "| --threads $threads | $(median < "$scratch/rss_all" | awk '{printf "%.1f MiB", $1 / 1024}') |"
  done
  echo
  echo "($slices slices of ${width}x$width.)"
  echo
done
rm -f "$scratch/large.raw" "$scratch"/large*.ply

mpi=$build/src/mvox-mpi
if [ -x "$mpi" ] && command -v mpirun > /dev/null; then
  max_ranks=${MAX_RANKS:-4}
  echo "## MPI ranks (mpirun --oversubscribe on this machine): raw file to binary PLY"
  echo
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  input="$scratch/volume.raw --raw 256x256x$depth:u8 -t 100 -q"
  commands=("$mvox extract $input -o $scratch/alone.ply --threads 1")
  names=("mvox extract --threads 1")
  outputs=("$scratch/alone.ply")
  for ranks in $(seq 1 "$max_ranks"); do
    commands+=("mpirun --quiet --oversubscribe -np $ranks $mpi extract $input -o $scratch/ranks-$ranks.ply")
    names+=("mpirun -np $ranks mvox-mpi")
    outputs+=("$scratch/ranks-$ranks.ply")
  done
  compare_runs mpi
  echo "Inside the job (the --stats total: without starting the processes and MPI), medians of"
  echo "$runs:"
  echo
  echo "| run | job time |"
  echo "|---|---|"
  job_time() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["time_seconds"]["total"])' "$1"; }
  row() {
    local name=$1
    shift
    for run in $(seq "$runs"); do
      "$@" --stats "$scratch/s.json" > /dev/null
      job_time "$scratch/s.json"
    done > "$scratch/job_times"
    echo "| $name | $(median < "$scratch/job_times" | awk '{printf "%.0f ms", $1 * 1000}') |"
  }
  # shellcheck disable=SC2086
  row "mvox extract --threads 1" "$mvox" extract $input -o "$scratch/alone.ply" --threads 1
  for ranks in $(seq 1 "$max_ranks"); do
    # shellcheck disable=SC2086
    row "mpirun -np $ranks mvox-mpi" mpirun --quiet --oversubscribe -np "$ranks" "$mpi" extract $input -o "$scratch/ranks.ply"
  done
  echo
fi

echo "## Peak memory, flat in depth"
echo
echo "| run | 256x256x$depth | 256x256x$deep |"
echo "|---|---|---|"
for threads in $(seq 1 "$max_threads"); do
  row="| --threads $threads"
  for volume in "volume:$depth" "deep:$deep"; do
    name=${volume%%:*}
    for run in $(seq "$runs"); do
      /usr/bin/time -f "%M" -o "$scratch/rss" "$mvox" extract "$scratch/$name.raw" \
        --raw "256x256x${volume##*:}:u8" -t 100 -q -o "$scratch/m.ply" --threads "$threads"
      cat "$scratch/rss"
    done > "$scratch/rss_all"
    row+=" | $(median < "$scratch/rss_all" | awk '{printf "%.1f MiB", $1 / 1024}')"
  done
  echo "$row |"
done
