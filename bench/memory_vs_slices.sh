#!/usr/bin/env bash
# Peak memory of `mvox extract` on a short and a tall stack of the same slice size: memory must
# not grow with the number of slices. Writes random-blob phantom stacks (256x256x100 and
# 256x256x2000 by default) into a scratch directory, runs each extraction RUNS times interleaved,
# and prints a Markdown table of the medians: the process's peak resident memory (from
# /usr/bin/time) and the job's own share (peak minus the resident size at start, from --stats).
#   bench/memory_vs_slices.sh MVOX_BINARY [RUNS] [SIZE] [SHORT_DEPTH] [TALL_DEPTH]
set -euo pipefail
mvox=$1
runs=${2:-3}
size=${3:-256}
short=${4:-100}
tall=${5:-2000}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

"$mvox" phantom blobs --size "${size}x${size}x${short}" -o "$scratch/short" -q
"$mvox" phantom blobs --size "${size}x${size}x${tall}" -o "$scratch/tall" -q

# The number after "KEY": in mvox's --stats JSON (one key per line).
json_number() { sed -n "s/^ *\"$1\": \([0-9.]*\).*/\1/p" "$2"; }
median() { sort -n | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }
for run in $(seq "$runs"); do
  for stack in short tall; do
    /usr/bin/time -f "%M" -o "$scratch/rss" "$mvox" extract "$scratch/$stack" -t 128 \
      -o "$scratch/$stack.ply" --stats "$scratch/$stack.json" -q
    echo "$(cat "$scratch/rss")" >> "$scratch/$stack.rss_kib"
    json_number job_memory_bytes "$scratch/$stack.json" >> "$scratch/$stack.job_bytes"
  done
done

echo "| stack | slices | polygons | peak resident memory (median of $runs) | the job's own share |"
echo "|---|---|---|---|---|"
for stack in short tall; do
  depth=$([ "$stack" = short ] && echo "$short" || echo "$tall")
  polygons=$(json_number polygons "$scratch/$stack.json")
  rss=$(median < "$scratch/$stack.rss_kib")
  job=$(median < "$scratch/$stack.job_bytes")
  awk -v s="$size" -v d="$depth" -v p="$polygons" -v r="$rss" -v j="$job" \
    'BEGIN { printf "| %sx%sx%s | %s | %s | %.1f MiB | %.2f MiB |\n", s, s, d, d, p, r / 1024, j / 1048576 }'
  eval "${stack}_rss=$rss"
done
awk -v t="$tall_rss" -v s="$short_rss" 'BEGIN { printf "\nTall/short peak memory: %.3f\n", t / s }'
