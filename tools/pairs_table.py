#!/usr/bin/env python3
"""The table of tools/device_pairs.sh's runs: per scene, every search stage and the search
step, each build's fastest and median time over its rounds (ms), and each scene's results
(exit status and checksum: one line per distinct result).

    python3 tools/pairs_table.py DIR      (DIR: the unpacked pairs/ folder)
"""
import collections
import glob
import json
import os
import statistics
import sys


def main(folder):
    # (scene, stage) -> build -> seconds per round.
    times = collections.defaultdict(lambda: collections.defaultdict(list))
    builds = []
    order = os.path.join(folder, "builds.txt")
    if os.path.exists(order):
        with open(order) as f:
            builds = f.read().split()
    skipped = []
    for path in sorted(glob.glob(os.path.join(folder, "*_r*.json"))):
        build, scene, _ = os.path.basename(path).rsplit("_", 2)
        try:
            with open(path) as f:
                profile = json.load(f)
        except (OSError, ValueError):
            # (A run cut short leaves no profile, or half of one.)
            skipped.append(os.path.basename(path))
            continue
        if build not in builds:
            builds.append(build)
        for stage in profile["stages"]:
            if stage["phase"] == "search":
                times[(scene, stage["stage"])][build].append(stage["seconds"])
        times[(scene, "search step")][build].append(profile["phases"]["search"])
    print("| scene | stage | " + " | ".join(f"{b} fastest (median)" for b in builds) + " |")
    print("|---|---|" + "---:|" * len(builds))
    for (scene, stage), per_build in sorted(times.items()):
        cells = []
        for b in builds:
            runs = per_build.get(b)
            cells.append(
                f"{min(runs) * 1e3:.2f} ({statistics.median(runs) * 1e3:.2f})" if runs else "–"
            )
        print(f"| {scene} | {stage} | " + " | ".join(cells) + " |")
    for path in sorted(glob.glob(os.path.join(folder, "sums_*.txt"))):
        with open(path) as f:
            results = sorted({" ".join(line.split()[1:]) for line in f if line.strip()})
        print(f"\n{os.path.basename(path)}: {len(results)} distinct result(s): {results}")
    if skipped:
        print(f"\nno profile read: {', '.join(skipped)}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
