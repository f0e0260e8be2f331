#!/bin/sh
# The runs of the thread sweep (`cargo xtask scaling`), with a csm binary and meshes already
# there: for a machine without a Rust toolchain (a lent many-core machine), where only this
# script, the binary and the meshes are carried. `cargo xtask scaling --runs OUT` renders the
# table from OUT afterwards, on any machine.
#
#   tools/scaling_runs.sh CSM OUT THREADS REPEAT MESH...
#
# Paths must not hold spaces. CSM: the release binary; OUT: the folder to write into; THREADS: thread counts,
# comma-separated (1,2,4,8,16); REPEAT: runs per thread count; MESH: .mdpa, .msh or their
# .gz / .xz (unpacked once into OUT), or `demo:FACES` for `csm demo --faces FACES` (the
# embedded scene, built in the phase `read`; its sampled ground truth is the phase `truth`,
# its demo.vtu is written too). For every mesh, round after round, every thread count:
# `csm search MESH --threads N --profile`, timed by the shell's clock (to a tenth of a
# millisecond), under /usr/bin/time for its peak memory where it is there, into
# OUT/<mesh name>/t<N>_r<round>.{profile.json,time.txt,result.sha256} (the checksum of
# RESULT.json without its timings: the renderer checks that they all agree).
# OUT/machine.txt names the machine. The setup is csm's default for parts named slave and
# master, with the benchmark's setup when OUT/setup.json exists (the xtask writes it).
set -eu

if [ $# -lt 5 ]; then
    echo "usage: $0 CSM OUT THREADS REPEAT MESH..." >&2
    exit 2
fi
csm=$1
out=$2
threads=$(echo "$3" | tr ',' ' ')
repeat=$4
shift 4
mkdir -p "$out"
{
    grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //' || echo "unknown CPU"
    echo "$(nproc 2>/dev/null || echo '?') cores available"
} | paste -sd ',' - | sed 's/,/, /' > "$out/machine.txt"
setup=""
if [ -f "$out/setup.json" ]; then
    setup="--setup $out/setup.json"
fi

for mesh in "$@"; do
    name=$(basename "$mesh")
    demo=""
    case "$name" in
        demo:*) demo=${name#demo:}; name="demo_$demo.scene" ;;
        *.gz) name=${name%.gz}; unpacked="$out/$name"; [ -f "$unpacked" ] || gzip -dc "$mesh" > "$unpacked"; mesh=$unpacked ;;
        *.xz) name=${name%.xz}; unpacked="$out/$name"; [ -f "$unpacked" ] || xz -dc "$mesh" > "$unpacked"; mesh=$unpacked ;;
    esac
    dir="$out/${name%.*}"
    mkdir -p "$dir"
    round=1
    while [ "$round" -le "$repeat" ]; do
        for t in $threads; do
            base="$dir/t${t}_r${round}"
            if [ -n "$demo" ]; then
                run="demo --faces $demo -o $dir/demo"
                result="$dir/demo/RESULT.json"
            else
                run="search $mesh $setup -o $dir/result.json"
                result="$dir/result.json"
            fi
            if [ -x /usr/bin/time ]; then
                # The wall time from the shell's clock (nanoseconds; /usr/bin/time's own
                # counts hundredths, 2.5 % of a 0.4 s run), the peak memory from time's.
                start=$(date +%s.%N)
                # shellcheck disable=SC2086
                /usr/bin/time -f "%M" -o "$base.rss.txt" \
                    "$csm" $run --threads "$t" --quiet --profile "$base.profile.json"
                end=$(date +%s.%N)
                awk -v a="$start" -v b="$end" -v m="$(tail -n 1 "$base.rss.txt")" \
                    'BEGIN { printf "%.4f %s\n", b - a, m }' > "$base.time.txt"
                rm -f "$base.rss.txt"
            else
                start=$(date +%s.%N)
                # shellcheck disable=SC2086
                "$csm" $run --threads "$t" --quiet --profile "$base.profile.json"
                end=$(date +%s.%N)
                awk -v a="$start" -v b="$end" 'BEGIN { print b - a, 0 }' > "$base.time.txt"
            fi
            sed '/"timings_s"/,/}/d' "$result" | sha256sum | cut -d' ' -f1 \
                > "$base.result.sha256"
            echo "scaling: $name $t threads, round $round: $(cut -d' ' -f1 "$base.time.txt") s" >&2
        done
        round=$((round + 1))
    done
    rm -rf "$dir/result.json" "$dir/demo"
done
