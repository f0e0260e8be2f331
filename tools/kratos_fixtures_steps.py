"""Multi-step and dynamic-search reference fixtures from Kratos 10.4.4 (run by `cargo xtask fixtures`).

Writes tests/fixtures/steps/<case>.json in csm's RESULT.json format (`csm-result/1`, DESIGN.md §3)
plus `mesh`, `setup` (the SETUP.json given to csm) and `kratos`, and tests/fixtures/steps/README.md.
Kratos runs with one thread.

1. `dynamic_search_{triangle,quadrilateral}`: Kratos' own test_dynamic_search.py (reference §20.2)
   on test_double_curvature_integration_{triangle,quadrilateral}.mdpa, set up exactly as the test
   does: model part "Structure" (buffer 2) with its nodal variables, CloneTimeStep(1.01) before
   reading, DoFs (none fixed), SLAVE/MASTER on the nodes, ACCELERATION_X = -9.81 at buffer index 1 on
   the slave nodes, STEP 1, DELTA_TIME 0.5, ACTIVE_CHECK_FACTOR 0.3, INTEGRATION_ORDER_CONTACT 3,
   INTERFACE on the nodes of DISPLACEMENT_Displacement_Auto2, GenerateInterfacePart on that part,
   its conditions and nodes copied into "Contact", FindNodalHProcess on that part (it has no
   elements: NODAL_H stays DBL_MAX), ALMFastInit, then the C++ search process built directly with
   {"dynamic_search": true, "simple_search": false, "normal_orientation_threshold": 0.0} (the
   wrapper's defaults for the rest: InRadius, MappingCheck, no condition_name, so no paired
   conditions) and its ExecuteInitialize + ExecuteInitializeSolutionStep. The concrete class the
   wrapper would choose is built instead of the wrapper so that CheckMortarConditions() can print
   the INDEX_MAPs (as in tools/kratos_fixtures_search.py). Recorded: the INDEX_MAPs of the slave
   conditions, NORMAL_GAP and ACTIVE of the slave nodes (= the nodes of Parts_Parts_Auto1, the
   test's checked part), the paired-condition count. csm gets the same through the SETUP.json keys
   `cpp_search_parameters`, `nodal_h` (DBL_MAX), `process_info` and `nodal_values` (the
   acceleration at buffer index 1).

2. `<scene>__<case>`: multi-step runs of ALMContactProcess (the Python path of
   tools/kratos_fixtures_search.py) on own scenes of tests/data/scenes/, driven as Kratos' analysis
   stage drives its processes: ProcessInfo DOMAIN_SIZE, STEP 1, TIME 1, DELTA_TIME dt_1;
   ExecuteInitialize; then for every step k: (k > 1: STEP += 1 and CloneTimeStep(TIME + dt_k));
   DELTA_TIME := dt_k; the SETUP.json `steps[k]` rigid increment of each named part applied to its
   nodes (current coordinates, DISPLACEMENT += increment, VELOCITY := increment / dt, ACCELERATION
   := (VELOCITY - VELOCITY at buffer index 1) / dt; every other node gets a zero increment);
   ExecuteInitializeSolutionStep; record; ExecuteFinalizeSolutionStep. The rigid increment is
   computed with the same floating-point operations as csm (`rigid_position` below): x' = c +
   (v cos a + (k x v) sin a + k (k . v)(1 - cos a)) + t with v = x - c and k the unit axis.
   Each step records the INDEX_MAPs (CheckMortarConditions), NORMAL_GAP and ACTIVE of the slave
   nodes and the number of conditions in ComputingContact; the top-level fields are those of the
   last step (as csm's RESULT.json).

Usage (repository root): OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive python tools/kratos_fixtures_steps.py
    [--out tests/fixtures/steps] [--cases a,b]
"""
import argparse
import json
import math
import os
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import kratos_fixtures_search as base  # noqa: E402

