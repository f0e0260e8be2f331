#!/bin/sh
# Paired runs of csm builds on a lent many-core machine (one command): the builds alternate,
# round after round, on the same scenes and thread count, so that a comparison does not depend
# on which host the machine is (one-thread times differ by up to 30 % between lent hosts).
#
#   tools/device_pairs.sh THREADS ROUNDS BUILD...
#
# Prepared here, as for tools/device_sweep.sh: .dev2/ holds each BUILD (a release `csm`,
# named as given), xtask (release, for the blocks scene), setup.json and
# sphere_on_plate_2e5.mdpa.xz; carry .dev2. Scenes: the blocks 1e5, the sphere 2e5 and
# `csm demo --faces 400000`. Writes $OUT/pairs.tgz: per build, scene and round the profile
# (`--profile`); per scene, each run's build, exit status and checksum of RESULT.json without
# its timings (every build and round must give one); builds.txt, the builds in the order
# given. Render here with `python3 tools/pairs_table.py DIR`.
set -u
: "${OUT:?set OUT to the folder that comes back}"
if [ $# -lt 3 ]; then
    echo "usage: $0 THREADS ROUNDS BUILD..." >&2
    exit 2
fi
threads=$1
rounds=$2
shift 2
D=.dev2; S=/tmp/scenes; P=/tmp/pairs
rm -rf $P
mkdir -p $S $P
echo "$@" > $P/builds.txt
echo "== $(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo)"
lscpu 2>/dev/null | grep -E '^(Thread|Core|Socket)' || true
$D/xtask scene stacked_blocks 1e5 $S/blocks.mdpa > /dev/null
xz -dc $D/sphere_on_plate_2e5.mdpa.xz > $S/sphere.mdpa
# The build, the exit status and the checksum of a result (none where it was not written).
note() {
    sum=$( [ -f "$3" ] && sed '/"timings_s"/,/}/d' "$3" | sha256sum | cut -c1-16 )
    echo "$1 rc=$2 ${sum:-none}"
}
for r in $(seq "$rounds"); do
    for b in "$@"; do
        rm -rf /tmp/demo_out
        timeout 60 $D/$b demo --faces 400000 --threads "$threads" --quiet -o /tmp/demo_out \
            --profile $P/${b}_demo_r$r.json > /dev/null 2>&1
        note "$b" $? /tmp/demo_out/RESULT.json >> $P/sums_demo.txt
        for sc in blocks sphere; do
            rm -f /tmp/$sc.json
            timeout 60 $D/$b search $S/$sc.mdpa --setup $D/setup.json --threads "$threads" \
                --quiet -o /tmp/$sc.json --profile $P/${b}_${sc}_r$r.json
            note "$b" $? /tmp/$sc.json >> $P/sums_$sc.txt
        done
    done
    echo "== round $r done $(date +%T)"
done
for f in $P/sums_*.txt; do
    echo "$(basename "$f" .txt): $(cut -d' ' -f2- "$f" | sort -u | tr '\n' ';')"
done
rm -f $S/blocks.mdpa $S/sphere.mdpa
tar czf "$OUT/pairs.tgz" -C /tmp pairs
