#!/usr/bin/env python3
"""Compares two `terralod bench --report` runs of the same flight frame by frame.

Streaming frames depend on when loads finish (threads), so two runs of one binary differ in
the frames that wait for chunks. The frames that are settled in both runs (none coarser than
wanted, none easing in) must show the same chunks, triangles, draws and eye: this is what
"the same selections" means for two builds.

    compare_frames.py A/frames.csv B/frames.csv     exit 1 when a settled frame differs
"""
import csv
import sys

KEYS = ("triangles", "draws", "chunks", "eye_x", "eye_y", "eye_z")


def load(path):
    with open(path, newline="") as f:
        return {int(r["frame"]): r for r in csv.DictReader(f)}


def settled(r):
    return r["coarser"] == "0" and r.get("easing", "0") == "0"


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, b = load(sys.argv[1]), load(sys.argv[2])
    both = [f for f in sorted(a) if f in b and settled(a[f]) and settled(b[f])]
    differing = [f for f in both if any(a[f][k] != b[f][k] for k in KEYS)]
    print(f"frames {len(a)} and {len(b)}; settled in both {len(both)}; "
          f"differing in {', '.join(KEYS)}: {len(differing)} {differing[:10]}")
    sys.exit(1 if differing or len(a) != len(b) else 0)


if __name__ == "__main__":
    main()
