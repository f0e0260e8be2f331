#!/usr/bin/env python3
"""The table of tools/device_pairs.sh's runs: per scene, every search stage and the search
step, each build's fastest and median time over its rounds (ms) and, where the profiles have
CPU times (Linux), the median share of the threads that were busy (CPU time over wall time
times threads: below 1 the threads waited), and each scene's results (exit status and
checksum: one line per distinct result).

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
    # (scene, stage) -> build -> busy share per round (where the profile has CPU times).
    busy = collections.defaultdict(lambda: collections.defaultdict(list))
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
        threads = max(profile.get("threads", 1), 1)
        step_cpu = 0.0
        for stage in profile["stages"]:
            if stage["phase"] == "search":
                key = (scene, stage["stage"])
                times[key][build].append(stage["seconds"])
                if "cpu" in stage and stage["seconds"] > 0:
                    busy[key][build].append(stage["cpu"] / (stage["seconds"] * threads))
                step_cpu += stage.get("cpu", 0.0)
        step = profile["phases"]["search"]
        times[(scene, "search step")][build].append(step)
        if step_cpu > 0 and step > 0:
            busy[(scene, "search step")][build].append(step_cpu / (step * threads))
    print("| scene | stage | " + " | ".join(f"{b} fastest (median)" for b in builds) + " |")
    print("|---|---|" + "---:|" * len(builds))
    for (scene, stage), per_build in sorted(times.items()):
        cells = []
        for b in builds:
            runs = per_build.get(b)
            shares = busy[(scene, stage)].get(b)
            share = f" busy {statistics.median(shares):.2f}" if shares else ""
            cells.append(
                f"{min(runs) * 1e3:.2f} ({statistics.median(runs) * 1e3:.2f}){share}"
                if runs
                else "–"
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