import KratosMultiphysics as KM  # noqa: E402
import KratosMultiphysics.ContactStructuralMechanicsApplication as CSMA  # noqa: E402

ROOT = base.ROOT
VERSION = base.VERSION
DBL_MAX = sys.float_info.max


# ----------------------------------------------------------------------------------------------
# 1. test_dynamic_search.py (reference §20.2)
# ----------------------------------------------------------------------------------------------
DYNAMIC_MESHES = [("triangle", "test_double_curvature_integration_triangle.mdpa"),
                  ("quadrilateral", "test_double_curvature_integration_quadrilateral.mdpa")]
DYNAMIC_PARAMETERS = {"dynamic_search": True, "simple_search": False, "normal_orientation_threshold": 0.0}
DYNAMIC_GRAVITY = -9.81
DYNAMIC_DELTA_TIME = 0.5
DYNAMIC_ACTIVE_CHECK_FACTOR = 3.0e-1
DYNAMIC_TIME = 1.01


def dynamic_setup():
    """The SETUP.json that tells csm what test_dynamic_search.py does."""
    return {"model_part_name": "Structure",
            "contact_model_part": {"0": ["DISPLACEMENT_Displacement_Auto2"]},
            "assume_master_slave": {"0": ["Parts_Parts_Auto1"]},
            "contact_type": "Frictionless",
            "cpp_search_parameters": dict(DYNAMIC_PARAMETERS),
            "nodal_h": DBL_MAX,
            "process_info": {"STEP": 1, "TIME": DYNAMIC_TIME, "DELTA_TIME": DYNAMIC_DELTA_TIME,
                             "ACTIVE_CHECK_FACTOR": DYNAMIC_ACTIVE_CHECK_FACTOR},
            "nodal_values": [{"part": "Parts_Parts_Auto1", "variable": "ACCELERATION", "buffer": 1,
                              "value": [DYNAMIC_GRAVITY, 0.0, 0.0]}]}


