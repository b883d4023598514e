#!/usr/bin/env bash
# Fuzzes mvox's parsers with libFuzzer: configures a clang build in build-fuzz (-DMVOX_FUZZ=ON),
# builds every target listed in fuzz/CMakeLists.txt, runs each for SECONDS_PER_TARGET (default
# 60) on a scratch copy of its seed corpus fuzz/corpus/NAME/ (the committed corpus never grows),
# and prints per target: runs executed, crashes, coverage. A crash, leak, timeout or
# out-of-memory input is kept under build-fuzz/artifacts/NAME/ and makes the script fail;
# reproduce it with: build-fuzz/fuzz/NAME build-fuzz/artifacts/NAME/crash-..., and keep it, once
# fixed, as fuzz/corpus/NAME/regression_WHAT (replayed first by every run).
#
#   scripts/install_fuzz_deps.sh   # once: clang and libFuzzer
#   scripts/fuzz.sh [SECONDS_PER_TARGET [TARGET...]]   # TARGETs: a subset, e.g. ply_reader_fuzzer
set -euo pipefail

seconds=${1:-60}
if ! [[ $seconds =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "usage: scripts/fuzz.sh [SECONDS_PER_TARGET [TARGET...]]" >&2
  exit 2
fi
repo=$(cd "$(dirname "$0")/.." && pwd)
build=$repo/build-fuzz
command -v clang++ > /dev/null || {
  echo "fuzz.sh: clang++ not found; run scripts/install_fuzz_deps.sh" >&2
  exit 1
}

mkdir -p "$build"
cmake -S "$repo" -B "$build" -DMVOX_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMVOX_BUILD_TESTS=OFF -DMVOX_BUILD_BENCH=OFF \
  -DMVOX_LIVE_WINDOW=OFF > "$build/configure.log" 2>&1 || {
  cat "$build/configure.log" >&2
  exit 1
}
mapfile -t targets < "$build/fuzz/fuzzers.txt"
if [ $# -gt 1 ]; then
  shift
  for wanted in "$@"; do
    printf '%s\n' "${targets[@]}" | grep -qx -- "$wanted" || {
      echo "fuzz.sh: no target $wanted; targets: ${targets[*]}" >&2
      exit 2
    }
  done
  targets=("$@")
fi
cmake --build "$build" -j2 --target "${targets[@]}"
# The seeds first, inputs that once crashed among them: a quick regression check.
seed_tests=$(printf 'fuzz_seeds\\.%s$|' "${targets[@]}")
ctest --test-dir "$build/fuzz" --output-on-failure -R "${seed_tests%|}"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
failed=0
printf '\n| target | seconds | runs | crashes | coverage (edges) | features | corpus |\n'
printf '|---|---|---|---|---|---|---|\n'
for target in "${targets[@]}"; do
  work=$scratch/$target
  mkdir -p "$work/corpus" "$work/artifacts"
  if [ -d "$repo/fuzz/corpus/$target" ]; then cp -r "$repo/fuzz/corpus/$target/." "$work/corpus/"; fi
  # Memory limits make a header that drives a large allocation a finding (out-of-memory), not a
  # slow success: no single allocation may exceed 256 MiB, nor the process 1 GiB.
  options=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=1024 -malloc_limit_mb=256
    -print_final_stats=1
    -artifact_prefix="$work/artifacts/")
  if [ -f "$repo/fuzz/$target.dict" ]; then options+=(-dict="$repo/fuzz/$target.dict"); fi
  status=0
  # The TIFF target decodes through the TIFF module, which the build puts in src/.
  MVOX_MODULE_PATH=$build/src "$build/fuzz/$target" "${options[@]}" "$work/corpus" \
    > "$work/log" 2>&1 || status=$?
  runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$work/log" | grep -o '[0-9]*$' || true)
  last=$(grep -E '^#[0-9]+' "$work/log" | tail -n 1 || true)
  coverage=$(grep -o 'cov: [0-9]*' <<< "$last" | grep -o '[0-9]*' || true)
  features=$(grep -o 'ft: [0-9]*' <<< "$last" | grep -o '[0-9]*' || true)
  corpus=$(grep -o 'corp: [0-9]*' <<< "$last" | grep -o '[0-9]*' || true)
  crashes=$(find "$work/artifacts" -type f | wc -l)
  if [ "$crashes" -gt 0 ] || [ "$status" -ne 0 ]; then
    failed=1
    mkdir -p "$build/artifacts/$target"
    cp "$work"/artifacts/* "$build/artifacts/$target/" 2> /dev/null || true
    cp "$work/log" "$build/artifacts/$target/log.txt"
    [ "$crashes" -gt 0 ] || crashes="exit $status"
  fi
  printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$target" "$seconds" "${runs:-?}" "$crashes" \
    "${coverage:-?}" "${features:-?}" "${corpus:-?}"
done
if [ "$failed" -ne 0 ]; then
  echo
  echo "fuzz.sh: failures; inputs and logs in $build/artifacts/" >&2
  exit 1
fi
