#!/usr/bin/env bash
# The fuzzing campaign: runs fuzz targets (the `fuzz` preset's build) one after another for
# SECONDS each, each on its own persistent corpus ($FUZZ_DIR/<target>, seeded from
# fuzz/corpus/<target>), and appends one line per run to $FUZZ_DIR/runs.tsv: date, target,
# seconds, executions, and "clean", "interrupted" (SIGINT) or the crash file. Totals per target:
# `bench/fuzz.sh --totals`. Runs under nice; any crash stops that target's run and is kept in
# $FUZZ_DIR/<target>-crashes.
#
#   bench/fuzz.sh [SECONDS] [TARGET...]     defaults: 3600, every target
#   bench/fuzz.sh --totals
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${FUZZ_BUILD:-$here/build/fuzz}
dir=${FUZZ_DIR:-$here/build/fuzz-campaign}
mkdir -p "$dir"
if [ "${1:-}" = "--totals" ]; then
  awk -F'\t' '{ runs[$2]++; secs[$2] += $3; execs[$2] += $4; if ($5 != "clean" && $5 != "interrupted") crashes[$2]++ }
    END { printf "%-24s %5s %9s %14s %8s\n", "target", "runs", "seconds", "executions", "crashes";
          for (t in runs) printf "%-24s %5d %9d %14d %8d\n", t, runs[t], secs[t], execs[t], crashes[t] }' \
    "$dir/runs.tsv"
  exit 0
fi
seconds=${1:-3600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] ||
  targets=(tileset_reader_fuzzer chunk_codec_fuzzer texture_codec_fuzzer flight_json_fuzzer dem_reader_fuzzer)
[ -x "$build/fuzz/${targets[0]}" ] || { echo "fuzz.sh: build first: cmake --preset fuzz && cmake --build --preset fuzz" >&2; exit 1; }
for target in "${targets[@]}"; do
  corpus=$dir/$target crashes=$dir/$target-crashes log=$dir/$target.log
  mkdir -p "$corpus" "$crashes"
  options=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
    -artifact_prefix="$crashes/")
  [ -f "$here/fuzz/$target.dict" ] && options+=(-dict="$here/fuzz/$target.dict")
  echo "fuzz.sh: $target for $seconds s (log $log)"
  start=$(date +%s)
  status=0
  nice -n 10 "$build/fuzz/$target" "${options[@]}" "$corpus" "$here/fuzz/corpus/$target" \
    >"$log" 2>&1 || status=$?
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  if [ -z "$executions" ]; then  # a crash ends the run before the final stats
    executions=$(grep -o '^#[0-9]*' "$log" | tail -1 | tr -d '#')
  fi
  result=clean
  if [ "$status" -ne 0 ]; then
    result=$(grep -o 'Test unit written to .*' "$log" | tail -1 | sed 's/Test unit written to //' || true)
    grep -q 'run interrupted' "$log" && result=interrupted
    result=${result:-"exit $status"}
  fi
  printf '%s\t%s\t%s\t%s\t%s\n' "$(date -u +%FT%TZ)" "$target" "$(($(date +%s) - start))" \
    "${executions:-0}" "$result" >>"$dir/runs.tsv"
  echo "fuzz.sh: $target: ${executions:-0} executions, $result"
done