def run_dynamic(mdpa):
    """test_dynamic_search.py, step by step; returns (result, info)."""
    model = KM.Model()
    mp = model.CreateModelPart("Structure", 2)
    for var in [KM.DISPLACEMENT, KM.VELOCITY, KM.ACCELERATION, KM.VOLUME_ACCELERATION, KM.REACTION,
                KM.NORMAL, CSMA.LAGRANGE_MULTIPLIER_CONTACT_PRESSURE, CSMA.WEIGHTED_GAP, KM.NODAL_H]:
        mp.AddNodalSolutionStepVariable(var)
    mp.CloneTimeStep(DYNAMIC_TIME)
    KM.ModelPartIO(os.path.join(ROOT, base.KRATOS_TESTS_DIR, mdpa[:-len(".mdpa")])).ReadModelPart(mp)
    for dof, reaction in [(KM.DISPLACEMENT_X, KM.REACTION_X), (KM.DISPLACEMENT_Y, KM.REACTION_Y),
                          (KM.DISPLACEMENT_Z, KM.REACTION_Z),
                          (CSMA.LAGRANGE_MULTIPLIER_CONTACT_PRESSURE, CSMA.WEIGHTED_GAP)]:
        KM.VariableUtils().AddDof(dof, reaction, mp)
    interface = mp.CreateSubModelPart("Contact")
    contact = mp.GetSubModelPart("DISPLACEMENT_Displacement_Auto2")
    slave = mp.GetSubModelPart("Parts_Parts_Auto1")
    KM.VariableUtils().SetFlag(KM.SLAVE, False, contact.Nodes)
    KM.VariableUtils().SetFlag(KM.MASTER, True, contact.Nodes)
    KM.VariableUtils().SetFlag(KM.SLAVE, True, slave.Nodes)
    KM.VariableUtils().SetFlag(KM.MASTER, False, slave.Nodes)
    for node in slave.Nodes:
        node.SetSolutionStepValue(KM.ACCELERATION_X, 1, DYNAMIC_GRAVITY)
    mp.ProcessInfo[KM.STEP] = 1
    mp.ProcessInfo[KM.DELTA_TIME] = DYNAMIC_DELTA_TIME
    for prop in mp.GetProperties():
        prop[CSMA.INTEGRATION_ORDER_CONTACT] = 3
    mp.ProcessInfo[CSMA.ACTIVE_CHECK_FACTOR] = DYNAMIC_ACTIVE_CHECK_FACTOR
    KM.VariableUtils().SetFlag(KM.INTERFACE, True, contact.Nodes)
    CSMA.InterfacePreprocessCondition(mp).GenerateInterfacePart(
        contact, KM.Parameters('{"simplify_geometry": false}'))
    for cond in contact.Conditions:
        interface.AddCondition(cond)
    for node in contact.Nodes:
        interface.AddNode(node, 0)
    KM.FindNodalHProcess(contact).Execute()
    CSMA.ALMFastInit(contact).Execute()
    params, simple = base.wrapper_parameters(KM.Parameters(json.dumps(DYNAMIC_PARAMETERS)))
    cls = base.concrete_class(mp, simple, mp.ProcessInfo[KM.DOMAIN_SIZE])
    info = {"class": cls.__name__}
    h = [n.GetSolutionStepValue(KM.NODAL_H) for n in mp.Nodes]
    if min(h) != DBL_MAX:
        raise RuntimeError("NODAL_H is expected to stay DBL_MAX on every node (reference §20.2)")
    search = cls(mp, params)
    t0 = time.perf_counter()
    search.ExecuteInitialize()
    t1 = time.perf_counter()
    search.ExecuteInitializeSolutionStep()
    t2 = time.perf_counter()
    info["distance_threshold"] = mp.ProcessInfo[CSMA.DISTANCE_THRESHOLD]
    with base.CapturedLog() as log:
        search.CheckMortarConditions()
    maps = base.parse_index_maps(log.text)
    slaves = sorted(c.Id for c in interface.Conditions if c.Is(KM.SLAVE))
    result = {"warnings": []}
    result["pairs"] = {"0": {str(s): maps.get(s, []) for s in slaves}}
    slave_nodes = [n for n in interface.Nodes if n.Is(KM.SLAVE)]
    if sorted(n.Id for n in slave_nodes) != sorted(n.Id for n in slave.Nodes):
        raise RuntimeError("the slave nodes of Contact are not those of Parts_Parts_Auto1")
    result["nodes"] = base.node_values(slave_nodes, result["warnings"])
    computing = mp.GetSubModelPart("ComputingContact")
    result["paired_conditions"] = computing.NumberOfConditions()
    result["timings_s"] = {"initialize": t1 - t0, "search": t2 - t1}
    # A second ExecuteFinalizeSolutionStep would clear the maps: ResetContactOperators fetches
    # the paired condition of every INDEX_MAP entry, and without condition_name they are all 0
    # (reference Q18). Recorded for the documentation.
    try:
        search.ExecuteFinalizeSolutionStep()
        info["finalize"] = "ok"
    except RuntimeError as e:
        info["finalize"] = "error: " + base.kratos_error(e)
    return result, info


