#!/bin/sh
# The 16-core sweeps of the twenty-third session, as run on the lent machine (one command):
# (A) the thread sweep of docs/performance.md's 16-core section, (B) mpirun on 1-16 ranks,
# docs/distributed.md "Measured". Prepared here: .dev2/ holds csm (release), csm-mpi (release,
# --features mpi), xtask (release), copies (release, examples/copies.rs; optional), setup.json
# (.devrun's: Parts_Slave/Parts_Master) and sphere_on_plate_2e5.mdpa.xz
# (tools/bench_scenes.py); .ompi/ is tools/ompi_bundle/make_bundle.sh's bundle; both carried. Writes $OUT/threads.tgz (render here with `cargo xtask scaling --runs
# DIR --label 16-core`) and $OUT/mpi.tgz (profiles, /usr/bin/time lines, logs). B=0 skips part B
# (then .ompi/ need not be carried); RA sets the runs per thread count (3), TA part A's limit (s).
set -u
D=.dev2; O=/tmp/runs; M=/tmp/mpi; S=/tmp/scenes
mkdir -p $O $M $S; cp $D/setup.json $O/
echo "== $(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo)"; free -g | head -2
$D/xtask scene stacked_blocks 1e5 $S/stacked_blocks_1e5.mdpa
xz -dc $D/sphere_on_plate_2e5.mdpa.xz > $S/sphere_on_plate_2e5.mdpa
echo "== A: threads $(date +%T)"
timeout ${TA:-200} sh tools/scaling_runs.sh $D/csm $O 1,2,4,8,16 ${RA:-3} \
  $S/stacked_blocks_1e5.mdpa $S/sphere_on_plate_2e5.mdpa demo:400000 2>&1 | tail -n 2
timeout 60 $D/xtask scaling --threads 1,2,4,8,16 --ceilings-into $O
# Each stage's ceiling (the table's "16 copies" column), where .dev2/ holds the release build of
# examples/copies.rs: rounds of one copy and of 16 alternating.
if [ -x $D/copies ]; then
  for mesh in stacked_blocks_1e5 sphere_on_plate_2e5; do
    mkdir -p $O/$mesh/copies
    for r in $(seq ${RA:-3}); do for k in 1 16; do
      timeout 60 $D/copies $S/$mesh.mdpa $O/setup.json $k $O/$mesh/copies/c${k}_r$r.json
    done; done
  done
fi
rm -f $S/stacked_blocks_1e5.mdpa $S/sphere_on_plate_2e5.mdpa
tar czf $OUT/threads.tgz -C /tmp runs
if [ "${B:-1}" = 0 ]; then echo "== done $(date +%T)"; exit 0; fi
echo "== B: ranks $(date +%T)"
. ./.ompi/env.sh
$D/xtask scene stacked_blocks 6e5 $S/strong.mdpa
run() { # name np threads binary mesh [mpirun]
  if [ "$6" = mpi ]; then pre="$MPIRUN -np $2 -x RAYON_NUM_THREADS=$3"; else pre=""; fi
  /usr/bin/time -f "%e %M" -o $M/$1.time timeout 120 $pre $4 search $5 --setup $D/setup.json \
    --threads $3 --quiet -o $M/$1.json --profile $M/$1.profile.json > $M/$1.log 2>&1
  echo "$1 rc=$? $(cat $M/$1.time | tail -1) $(sed '/"timings_s"/,/}/d' $M/$1.json | sha256sum | cut -c1-12)"
}
run strong_proc_t1 1 1 $D/csm $S/strong.mdpa no
run strong_proc_t16 1 16 $D/csm $S/strong.mdpa no
for np in 1 2 4 8 16; do run strong_np$np $np 1 $D/csm-mpi $S/strong.mdpa mpi; done
run strong_np4_t4 4 4 $D/csm-mpi $S/strong.mdpa mpi
rm -f $S/strong.mdpa
echo "== weak $(date +%T)"
for np in 1 2 4 8 16; do
  $D/xtask scene stacked_blocks $((62500 * np)) $S/weak.mdpa > /dev/null
  run weak_proc_t${np} 1 $np $D/csm $S/weak.mdpa no
  run weak_np$np $np 1 $D/csm-mpi $S/weak.mdpa mpi
done
(cd $M && tar czf $OUT/mpi.tgz *.profile.json *.time *.log)
echo "== done $(date +%T)"
