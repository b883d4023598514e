#!/usr/bin/env bash
# Are the mesh writers as fast as the disk? For each format, `mvox extract` of one volume is
# run RUNS times, interleaved with copying a file of the same size (cp: reading it from the page
# cache and writing it, what any writer of that file must at least do), and with reading the
# input (cat). Prints a Markdown table of medians: the writer's time as --stats reports it (the
# time spent in the mesh sink and in finishing the file) in a `--threads 1` run, where one
# thread does everything, the copy's, their ratio, and the wall time of a run with the default
# threads (slab workers from 64 MiB of samples, which share the writing) against reading the
# input plus copying the output.
#   bench/writer_speed.sh MVOX VOLUME.raw WxHxD THRESHOLD [RUNS] [SCRATCH_DIR]
# For the 1024^3 figures in docs/benchmarks.md:
#   build/bench/mvox_bench_resample ../shared/datasets/engine/engine_256x256x128_uint8.raw \
#       256x256x128 /tmp/engine1024.raw 1024x1024x1024
#   bench/writer_speed.sh build/src/mvox /tmp/engine1024.raw 1024x1024x1024 100 5
set -euo pipefail
mvox=$(realpath "$1")
volume=$(realpath "$2")
size=$3
threshold=$4
runs=${5:-5}
scratch=$(mktemp -d "${6:-${TMPDIR:-/tmp}}/mvox-writer-speed.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"

median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
seconds() {  # seconds COMMAND...: wall seconds of one run
  local start end
  start=$(date +%s.%N)
  "$@"
  end=$(date +%s.%N)
  echo "$end - $start" | bc -l
}

echo "| format | file | writer (--stats write, --threads 1) | cp of the file | writer / cp | whole run | cat input + cp output | run / (cat + cp) |"
echo "|---|---|---|---|---|---|---|---|"
for format in ply stl obj ply-ascii; do
  extension=${format%%-*}
  : > writer.txt; : > copy.txt; : > run.txt; : > input.txt
  for _ in $(seq "$runs"); do
    rm -f "mesh.$extension" copy
    # Every timed command starts after sync (not timed): one run's dirty pages must not throttle
    # the next run's writes (cp's time swung from 0.3 to 1.8 s without it).
    sync
    "$mvox" extract "$volume" --raw "$size:u8" -t "$threshold" -o "mesh.$extension" \
      --format "$format" --stats stats.json -q --threads 1
    rm -f "mesh.$extension"
    sync
    seconds "$mvox" extract "$volume" --raw "$size:u8" -t "$threshold" -o "mesh.$extension" \
      --format "$format" -q >> run.txt
    python3 -c 'import json; print(json.load(open("stats.json"))["time_seconds"]["write"])' \
      >> writer.txt
    sync
    seconds cp "mesh.$extension" copy >> copy.txt
    sync
    seconds sh -c "cat '$volume' > /dev/null" >> input.txt
  done
  bytes=$(stat -c %s "mesh.$extension")
  writer=$(median < writer.txt)
  copy=$(median < copy.txt)
  run=$(median < run.txt)
  input=$(median < input.txt)
  printf '| %s | %s MB | %.3f s | %.3f s | %.2f | %.3f s | %.3f s | %.2f |\n' "$format" \
    "$((bytes / 1000000))" "$writer" "$copy" "$(echo "$writer / $copy" | bc -l)" "$run" \
    "$(echo "$input + $copy" | bc -l)" "$(echo "$run / ($input + $copy)" | bc -l)"
  rm -f "mesh.$extension" copy
done
echo
echo "Medians of $runs runs; $(basename "$volume") ($size u8, threshold $threshold); files in"
echo "$(df -T "$scratch" | awk 'NR == 2 { print $2 }') on $(nproc) cores, $(date -u +%Y-%m-%d)."
