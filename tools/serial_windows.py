#!/usr/bin/env python3
"""Where a multi-threaded run is serial: the samples of `perf script` in the time windows in
which only one thread of the process ran, attributed to csm's functions.

A speed-up table (`cargo xtask scaling`) says how much of a stage did not get faster, not
why. This script finds the one-thread stretches themselves. Record with frame pointers (the
call chains then reach csm's own frames), then run it on the script output:

    RUSTFLAGS="-C force-frame-pointers=yes" CARGO_TARGET_DIR=/tmp/fp \\
        cargo build --release --bin csm
    perf record -F 4999 -g -o run.data /tmp/fp/release/csm search MESH --threads 2 ...
    perf script -i run.data -F tid,time,ip,sym > run.txt
    tools/serial_windows.py run.txt [--window 0.001] [--depth 2] [--top 40]

Each sample falls in a window of `--window` seconds; a window in which samples of one thread
only were taken counts as serial (with 2 threads at 5 kHz a window of 1 ms holds about 5
samples per running thread). A sample is named by the innermost csm function of its call
chain (with `--depth` callers), or by its innermost frame where no csm frame is found
(kernel work, the C library, rayon's workers whose closures were inlined). The columns:
samples in serial windows, samples in parallel ones, the name. At `-F 4999` a sample is
about 0.2 ms of one thread.
"""

import argparse
import collections
import re
import sys

HEADER = re.compile(r"^\s*(\d+)\s+(\d+\.\d+):\s*$")
IMPL = re.compile(r"<impl [^>]*>::")


def samples(lines):
    """(tid, time, [symbol, ...] innermost first) for every sample of `perf script`."""
    current = None
    for line in lines:
        if not line.strip():
            if current:
                yield current
            current = None
            continue
        m = HEADER.match(line)
        if m:
            current = (int(m.group(1)), float(m.group(2)), [])
        elif current is not None and line.startswith("\t"):
            parts = line.strip().split(None, 1)
            current[2].append(parts[1] if len(parts) > 1 else "?")
    if current:
        yield current


def name(stack, depth):
    """The innermost csm functions of a call chain (`depth` of them), or its innermost frame."""
    own = []
    for symbol in stack:
        if "csm_" in symbol or symbol.startswith("csm::"):
            symbol = IMPL.sub("", symbol.replace("::{{closure}}", ""))
            if not own or own[-1] != symbol:
                own.append(symbol)
    if not own:
        return "(no csm frame) " + (stack[0] if stack else "?")
    return " <- ".join(own[:depth])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("script", help="the output of `perf script -F tid,time,ip,sym`")
    parser.add_argument("--window", type=float, default=0.001, help="seconds per window")
    parser.add_argument("--depth", type=int, default=2, help="csm callers named per sample")
    parser.add_argument("--top", type=int, default=40, help="rows printed")
    args = parser.parse_args()
    try:
        with open(args.script, encoding="utf-8", errors="replace") as f:
            all_samples = list(samples(f))
    except OSError as e:
        sys.exit(f"{args.script}: {e.strerror}")
    if not all_samples:
        sys.exit(f"{args.script}: no samples (was it written by `perf script`?)")
    start = min(t for _, t, _ in all_samples)
    threads_in = collections.defaultdict(set)
    for tid, t, _ in all_samples:
        threads_in[int((t - start) / args.window)].add(tid)
    serial = collections.Counter()
    parallel = collections.Counter()
    for tid, t, stack in all_samples:
        window = int((t - start) / args.window)
        counter = serial if len(threads_in[window]) == 1 else parallel
        counter[name(stack, args.depth)] += 1
    windows = max(threads_in) + 1
    one = sum(1 for w in threads_in.values() if len(w) == 1)
    print(
        f"{len(all_samples)} samples, {len({s[0] for s in all_samples})} threads; "
        f"{sum(serial.values())} in serial windows ({one} of {windows} windows of "
        f"{args.window * 1e3:g} ms)"
    )
    print(f"{'serial':>7} {'parallel':>8}  function")
    for key, count in serial.most_common(args.top):
        print(f"{count:7d} {parallel[key]:8d}  {key}")


if __name__ == "__main__":
    main()