# ----------------------------------------------------------------------------------------------
# 2. Multi-step runs (ALMContactProcess, steps as Kratos' analysis stage runs them)
# ----------------------------------------------------------------------------------------------
def rigid_position(p, motion):
    """The new position of point p under one rigid increment: rotation about the axis through
    the centre, then translation. The same floating-point operations as csm's
    `RigidMotion::apply` (crates/csm-search/src/setup/types.rs)."""
    x, y, z = p
    rotate = motion.get("rotate")
    if rotate is not None:
        a0, a1, a2 = rotate["axis"]
        n = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        k0, k1, k2 = a0 / n, a1 / n, a2 / n
        c0, c1, c2 = rotate.get("centre", [0.0, 0.0, 0.0])
        angle = rotate["angle_deg"] * (math.pi / 180.0)
        cos, sin = math.cos(angle), math.sin(angle)
        v0, v1, v2 = x - c0, y - c1, z - c2
        w0, w1, w2 = k1 * v2 - k2 * v1, k2 * v0 - k0 * v2, k0 * v1 - k1 * v0
        f = (k0 * v0 + k1 * v1 + k2 * v2) * (1.0 - cos)
        x = c0 + (v0 * cos + w0 * sin + k0 * f)
        y = c1 + (v1 * cos + w1 * sin + k1 * f)
        z = c2 + (v2 * cos + w2 * sin + k2 * f)
    t0, t1, t2 = motion.get("translate", [0.0, 0.0, 0.0])
    return (x + t0, y + t1, z + t2)


def apply_step_motion(mp, step):
    """The rigid increments of one step: every node of a named part moves, every other node gets a
    zero increment; DISPLACEMENT accumulates, VELOCITY = increment / dt, ACCELERATION = (VELOCITY -
    previous VELOCITY) / dt (previous = buffer index 1, after CloneTimeStep)."""
    dt = step["delta_time"]
    moved = {}
    for part, motion in sorted(step.get("move", {}).items()):
        for node in mp.GetSubModelPart(part).Nodes:
            if node.Id in moved:
                raise RuntimeError("node %d is in two moved parts" % node.Id)
            moved[node.Id] = rigid_position((node.X, node.Y, node.Z), motion)
    for node in mp.Nodes:
        old = (node.X, node.Y, node.Z)
        new = moved.get(node.Id, old)
        inc = [new[i] - old[i] for i in range(3)]
        node.X, node.Y, node.Z = new
        u = node.GetSolutionStepValue(KM.DISPLACEMENT)
        v_old = node.GetSolutionStepValue(KM.VELOCITY, 1)
        v = [inc[i] / dt for i in range(3)]
        a = [(v[i] - v_old[i]) / dt for i in range(3)]
        node.SetSolutionStepValue(KM.DISPLACEMENT, KM.Array3([u[i] + inc[i] for i in range(3)]))
        node.SetSolutionStepValue(KM.VELOCITY, KM.Array3(v))
        node.SetSolutionStepValue(KM.ACCELERATION, KM.Array3(a))


def contact_state(mp, process):
    """INDEX_MAPs, slave nodes and paired-condition count after the search step."""
    search = process.search_utility_list["0"]
    with base.CapturedLog() as log:
        search.CheckMortarConditions()
    maps = base.parse_index_maps(log.text)
    sub = mp.GetSubModelPart("Contact").GetSubModelPart("ContactSub0")
    slaves = sorted(c.Id for c in sub.Conditions if c.Is(KM.SLAVE))
    warnings = []
    state = {"pairs": {"0": {str(s): maps.get(s, []) for s in slaves}},
             "nodes": base.node_values([n for n in sub.Nodes if n.Is(KM.SLAVE)], warnings),
             "paired_conditions": mp.GetSubModelPart("ComputingContact").NumberOfConditions()}
    # Cross-check: every paired condition is in the maps (kept ones included).
    by_nodes = {base.geometry_key(c.GetGeometry()): c.Id for c in sub.Conditions}
    paired = set(base.paired_from_computing(mp, by_nodes))
    map_pairs = {(s, m) for s, ms in maps.items() for m in ms}
    return state, warnings, paired == map_pairs


