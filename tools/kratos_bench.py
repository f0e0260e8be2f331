#!/usr/bin/env python3
"""One Kratos 10.4.4 search step on a mesh, timed stage by stage (run by `cargo xtask bench`).

    OMP_NUM_THREADS=1 python tools/kratos_bench.py MESH.mdpa SETUP.json OUT.json

Drives ALMContactProcess exactly as tools/kratos_fixtures_search.py does (model part
"Structure" with the ALM nodal variables, ModelPartIO, DOMAIN_SIZE 3, STEP 1, TIME 1,
DELTA_TIME 1), and writes

  {"kratos": "<version>", "pairs": {"0": {"<slave id>": [masters ascending]}},
   "timings_s": {"import": s, "read": s, "initialize": s, "search": s}}

`search` is ExecuteInitializeSolutionStep alone — the figure csm's `timings_s.search` is compared
with; `initialize` is ExecuteInitialize; `read` is ModelPartIO; `import` is loading Kratos. The
whole-process wall time and the peak memory are measured outside (`/usr/bin/time -v`).
"""
import json
import os
import sys
import time

T_START = time.perf_counter()
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import kratos_fixtures_search as kfs  # noqa: E402  (imports Kratos, one thread)

KM = kfs.KM


def main():
    mesh, setup_path, out = sys.argv[1:4]
    t_import = time.perf_counter() - T_START
    with open(setup_path) as f:
        setup = json.load(f)
    t0 = time.perf_counter()
    model = KM.Model()
    mp = model.CreateModelPart("Structure", 2)
    for var in kfs.ALM_VARIABLES:
        mp.AddNodalSolutionStepVariable(var)
    KM.ModelPartIO(os.path.abspath(mesh)[:-len(".mdpa")]).ReadModelPart(mp)
    t1 = time.perf_counter()
    mp.ProcessInfo[KM.DOMAIN_SIZE] = 3
    mp.ProcessInfo[KM.STEP] = 1
    mp.ProcessInfo[KM.TIME] = 1.0
    mp.ProcessInfo[KM.DELTA_TIME] = 1.0
    kratos_setup = {k: v for k, v in setup.items() if k not in kfs.CSM_KEYS}
    process = kfs.HarnessALMContactProcess(model, KM.Parameters(json.dumps(kratos_setup)))
    t2 = time.perf_counter()
    process.ExecuteInitialize()
    t3 = time.perf_counter()
    process.ExecuteInitializeSolutionStep()
    t4 = time.perf_counter()
    with kfs.CapturedLog() as log:
        process.search_utility_list["0"].CheckMortarConditions()
    maps = kfs.parse_index_maps(log.text)
    sub = mp.GetSubModelPart("Contact").GetSubModelPart("ContactSub0")
    slaves = sorted(c.Id for c in sub.Conditions if c.Is(KM.SLAVE))
    result = {
        "kratos": kfs.VERSION,
        "pairs": {"0": {str(s): maps.get(s, []) for s in slaves}},
        "timings_s": {"import": t_import, "read": t1 - t0, "initialize": t3 - t2,
                      "search": t4 - t3},
    }
    with open(out, "w") as f:
        json.dump(result, f)


if __name__ == "__main__":
    main()
