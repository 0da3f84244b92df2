#!/usr/bin/env bash
# Runs one fuzz target briefly, as CI does: every seed of its corpus first, then mutations
# until SECONDS have passed. New inputs and any crash go to SCRATCH, never to the corpus.
# Usage: fuzz/run-smoke.sh TARGET SCRATCH CORPUS SECONDS
set -euo pipefail
target=$1 scratch=$2 corpus=$3 seconds=$4
dict=$(dirname "$0")/$(basename "$target").dict
rm -rf "$scratch"
mkdir -p "$scratch/new"
options=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
  -artifact_prefix="$scratch/")
[ -f "$dict" ] && options+=(-dict="$dict")
exec "$target" "${options[@]}" "$scratch/new" "$corpus"