def run_steps(mesh, dim, setup):
    model, mp = base.read_structure(mesh, base.ALM_VARIABLES)
    steps = setup["steps"]
    pi = mp.ProcessInfo
    pi[KM.DOMAIN_SIZE] = dim
    pi[KM.STEP] = 1
    pi[KM.TIME] = 1.0
    pi[KM.DELTA_TIME] = 1.0
    kratos_setup = {k: v for k, v in setup.items() if k not in base.CSM_KEYS}
    process = base.HarnessALMContactProcess(model, KM.Parameters(json.dumps(kratos_setup)))
    t0 = time.perf_counter()
    process.ExecuteInitialize()
    t1 = time.perf_counter()
    out = {"warnings": [], "steps": []}
    info = {"class": process.concrete_class_name, "crosscheck": [], "time": []}
    for k, step in enumerate(steps, 1):
        dt = step["delta_time"]
        if k > 1:
            pi[KM.STEP] += 1
            mp.CloneTimeStep(pi[KM.TIME] + dt)
        if abs(pi[KM.DELTA_TIME] - dt) > 1e-12 * dt and k > 1:
            info.setdefault("notes", []).append("CloneTimeStep left DELTA_TIME %r at step %d" % (pi[KM.DELTA_TIME], k))
        pi[KM.DELTA_TIME] = dt
        apply_step_motion(mp, step)
        s0 = time.perf_counter()
        process.ExecuteInitializeSolutionStep()
        s1 = time.perf_counter()
        state, warnings, same = contact_state(mp, process)
        out["warnings"].extend(warnings)
        info["crosscheck"].append(same)
        info["time"].append((pi[KM.STEP], pi[KM.TIME]))
        entry = {"step": k}
        entry.update(state)
        entry["timings_s"] = {"search": s1 - s0}
        out["steps"].append(entry)
        process.ExecuteFinalizeSolutionStep()
    last = out["steps"][-1]
    out["pairs"], out["nodes"], out["paired_conditions"] = last["pairs"], last["nodes"], last["paired_conditions"]
    out["timings_s"] = {"initialize": t1 - t0, "search": sum(s["timings_s"]["search"] for s in out["steps"])}
    return out, info


def alm_setup(search_parameters, steps):
    return {"model_part_name": "Structure",
            "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]},
            "contact_type": "Frictionless",
            "search_parameters": search_parameters,
            "steps": steps}


