#!/usr/bin/env bash
# Staged builds on Slurm (issue 25), figures for docs/benchmarks.md "Builds on a cluster":
#  1. the 16385² synth, textured (the default) and untextured: the local build against the
#     same build in 16 block jobs on a single-node Slurm cluster on this machine
#     (scripts/slurm-local.sh): wall, peak RSS of the local build and of the largest job (as
#     each job measured itself: `build --verbose`), and whether the bytes are identical;
#  2. the 65537² synth, untextured, in 64 jobs: each stage's longest task, total task time and
#     peak RSS (textured, it would write about 48 GB of textures here).
#
#   bench/slurm_build.sh          scratch in $BENCH_DIR/slurm (default build/bench); about
#                                 25 minutes and 40 GB of disk on 2 cores
# ONLY="16385" or ONLY="65537" runs one part; RUNS=N times the 16385² builds N times each, in
# turn, and reports medians. Needs `make` first and slurm-wlm (install-deps).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
terralod=${TERRALOD:-$here/build/release/apps/terralod/terralod}
dir=${BENCH_DIR:-$here/build/bench}/slurm
mkdir -p "$dir"
cd "$dir"
want() { [ -z "${ONLY:-}" ] || [[ " $ONLY " == *" $1 "* ]]; }

cluster=$dir/cluster
"$here/scripts/slurm-local.sh" stop "$cluster" >/dev/null 2>&1 || true
eval "$("$here/scripts/slurm-local.sh" start "$cluster")"
# slurmctld's log (when each task was allocated and ended) is kept as $dir/slurmctld.log.
trap 'cp "$cluster/log/slurmctld.log" "$dir/slurmctld.log" 2>/dev/null
"$here/scripts/slurm-local.sh" stop "$cluster" >/dev/null 2>&1 || true' EXIT

# local NAME DEM ARGS...: one local build; prints wall seconds and peak RSS (MB).
local_build() {
  local name=$1 dem=$2
  shift 2
  /usr/bin/time -f "%e %M" -o time.txt "$terralod" build "$dem" -o "$name.tlod" "$@" >/dev/null
  read -r wall rss <time.txt
  echo "$wall $((rss / 1024))"
}

# staged NAME DEM JOBS ARGS...: the same on the cluster; prints wall seconds, then the stage
# figures (`build --verbose`) into NAME.stages.
staged_build() {
  local name=$1 dem=$2 jobs=$3
  shift 3
  rm -rf "$dir/work"
  /usr/bin/time -f "%e" -o time.txt "$terralod" build "$dem" -o "$name.tlod" "$@" \
    --scheduler slurm --work-dir "$dir/work" --jobs "$jobs" --verbose >"$name.stages"
  cat time.txt
}

if want 16385; then
  [ -e s16385.tif ] || "$terralod" synth --size 16385 --spacing 5 --seed 1 -o s16385.tif >/dev/null
  echo "| build | local wall s | local peak RSS MB | 16 jobs wall s | wall ratio | largest job RSS MB | RSS ratio | identical |"
  echo "|---|---|---|---|---|---|---|---|"
  # RUNS pairs (default 1), local and staged in turn; the row gives each figure's median and
  # the ratio of the medians (this machine's speed drifts by 20 % between runs).
  median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
  for variant in textured untextured; do
    args=()
    [ "$variant" = untextured ] && args=(--no-texture)
    : >pairs.txt
    for _ in $(seq "${RUNS:-1}"); do
      read -r lwall lrss < <(local_build "local_$variant" s16385.tif "${args[@]}")
      swall=$(staged_build "slurm_$variant" s16385.tif 16 "${args[@]}")
      jrss=$(awk '/peak RSS/ {v=$(NF-1); if (v > m) m = v} END {print m}' "slurm_$variant.stages")
      same=no
      cmp -s "local_$variant.tlod" "slurm_$variant.tlod" && same=yes
      echo "$lwall $lrss $swall $jrss $same" >>pairs.txt
    done
    lw=$(cut -d' ' -f1 pairs.txt | median) lr=$(cut -d' ' -f2 pairs.txt | median)
    sw=$(cut -d' ' -f3 pairs.txt | median) jr=$(cut -d' ' -f4 pairs.txt | median)
    same=yes
    grep -q ' no$' pairs.txt && same=no
    awk -v n="$variant" -v lw="$lw" -v lr="$lr" -v sw="$sw" -v jr="$jr" -v s="$same" \
      'BEGIN { printf "| %s | %.1f | %d | %.1f | %.2f | %.0f | %.3f | %s |\n", n, lw, lr, sw, sw / lw, jr, jr / lr, s }'
    [ "${RUNS:-1}" = 1 ] || sed 's/^/    run: local s, MB, staged s, largest job MB, identical: /' pairs.txt
    sed 's/^terralod: /    /' "slurm_$variant.stages"
    rm -f "local_$variant.tlod" "slurm_$variant.tlod" pairs.txt
  done
fi

if want 65537; then
  [ -e s65537.tif ] || "$terralod" synth --size 65537 --spacing 5 --seed 1 -o s65537.tif >/dev/null
  swall=$(staged_build slurm_65537 s65537.tif 64 --no-texture)
  echo "65537² untextured in 64 jobs: $swall s wall"
  sed 's/^terralod: /    /' slurm_65537.stages
  rm -f slurm_65537.tlod
fi
