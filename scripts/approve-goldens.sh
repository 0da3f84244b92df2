#!/usr/bin/env bash
# Approves golden images: copies every <name>.actual.png that a failed (or first) golden test
# wrote into tests/golden/expected/<name>.png. Look at each .actual.png and .diff.png first.
# Usage: scripts/approve-goldens.sh [DIR]
#   DIR defaults to $TERRALOD_GOLDEN_OUT, else build/$PRESET/golden-out (PRESET: release).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-${TERRALOD_GOLDEN_OUT:-$root/build/${PRESET:-release}/golden-out}}
if [ ! -d "$dir" ]; then
  echo "approve-goldens: $dir is not a directory (run the render tests first)" >&2
  exit 1
fi
expected="$root/tests/golden/expected"
mkdir -p "$expected"
shopt -s nullglob
count=0
for actual in "$dir"/*.actual.png; do
  name=$(basename "$actual" .actual.png)
  cp "$actual" "$expected/$name.png"
  echo "approved $name: $actual -> tests/golden/expected/$name.png"
  count=$((count + 1))
done
[ "$count" -gt 0 ] || echo "approve-goldens: nothing to approve in $dir"