# (case name, scene, dimension, setup). The motions are chosen so that pairs, gaps and ACTIVE
# flags change from step to step.
STEP_CASES = [
    # database_step_update 2: searches at steps 1 and 3; step 2 is skipped (every Contact node and
    # condition set inactive, reference §1.4/Q36) while the block keeps moving; step 3 tilts it.
    ("stacked_blocks__database_step_update_2", "stacked_blocks", 3,
     alm_setup({"database_step_update": 2}, [
         {"delta_time": 0.1, "move": {"Parts_Upper": {"translate": [0.03, 0.02, 0.0]}}},
         {"delta_time": 0.1, "move": {"Parts_Upper": {"translate": [0.03, 0.02, 0.001]}}},
         {"delta_time": 0.1, "move": {"Parts_Upper": {
             "translate": [0.03, 0.02, -0.001],
             "rotate": {"axis": [0.0, 1.0, 0.0], "angle_deg": 0.2, "centre": [0.5, 0.5, 0.0]}}}},
     ])),
    # Search every step with the dynamic search (half jump from VELOCITY and ACCELERATION history,
    # reference §11) and static_check_movement (WEIGHTED_GAP of the previous step, §10.6); a small
    # active_check_factor makes the 2e-4 floor of consider_gap_threshold matter.
    ("sphere_on_plate_tri__dynamic_static_check", "sphere_on_plate_tri", 3,
     alm_setup({"dynamic_search": True, "static_check_movement": True, "consider_gap_threshold": True,
                "active_check_factor": 0.001}, [
         {"delta_time": 0.5, "move": {"Parts_Sphere": {"translate": [0.01, 0.0, -0.002]}}},
         {"delta_time": 0.5, "move": {"Parts_Sphere": {"translate": [0.01, 0.005, 0.001]}}},
         {"delta_time": 0.25, "move": {"Parts_Sphere": {
             "translate": [0.0, 0.0, -0.003],
             "rotate": {"axis": [1.0, 1.0, 0.0], "angle_deg": 1.0, "centre": [0.0, 0.0, 1.0]}}}},
     ])),
    # static_check_movement with consider_gap_threshold: every slave node of the flat interface
    # opens to a gap of 1.5e-4 (step 2), between L = DISTANCE_THRESHOLD * 0.001 (about 1e-4) and
    # the 2e-4 floor, with a WEIGHTED_GAP growing from the previous step's (buffer index 1):
    # active only through the static check; then closes to 1.2e-4 (step 3): the weighted gap
    # decreases, the floor does not apply and the nodes are inactive (reference §10.6).
    ("stacked_blocks__static_check_movement", "stacked_blocks", 3,
     alm_setup({"static_check_movement": True, "consider_gap_threshold": True,
                "active_check_factor": 0.001}, [
         {"delta_time": 0.1, "move": {"Parts_Upper": {"translate": [0.02, 0.0, 0.0]}}},
         {"delta_time": 0.1, "move": {"Parts_Upper": {"translate": [0.02, 0.01, 1.5e-4]}}},
         {"delta_time": 0.1, "move": {"Parts_Upper": {"translate": [0.0, 0.02, -0.3e-4]}}},
     ])),
    # 2D, Simple activation, a rolling disc (rotation about z through its centre plus translation).
    ("cylinder_on_block_2d__simple_rolling", "cylinder_on_block_2d", 2,
     alm_setup({"simple_search": True}, [
         {"delta_time": 1.0, "move": {"Parts_Disc": {
             "translate": [0.05, -0.001, 0.0],
             "rotate": {"axis": [0.0, 0.0, 1.0], "angle_deg": -2.0, "centre": [0.0, 0.995, 0.0]}}}},
         {"delta_time": 1.0, "move": {"Parts_Disc": {
             "translate": [0.05, 0.0, 0.0],
             "rotate": {"axis": [0.0, 0.0, 1.0], "angle_deg": -2.0, "centre": [0.05, 0.994, 0.0]}}}},
         {"delta_time": 1.0, "move": {"Parts_Disc": {
             "translate": [0.05, 0.002, 0.0],
             "rotate": {"axis": [0.0, 0.0, 1.0], "angle_deg": -2.0, "centre": [0.1, 0.994, 0.0]}}}},
     ])),
]


# ----------------------------------------------------------------------------------------------
# Output
# ----------------------------------------------------------------------------------------------
def dumps(obj):
    """base.dumps, with every entry of `steps` written the same way on its own lines."""
    steps = obj.get("steps")
    if steps is None:
        return base.dumps(obj)
    head = dict(obj)
    del head["steps"]
    text = base.dumps(head).rstrip("\n")
    assert text.endswith("}")
    parts = []
    for s in steps:
        parts.append("  " + base.dumps(s).rstrip("\n").replace("\n", "\n  "))
    return text[:-1].rstrip("\n") + ',\n "steps":[\n' + ",\n".join(parts) + "\n ]\n}\n"


def fixture(mesh, setup, result, extra=None):
    obj = {"format": "csm-result/1", "mesh": mesh, "setup": setup, "kratos": VERSION}
    if extra:
        obj.update(extra)
    for k in ("pairs", "nodes", "paired_conditions", "warnings"):
        obj[k] = result[k]
    obj["timings_s"] = {k: round(v, 6) for k, v in result["timings_s"].items()}
    if "steps" in result:
        obj["steps"] = [dict(s, timings_s={k: round(v, 6) for k, v in s["timings_s"].items()})
                        for s in result["steps"]]
    return obj


def summary(state):
    pairs = state["pairs"]["0"]
    return (sum(1 for v in pairs.values() if v), sum(len(v) for v in pairs.values()),
            sum(1 for v in state["nodes"].values() if v["active"]),
            sum(1 for v in state["nodes"].values() if v["normal_gap"] is None),
            state["paired_conditions"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "fixtures", "steps"))
    ap.add_argument("--cases", default="")
    args = ap.parse_args()
    KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
    only = set(c for c in args.cases.split(",") if c)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    failures = []
    for short, mdpa in DYNAMIC_MESHES:
        name = "dynamic_search_" + short
        if only and name not in only:
            continue
        mesh = "%s/%s" % (base.KRATOS_TESTS_DIR, mdpa)
        result, info = run_dynamic(mdpa)
        obj = fixture(mesh, dynamic_setup(), result, {"checked_part": "Parts_Parts_Auto1"})
        with open(os.path.join(args.out, name + ".json"), "w", newline="\n") as f:
            f.write(dumps(obj))
        row = (name, "-", info["class"]) + summary(result) + (result["timings_s"]["search"],
                                                              "DISTANCE_THRESHOLD %r; finalize: %s" % (
                                                                  info["distance_threshold"], info["finalize"]))
        rows.append(row)
        print(row, flush=True)
    for name, scene, dim, setup in STEP_CASES:
        if only and name not in only:
            continue
        mesh = "%s/%s.mdpa" % (base.SCENES_DIR, scene)
        result, info = run_steps(mesh, dim, setup)
        with open(os.path.join(args.out, name + ".json"), "w", newline="\n") as f:
            f.write(dumps(fixture(mesh, setup, result)))
        for s, same in zip(result["steps"], info["crosscheck"]):
            row = (name, s["step"], info["class"]) + summary(s) + (
                s["timings_s"]["search"], "paired conditions = maps" if same else "PAIRED CONDITIONS != MAPS")
            rows.append(row)
            print(row, flush=True)
            if not same:
                failures.append((name, s["step"]))
        for note in info.get("notes", []):
            print(name, note)
    if not only:
        write_readme(args.out, rows)
    for f in failures:
        print("CROSS-CHECK FAILED:", f, file=sys.stderr)
    return 1 if failures else 0


def write_readme(out, rows):
    lines = ["# Kratos multi-step and dynamic-search fixtures (generated by tools/kratos_fixtures_steps.py — do not edit)",
             "",
             "Kratos %s, one thread. Format `csm-result/1` plus `mesh`, `setup` (the SETUP.json given to csm) "
             "and `kratos`; multi-step fixtures also have `steps` (one entry per step: `step`, `pairs`, "
             "`nodes`, `paired_conditions`, `timings_s`), their top-level fields being those of the last "
             "step. The script's docstring says exactly how Kratos is driven." % VERSION,
             "",
             "* `dynamic_search_{triangle,quadrilateral}`: Kratos' test_dynamic_search.py (reference §20.2) "
             "on its own meshes (`../shared/data/kratos-tests/`). NODAL_H stays DBL_MAX (FindNodalHProcess on "
             "a part without elements), so DISTANCE_THRESHOLD is inf and every slave node is ACTIVE; the "
             "slave nodes are shifted by the half jump 0.125 * 0.5^2 * (-9.81) = -0.3065625 in x for the "
             "search and the mapping. No paired conditions (no condition_name). The test's own expected "
             "JSON is not available; these fixtures are what Kratos 10.4.4 computes for its set-up. "
             "(INTEGRATION_ORDER_CONTACT 3, set by the test, only matters for paired conditions: there "
             "are none.)",
             "* `<scene>__<case>`: multi-step ALMContactProcess runs (steps as Kratos' analysis stage runs "
             "them: STEP += 1, CloneTimeStep, motion, ExecuteInitializeSolutionStep, "
             "ExecuteFinalizeSolutionStep). Paired conditions still ACTIVE are kept from step to step "
             "(ResetContactOperators), so `paired_conditions` counts kept and new ones.",
             "",
             "| case | step | Kratos class | slaves | pairs | active | gap null | paired | search s | note |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %s | %s | %d | %d | %d | %d | %d | %.4f | %s |" % r)
    with open(os.path.join(out, "README.md"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
