"""Search reference fixtures from Kratos 10.4.4 (run by `cargo xtask fixtures`).

For every scene of tests/data/scenes/ (made by tools/gen_scenes.py) and every setup below, runs
one contact-search step of Kratos 10.4.4 with one thread and writes
tests/fixtures/search/<scene>/<setup>.json in csm's RESULT.json format (`csm-result/1`, DESIGN.md
§3) plus the mesh, the SETUP.json object given to csm (exactly what Kratos was given) and the
Kratos version:

  {"format": "csm-result/1", "mesh": "tests/data/scenes/<scene>.mdpa", "setup": {...},
   "kratos": "<version>", "pairs": {"0": {"<slave cond>": [masters ascending]}},
   "nodes": {"<slave node>": {"normal_gap": x|null, "active": b}}, "paired_conditions": n,
   "warnings": [], "timings_s": {"initialize": s, "search": s}}

or, when Kratos raised, the same without pairs/nodes/paired_conditions and with
"error": "<Kratos' message>" (csm must fail as well in kratos mode).

Python path (scenes sphere_on_plate_tri, sphere_on_plate_mixed, stacked_blocks,
cylinder_on_block_2d, stacked_blocks_pen, stacked_blocks_rotated, cylinder_on_plate_quads): the SETUP.json is the `Parameters` of ALMContactProcess. Model part
"Structure" (buffer 2) with the nodal variables of frictionless ALM contact, ModelPartIO,
ProcessInfo DOMAIN_SIZE/STEP = 1/TIME = 1/DELTA_TIME = 1, then ExecuteInitialize and
ExecuteInitializeSolutionStep (timed alone). ALMContactProcess is subclassed only to create the
concrete search class the wrapper would choose (reference §2) with the wrapper's parameters, so
that `CheckMortarConditions()` can print the INDEX_MAPs (captured through a Kratos file logger
and parsed). The pairs are cross-checked against the paired conditions of ComputingContact
(MappingCheck: equal sets; No/DirectCheck: every paired condition is in the maps).
Setups: type_search x check_gap x simple_search, named <type_search>__<check>__<simple|advanced>
(check_gap "mapping_check" = the key omitted, Kratos' default). stacked_blocks_pen has only
octree_with_obb, once as usual and once with the csm key "process_info": {"DOMAIN_SIZE": 0}
(suffix __domain_size_0; the harness sets it in ProcessInfo): with DOMAIN_SIZE unset Kratos'
octree box gets no thickness and finds no pair (the reproduction target of the reference header;
with DOMAIN_SIZE = 3 Kratos 10.4.4 does find the pairs, on this scene and on stacked_blocks).
csm-only keys (process_info, nodal_h, cpp_search_parameters, ...) are applied by the harness and
not passed to ALMContactProcess. With octree_with_obb and No/DirectCheck Kratos also fills the
INDEX_MAP of master conditions (and creates master-master paired conditions, counted in
paired_conditions); `pairs` lists slave-side conditions only (DESIGN.md §3).

C++ path (scene plane_cylinder_cpp): Kratos' test_search_process.cpp (reference §20.1): the
concrete class built directly with the test's parameters (C++ wrapper defaults for the rest) on
a model part prepared as the test does (sub model part Contact with everything, SLAVE/MASTER
flags, CalculateUnitNormals, NODAL_H = 1, STEP/NL_ITERATION_NUMBER/DELTA_TIME = 1,
DISTANCE_THRESHOLD = 1, DOMAIN_SIZE not set). csm gets the same through the SETUP.json keys
`cpp_search_parameters`, `nodal_h` and `process_info`. The §20.1 INDEX_MAP tables and the
header note (only slave nodes 1 and 2 ACTIVE, NORMAL_GAP ~ -0.0011945660046527) are asserted:
they calibrate this harness.

Kratos test meshes (scenes kratos_<short name>, meshes ../shared/data/kratos-tests/<file>.mdpa,
relative to the repository root; see kratos_meshes()): their contact parts list nodes only, so
ExecuteInitialize generates the interface conditions (InterfacePreprocessCondition, reference §13).
Python path, setups in_radius/in_radius_with_obb x no/direct/mapping_check (check_gap always
written) x simple/advanced. Each scene also gets interface.json (`csm-interface/1`): the conditions
of Contact/ContactSub0 after ExecuteInitialize (id, nodes in order, SLAVE/MASTER true/false/null),
checked to be the same in every run of the mesh; where ExecuteInitialize raised, those generated
before it, with the error.

The seed's other processes and options (issue 26):
* roles decided automatically (`assume_master_slave` absent): Kratos test meshes kept in
  tests/data/kratos/ (SOURCES.md there) — the simplest patch (`kratos_simplest_patch`, and with
  every node listed, `kratos_simplest_patch_all_nodes`), the 2D hertz mesh (`kratos_hertz`), the
  self-contact mesh as shipped (`kratos_self_contact`: Kratos raises) and with node-only contact
  parts (`kratos_self_contact_nodes_only`, two pairs) — and the generated self-contact scene
  `kratos_folded_strip`; `stacked_blocks/auto_roles__…` (Kratos raises). With roles not
  predefined the wrapper takes the first condition's node count for both sides.
* skin detection (`skin_detection`: every contact_model_part list empty; Kratos raises);
* MeshTyingProcess and MPCContactProcess (`<scene>_processes`, SETUP.json key `process`: the
  module); MPC's pairs are read from ComputingContact (its search has no CheckMortarConditions;
  with MappingCheck the maps are exactly the paired conditions), with the constraint count;
* condition ids 10 and 20 (`condition_ids_10_20`): Kratos' renumbered ids in `pairs`.
Several pair keys are written under their keys.

Also writes tests/fixtures/search/README.md (scene sizes, summary table, total Kratos time).

Usage (repository root): OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive python tools/kratos_fixtures_search.py
    [--out tests/fixtures/search] [--scenes a,b] [--quick]
"""
import argparse
import json
import math
import os
import re
import sys
import tempfile
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

import KratosMultiphysics as KM  # noqa: E402
import KratosMultiphysics.StructuralMechanicsApplication  # noqa: E402,F401
import KratosMultiphysics.ContactStructuralMechanicsApplication as CSMA  # noqa: E402
from KratosMultiphysics.ContactStructuralMechanicsApplication import alm_contact_process  # noqa: E402
from KratosMultiphysics.ContactStructuralMechanicsApplication import mesh_tying_process  # noqa: E402
from KratosMultiphysics.ContactStructuralMechanicsApplication import mpc_contact_process  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENES_DIR = "tests/data/scenes"
VERSION = KM.KratosGlobals.Kernel.Version()

PYTHON_SCENES = [("sphere_on_plate_tri", 3), ("sphere_on_plate_mixed", 3),
                 ("stacked_blocks", 3), ("cylinder_on_block_2d", 2), ("stacked_blocks_pen", 3),
                 ("stacked_blocks_rotated", 3), ("cylinder_on_plate_quads", 3)]
TYPES = ["in_radius", "in_box", "in_radius_with_obb", "in_box_with_obb", "octree_with_obb"]
CHECKS = ["no_check", "direct_check", "mapping_check"]

# ContactSearchWrapperProcess::GetDefaultParameters (reference §2).
WRAPPER_DEFAULTS = {
    "simple_search": False, "allocation_size": 1000, "bucket_size": 4, "search_factor": 3.5,
    "type_search": "InRadius", "check_gap": "MappingCheck", "condition_name": "",
    "final_string": "", "inverted_search": False, "dynamic_search": False,
    "static_check_movement": False, "predefined_master_slave": True, "id_name": "",
    "normal_orientation_threshold": 1.0e-8, "consider_gap_threshold": False,
    "predict_correct_lagrange_multiplier": False, "pure_slip": False, "debug_mode": False,
    "octree_search_parameters": {
        "bounding_box_factor": 0.1, "debug_obb": False,
        "OBB_intersection_type": "SeparatingAxisTheorem", "build_from_bounding_box": True,
        "lower_bounding_box_coefficient": 0.0, "higher_bounding_box_coefficient": 1.0}}

# SETUP.json keys that are csm's, not Kratos' (DESIGN.md §2): applied by the harness, not passed on.
CSM_KEYS = ("compatibility", "strict", "process_info", "nodal_h", "cpp_search_parameters", "steps",
            "nodal_values", "process")

NOT_MAPPED = 1.0e12  # NORMAL_GAP sentinel of the mapper ("not mapped")


# ----------------------------------------------------------------------------------------------
# Helpers
# ----------------------------------------------------------------------------------------------
def concrete_class(model_part, simple, dimension, predefined=True):
    """The class ContactSearchWrapperProcess instantiates (reference §2)."""
    prefix = "Simple" if simple else "Advanced"
    if dimension == 2:
        return getattr(CSMA, prefix + "ContactSearchProcess2D2N")
    contact = model_part.GetSubModelPart("Contact")
    if not predefined:  # the wrapper takes the first condition's node count for both sides
        size = len(next(iter(contact.Conditions)).GetGeometry())
        size = 3 if size == 6 else size
        return getattr(CSMA, prefix + "ContactSearchProcess3D%dN" % size)
    size_master = size_slave = 0
    for cond in contact.Conditions:
        if cond.Is(KM.MASTER):
            size_master = len(cond.GetGeometry())
        if cond.Is(KM.SLAVE):
            size_slave = len(cond.GetGeometry())
        if size_master and size_slave:
            break
    size_master = 3 if size_master == 6 else size_master
    size_slave = 3 if size_slave == 6 else size_slave
    suffix = {(3, 3): "3D3N", (4, 4): "3D4N", (4, 3): "3D3N4N", (3, 4): "3D4N3N"}[(size_master, size_slave)]
    return getattr(CSMA, prefix + "ContactSearchProcess" + suffix)


def wrapper_parameters(params):
    """Validates like the wrapper (recursively, wrapper defaults), then drops simple_search
    as the wrapper does before building the concrete class. Returns (Parameters, simple)."""
    params.RecursivelyValidateAndAssignDefaults(KM.Parameters(json.dumps(WRAPPER_DEFAULTS)))
    simple = params["simple_search"].GetBool()
    params.RemoveValue("simple_search")
    return params, simple


class CapturedLog:
    """Captures the Kratos logger (INFO level) into a temporary file while active."""

    def __enter__(self):
        fd, self.path = tempfile.mkstemp(suffix=".log")
        os.close(fd)
        self.out = KM.FileLoggerOutput(self.path)
        self.out.SetSeverity(KM.Logger.Severity.INFO)
        KM.Logger.AddOutput(self.out)
        return self

    def __exit__(self, *exc):
        KM.Logger.Flush()
        KM.Logger.RemoveOutput(self.out)
        del self.out
        with open(self.path) as f:
            self.text = f.read()
        os.remove(self.path)
        return False


# CheckMortarConditions prints, per non-empty map, "... Origin condition ID:<id> Number of pairs: <n>"
# then n lines "... The condition <master id> related with the new condition <paired id>".
ORIGIN = re.compile(r"Origin condition ID:\s*(\d+)\s+Number of pairs:\s*(\d+)")
DESTINATION = re.compile(r"The condition (\d+) related with the new condition")


def parse_index_maps(text):
    """Parses the CheckMortarConditions output into {slave id: [master ids]}."""
    maps = {}
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = ORIGIN.search(lines[i])
        if not m:
            i += 1
            continue
        sid, n = int(m.group(1)), int(m.group(2))
        masters = []
        for k in range(1, n + 1):
            d = DESTINATION.search(lines[i + k])
            if not d:
                raise RuntimeError("unexpected CheckMortarConditions line %r" % lines[i + k])
            masters.append(int(d.group(1)))
        if sid in maps:
            raise RuntimeError("slave %d printed twice" % sid)
        maps[sid] = sorted(masters)
        if len(set(masters)) != len(masters):
            raise RuntimeError("duplicate master in map of %d" % sid)
        i += n + 1
    return maps


def kratos_error(e):
    text = str(e)
    lines = [l.strip() for l in text.splitlines() if l.strip()]
    for i, l in enumerate(lines):
        if l.startswith("Error:"):
            message = l[len("Error:"):].strip()
            if "parallel region" in message:  # add the first thread's own message
                inner = next((m for m in lines[i + 1:] if "caught exception:" in m), None)
                if inner is not None:
                    message += " " + inner.replace("caught exception: Error:", "caught exception:")
            return message
    return lines[0] if lines else text


def node_values(nodes, warnings):
    out = {}
    for node in sorted(nodes, key=lambda n: n.Id):
        gap = None
        if node.Has(CSMA.NORMAL_GAP):
            g = node.GetValue(CSMA.NORMAL_GAP)
            if math.isnan(g) or math.isinf(g):
                warnings.append("NORMAL_GAP of node %d is %r (written as null)" % (node.Id, g))
            elif abs(g) < NOT_MAPPED * 0.999:
                gap = g
        out[str(node.Id)] = {"normal_gap": gap, "active": bool(node.Is(KM.ACTIVE))}
    return out


def geometry_key(geom):
    return tuple(sorted(geom[i].Id for i in range(len(geom))))


def paired_from_computing(model_part, by_nodes):
    """(slave id, master id) of every paired condition in ComputingContact; unmatched geometries
    are reported with id None."""
    out = []
    if not model_part.HasSubModelPart("ComputingContact"):
        return out
    for cond in model_part.GetSubModelPart("ComputingContact").Conditions:
        g = cond.GetGeometry()
        s = by_nodes.get(geometry_key(g.GetGeometryPart(0)))
        m = by_nodes.get(geometry_key(g.GetGeometryPart(1)))
        out.append((s, m))
    return out


# ----------------------------------------------------------------------------------------------
# Python path: ALMContactProcess
# ----------------------------------------------------------------------------------------------
def create_concrete_search(process, key):
    """The search the wrapper would build, as its concrete class (so that CheckMortarConditions
    exists), for a process of SearchBaseProcess; False when Contact has no condition to choose
    a class from (the caller then lets Kratos' own wrapper raise)."""
    if process.main_model_part.GetSubModelPart("Contact").NumberOfConditions() == 0:
        process.concrete_class_name = "ContactSearchProcess"
        return False
    params, simple = wrapper_parameters(process._create_search_parameters(key))
    predefined = params["predefined_master_slave"].GetBool()
    cls = concrete_class(process.main_model_part, simple, process.dimension, predefined)
    process.concrete_class_name = cls.__name__
    process.search_utility_list[key] = cls(process.main_model_part, params, process._get_properties_pair(key))
    return True


class HarnessALMContactProcess(alm_contact_process.ALMContactProcess):
    """ALMContactProcess whose search is the concrete class (so CheckMortarConditions exists)."""

    def _create_main_search(self, key="0"):
        # Skin detection loses the skin (Contact empty): Kratos' own wrapper, which raises.
        if not create_concrete_search(self, key):
            super()._create_main_search(key)


def flag_value(entity, flag):
    """true/false, or None where the flag was never set on the entity."""
    return bool(entity.Is(flag)) if entity.IsDefined(flag) else None


def interface_conditions(model_part):
    """The conditions of Contact/ContactSub0 (for node-only contact parts: the ones
    InterfacePreprocessCondition generated, after NormalCheckProcess may have reversed them), by id."""
    contact = model_part.GetSubModelPart("Contact")
    if not contact.HasSubModelPart("ContactSub0"):
        return []
    sub = contact.GetSubModelPart("ContactSub0")
    return [{"id": c.Id, "nodes": [n.Id for n in c.GetNodes()], "slave": flag_value(c, KM.SLAVE),
             "master": flag_value(c, KM.MASTER)} for c in sorted(sub.Conditions, key=lambda c: c.Id)]


def read_structure(mesh, variables, name="Structure"):
    model = KM.Model()
    mp = model.CreateModelPart(name, 2)
    for var in variables:
        mp.AddNodalSolutionStepVariable(var)
    KM.ModelPartIO(os.path.join(ROOT, mesh[:-len(".mdpa")])).ReadModelPart(mp)
    return model, mp


ALM_VARIABLES = [KM.DISPLACEMENT, KM.REACTION, KM.VOLUME_ACCELERATION, KM.VELOCITY,
                 KM.ACCELERATION, KM.NORMAL, KM.NODAL_H, CSMA.WEIGHTED_GAP,
                 CSMA.LAGRANGE_MULTIPLIER_CONTACT_PRESSURE, CSMA.WEIGHTED_SCALAR_RESIDUAL]


def run_python(mesh, dim, setup):
    model, mp = read_structure(mesh, ALM_VARIABLES)
    mp.ProcessInfo[KM.DOMAIN_SIZE] = dim
    mp.ProcessInfo[KM.STEP] = 1
    mp.ProcessInfo[KM.TIME] = 1.0
    mp.ProcessInfo[KM.DELTA_TIME] = 1.0
    for name, value in setup.get("process_info", {}).items():  # csm key: ProcessInfo overrides
        var = KM.KratosGlobals.GetVariable(name)
        mp.ProcessInfo[var] = int(value) if isinstance(var, KM.IntegerVariable) else float(value)
    kratos_setup = {k: v for k, v in setup.items() if k not in CSM_KEYS}
    result = {"warnings": []}
    info = {}
    try:
        process = HarnessALMContactProcess(model, KM.Parameters(json.dumps(kratos_setup)))
        t0 = time.perf_counter()
        process.ExecuteInitialize()
        t1 = time.perf_counter()
        info["interface"] = interface_conditions(mp)
        # Q33: NODAL_H stays DBL_MAX on nodes in no element (FindNodalHProcess on the root).
        info["nodal_h_dbl_max"] = sum(1 for n in mp.Nodes if n.GetSolutionStepValue(KM.NODAL_H) > 1.0e300)
        process.ExecuteInitializeSolutionStep()
        t2 = time.perf_counter()
    except RuntimeError as e:
        result["error"] = kratos_error(e)
        if "interface" not in info:  # raised in ExecuteInitialize: the conditions generated so far
            info["interface"] = interface_conditions(mp) if mp.HasSubModelPart("Contact") else []
            info["interface_error"] = result["error"]
        return result, info
    info["class"] = process.concrete_class_name
    # Every pair key, in key order (a ContactSub<key> each).
    keys = sorted(process.search_utility_list)
    result["pairs"] = {}
    maps = {}
    slave_nodes = {}
    unknown = set()
    for key in keys:
        with CapturedLog() as log:
            process.search_utility_list[key].CheckMortarConditions()
        key_maps = parse_index_maps(log.text)
        sub = mp.GetSubModelPart("Contact").GetSubModelPart("ContactSub" + key)
        slaves = sorted(c.Id for c in sub.Conditions if c.Is(KM.SLAVE))
        # The octree path with No/DirectCheck also fills INDEX_MAPs of master conditions
        # (reference header: master-master paired conditions); RESULT.json lists slave-side
        # conditions only.
        unknown |= set(key_maps) - set(slaves)
        result["pairs"][key] = {str(s): key_maps.get(s, []) for s in slaves}
        maps.update(key_maps)
        for n in sub.Nodes:
            if n.Is(KM.SLAVE):
                slave_nodes[n.Id] = n
    sub = mp.GetSubModelPart("Contact")
    result["nodes"] = node_values(list(slave_nodes.values()), result["warnings"])
    result["paired_conditions"] = mp.GetSubModelPart("ComputingContact").NumberOfConditions()
    result["timings_s"] = {"initialize": t1 - t0, "search": t2 - t1}
    # Cross-check with the paired conditions.
    by_nodes = {geometry_key(c.GetGeometry()): c.Id for c in sub.Conditions}
    paired = paired_from_computing(mp, by_nodes)
    map_pairs = {(s, m) for s, ms in maps.items() for m in ms}
    paired_set = set(paired)
    if setup["search_parameters"].get("check_gap", "check_mapping") in ("no_check", "direct_check"):
        ok = paired_set <= map_pairs or not paired
        info["crosscheck"] = ("paired conditions in maps" if paired_set <= map_pairs else
                              "%d paired conditions not in maps" % len(paired_set - map_pairs))
        extra = [p for p in paired if p[0] not in maps]
        if extra:
            info["crosscheck"] += "; %d with a non-slave origin" % len(extra)
    else:
        ok = paired_set == map_pairs and len(paired) == len(paired_set)
        info["crosscheck"] = "equal" if ok else "DIFFERENT (%d maps, %d paired)" % (len(map_pairs), len(paired))
    if unknown:
        info["crosscheck"] += "; %d non-slave conditions with a map (not in pairs)" % len(unknown)
    if info["nodal_h_dbl_max"]:
        info["crosscheck"] += "; NODAL_H = DBL_MAX on %d nodes" % info["nodal_h_dbl_max"]
    info["crosscheck_ok"] = ok
    return result, info


# ----------------------------------------------------------------------------------------------
# The other contact processes: MeshTyingProcess and MPCContactProcess
# ----------------------------------------------------------------------------------------------
class HarnessMeshTyingProcess(mesh_tying_process.MeshTyingProcess):
    """MeshTyingProcess whose search is the concrete class (so CheckMortarConditions exists)."""

    def _create_main_search(self, key="0"):
        if not create_concrete_search(self, key):
            super()._create_main_search(key)


# The nodal variables and degrees of freedom a mortar solver adds: the ALM ones, the vector
# multiplier and its residual (mesh tying, MPC); the MPC conditions need DISPLACEMENT dofs.
TYING_VARIABLES = ALM_VARIABLES + [KM.VECTOR_LAGRANGE_MULTIPLIER, CSMA.WEIGHTED_VECTOR_RESIDUAL]


def run_other_process(mesh, dim, setup):
    """One search step of MeshTyingProcess or MPCContactProcess (SETUP.json key `process`).
    Mesh tying: the INDEX_MAPs as for ALM. MPC: Kratos' MPCContactSearchProcess exposes no
    CheckMortarConditions; with MappingCheck the INDEX_MAPs are exactly the paired conditions
    (the ALM runs check that), so the pairs are read from ComputingContact. Also counts the
    master-slave constraints."""
    model, mp = read_structure(mesh, TYING_VARIABLES)
    for c in "XYZ":
        KM.VariableUtils().AddDof(getattr(KM, "DISPLACEMENT_" + c), getattr(KM, "REACTION_" + c), mp)
    for var, value in ((KM.DOMAIN_SIZE, dim), (KM.STEP, 1), (KM.TIME, 1.0), (KM.DELTA_TIME, 1.0)):
        mp.ProcessInfo[var] = value
    module = setup["process"]
    kratos_setup = {k: v for k, v in setup.items() if k not in CSM_KEYS}
    result = {"warnings": []}
    info = {"class": module}
    try:
        if module == "mesh_tying_process":
            process = HarnessMeshTyingProcess(model, KM.Parameters(json.dumps(kratos_setup)))
        else:
            process = mpc_contact_process.MPCContactProcess(model, KM.Parameters(json.dumps(kratos_setup)))
        t0 = time.perf_counter()
        process.ExecuteInitialize()
        t1 = time.perf_counter()
        process.ExecuteInitializeSolutionStep()
        t2 = time.perf_counter()
    except RuntimeError as e:
        result["error"] = kratos_error(e)
        return result, info
    contact = mp.GetSubModelPart("Contact")
    by_nodes = {geometry_key(c.GetGeometry()): c.Id for c in contact.Conditions}
    paired = paired_from_computing(mp, by_nodes)
    result["pairs"] = {}
    slave_nodes = {}
    for key in sorted(process.search_utility_list):
        sub = contact.GetSubModelPart("ContactSub" + key)
        slaves = sorted(c.Id for c in sub.Conditions if c.Is(KM.SLAVE))
        if module == "mesh_tying_process":
            info["class"] = process.concrete_class_name
            with CapturedLog() as log:
                process.search_utility_list[key].CheckMortarConditions()
            maps = parse_index_maps(log.text)
        else:
            maps = {}
            for s, m in paired:
                maps.setdefault(s, []).append(m)
            maps = {s: sorted(ms) for s, ms in maps.items()}
        result["pairs"][key] = {str(s): maps.get(s, []) for s in slaves}
        for n in sub.Nodes:
            if n.Is(KM.SLAVE):
                slave_nodes[n.Id] = n
    result["nodes"] = node_values(list(slave_nodes.values()), result["warnings"])
    result["paired_conditions"] = mp.GetSubModelPart("ComputingContact").NumberOfConditions()
    if module == "mpc_contact_process":
        result["master_slave_constraints"] = mp.NumberOfMasterSlaveConstraints()
    result["timings_s"] = {"initialize": t1 - t0, "search": t2 - t1}
    map_pairs = {(int(s), m) for ps in result["pairs"].values() for s, ms in ps.items() for m in ms}
    ok = set(paired) == map_pairs and len(paired) == len(set(paired))
    info["crosscheck"] = "equal" if ok else "DIFFERENT (%d maps, %d paired)" % (len(map_pairs), len(paired))
    info["crosscheck_ok"] = ok
    return result, info


def other_process_setups(scene):
    """MeshTyingProcess and MPCContactProcess on a scene with Parts_Slave/Parts_Master:
    MappingCheck, three search types, Simple and Advanced (MPC ignores simple_search)."""
    # (The scene name has the suffix "_processes" in the job list.)
    for module in ("mesh_tying_process", "mpc_contact_process"):
        short = "mesh_tying" if module == "mesh_tying_process" else "mpc"
        for ts in ("in_radius", "in_radius_with_obb", "octree_with_obb"):
            for simple in (False, True):
                sp = {"type_search": ts, "simple_search": simple}
                if module == "mesh_tying_process":
                    setup = {"model_part_name": "Structure",
                             "mesh_tying_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
                             "assume_master_slave": {"0": ["Parts_Slave"]},
                             "search_parameters": sp}
                    if scene == "sphere_on_plate_mixed":
                        # Triangles against quadrilaterals: the mesh tying's default
                        # consider_tessellation (true) makes Kratos triangulate the overlaps by
                        # Delaunay, which csm does not reproduce (docs/conformance.md).
                        setup["consider_tessellation"] = False
                else:
                    setup = {"process": module, "model_part_name": "Structure",
                             "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
                             "assume_master_slave": {"0": ["Parts_Slave"]},
                             "contact_type": "Frictionless", "search_parameters": sp}
                setup["process"] = module
                yield "%s__%s__mapping_check__%s" % (short, ts, "simple" if simple else "advanced"), setup


# ----------------------------------------------------------------------------------------------
# C++ path: test_search_process.cpp (reference §20.1)
# ----------------------------------------------------------------------------------------------
CPP_PROCESS_INFO = {"STEP": 1, "NL_ITERATION_NUMBER": 1, "DELTA_TIME": 1.0, "DISTANCE_THRESHOLD": 1.0}
CPP_TESTS = {
    "cpp_in_radius": {"simple_search": True, "search_factor": 3.5, "normal_orientation_threshold": 0.0,
                      "type_search": "InRadius", "check_gap": "MappingCheck"},
    "cpp_in_radius_with_obb": {"simple_search": True, "search_factor": 3.5,
                               "normal_orientation_threshold": 0.0, "type_search": "InRadiusWithOBB",
                               "check_gap": "MappingCheck",
                               "octree_search_parameters": {"bounding_box_factor": 0.1, "debug_obb": False}},
    "cpp_octree_with_obb": {"simple_search": True, "search_factor": 3.5,
                            "normal_orientation_threshold": 0.0, "type_search": "OctreeWithOBB",
                            "check_gap": "MappingCheck",
                            "octree_search_parameters": {"bounding_box_factor": 0.1, "debug_obb": False,
                                                         "OBB_intersection_type": "SeparatingAxisTheorem"}},
}
# §20.1 expectations (INDEX_MAP keys per slave condition).
CPP_EXPECTED = {
    "cpp_in_radius": {1: [9, 10], 2: [10, 11], 3: [11, 12], 4: [12, 13, 14], 5: [14, 15], 6: [15, 16], 7: [], 8: []},
    "cpp_in_radius_with_obb": {1: [9, 10], 2: [10, 11], 3: [11, 12], 4: [12, 13, 14], 5: [14], 6: [], 7: [], 8: []},
}
CPP_EXPECTED["cpp_octree_with_obb"] = CPP_EXPECTED["cpp_in_radius_with_obb"]
CPP_EXPECTED_GAP = -0.0011945660046527


def run_cpp(mesh, name):
    variables = [KM.DISPLACEMENT, CSMA.WEIGHTED_GAP, KM.VECTOR_LAGRANGE_MULTIPLIER,
                 CSMA.WEIGHTED_VECTOR_RESIDUAL, KM.NODAL_H, KM.NORMAL]
    model, mp = read_structure(mesh, variables)
    mp.CreateSubModelPart("ComputingContact")
    contact = mp.CreateSubModelPart("Contact")
    contact.AddNodes([n.Id for n in mp.Nodes])
    contact.AddConditions([c.Id for c in mp.Conditions])
    for part, slave in (("Parts_Slave", True), ("Parts_Master", False)):
        p = mp.GetSubModelPart(part)
        for entities in (p.Nodes, p.Conditions):
            KM.VariableUtils().SetFlag(KM.SLAVE, slave, entities)
            KM.VariableUtils().SetFlag(KM.MASTER, not slave, entities)
    pi = mp.ProcessInfo
    pi[KM.STEP] = CPP_PROCESS_INFO["STEP"]
    pi[KM.NL_ITERATION_NUMBER] = CPP_PROCESS_INFO["NL_ITERATION_NUMBER"]
    pi[KM.DELTA_TIME] = CPP_PROCESS_INFO["DELTA_TIME"]
    pi[CSMA.DISTANCE_THRESHOLD] = CPP_PROCESS_INFO["DISTANCE_THRESHOLD"]
    KM.NormalCalculationUtils().CalculateUnitNormals(contact, True)
    for node in mp.Nodes:
        node.SetSolutionStepValue(KM.NODAL_H, 1.0)
    params, simple = wrapper_parameters(KM.Parameters(json.dumps(CPP_TESTS[name])))
    cls = concrete_class(mp, simple, pi[KM.DOMAIN_SIZE])
    result = {"warnings": []}
    info = {"class": cls.__name__}
    try:
        search = cls(mp, params)
        t0 = time.perf_counter()
        search.ExecuteInitialize()
        t1 = time.perf_counter()
        search.ExecuteInitializeSolutionStep()
        t2 = time.perf_counter()
    except RuntimeError as e:
        result["error"] = kratos_error(e)
        return result, info
    with CapturedLog() as log:
        search.CheckMortarConditions()
    maps = parse_index_maps(log.text)
    slaves = sorted(c.Id for c in contact.Conditions if c.Is(KM.SLAVE))
    result["pairs"] = {"0": {str(s): maps.get(s, []) for s in slaves}}
    result["nodes"] = node_values([n for n in contact.Nodes if n.Is(KM.SLAVE)], result["warnings"])
    result["paired_conditions"] = mp.GetSubModelPart("ComputingContact").NumberOfConditions()
    result["timings_s"] = {"initialize": t1 - t0, "search": t2 - t1}
    # Calibration against §20.1 and the reference header.
    expected = CPP_EXPECTED[name]
    got = {s: maps.get(s, []) for s in slaves}
    problems = []
    if got != expected:
        problems.append("INDEX_MAP %s != §20.1 %s" % (got, expected))
    active = sorted(int(k) for k, v in result["nodes"].items() if v["active"])
    if active != [1, 2]:
        problems.append("ACTIVE slave nodes %s != [1, 2]" % active)
    for k in ("1", "2"):
        g = result["nodes"][k]["normal_gap"]
        if g is None or abs(g - CPP_EXPECTED_GAP) > 1e-12:
            problems.append("NORMAL_GAP of node %s = %r" % (k, g))
    info["calibration"] = problems
    info["crosscheck"] = "calibration %s" % ("OK" if not problems else "FAILED")
    info["crosscheck_ok"] = not problems
    return result, info


# ----------------------------------------------------------------------------------------------
# Setups, output
# ----------------------------------------------------------------------------------------------
def python_setups(scene):
    """Every type_search x check_gap x simple_search; for stacked_blocks_pen (the octree
    reproduction target) only octree_with_obb, with the emulated DOMAIN_SIZE and with
    DOMAIN_SIZE = 0 (never set: the octree box gets no thickness, reference §8 step 3)."""
    variants = [(t, None) for t in TYPES]
    if scene == "stacked_blocks_pen":
        variants = [("octree_with_obb", None), ("octree_with_obb", 0)]
    for ts, domain_size in variants:
        for check in CHECKS:
            for simple in (False, True):
                sp = {"type_search": ts}
                if check != "mapping_check":
                    sp["check_gap"] = check
                sp["simple_search"] = simple
                setup = {"model_part_name": "Structure",
                         "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
                         "assume_master_slave": {"0": ["Parts_Slave"]},
                         "contact_type": "Frictionless",
                         "search_parameters": sp}
                name = "%s__%s__%s" % (ts, check, "simple" if simple else "advanced")
                if domain_size is not None:
                    setup["process_info"] = {"DOMAIN_SIZE": domain_size}
                    name += "__domain_size_%d" % domain_size
                yield name, setup
    if scene == "stacked_blocks":
        # Roles not predefined on parts with conditions of their own: Kratos sets no MASTER
        # flag and raises "mPointListDestination not initialized" (reference §12).
        yield "auto_roles__in_radius__mapping_check__advanced", {
            "model_part_name": "Structure",
            "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "contact_type": "Frictionless",
            "search_parameters": {"type_search": "in_radius", "simple_search": False}}


# Kratos' own test meshes (/work/shared/data/kratos-tests, SOURCES.md there) whose contact parts list
# nodes only, so ALMContactProcess.ExecuteInitialize generates the interface conditions itself
# (InterfacePreprocessCondition, reference §13). Paths are relative to the repository root.
KRATOS_TESTS_DIR = "../shared/data/kratos-tests"
KRATOS_TYPES = ["in_radius", "in_radius_with_obb"]


def triquad_base_setup():
    """The contact process Parameters of the mesh's own ProjectParameters file."""
    path = os.path.join(ROOT, KRATOS_TESTS_DIR, "3D_contact_simplest_patch_matching_triquad_test_parameters.json")
    with open(path) as f:
        project = json.load(f)
    (process,) = [p for p in project["processes"]["contact_process_list"] if p["process_name"] == "ALMContactProcess"]
    return process["Parameters"]


def kratos_meshes():
    """(short name, mdpa file, dimension, base setup) of every Kratos test mesh.
    triquad: the setup of its ProjectParameters (slave = the tetrahedron block). patch_nonmatching:
    its ProjectParameters is an older format Kratos 10.4.4 rejects; the punch is the slave body, as
    in the test. double_curvature_*: as test_dynamic_search.py (reference §20.2): the interface part
    is DISPLACEMENT_Displacement_Auto2 (all nodes; the membrane elements become the conditions), the
    slave shell Parts_Parts_Auto1. (Listing DISPLACEMENT_Displacement_Auto1 as well makes Kratos
    generate the conditions of the elements inside it a second time: 8 duplicates on the triangles,
    all 1849 on the quadrilaterals, where Auto1 holds every node.)"""
    return [
        ("triquad", "3D_contact_simplest_patch_matching_triquad_test.mdpa", 3, triquad_base_setup()),
        ("patch_nonmatching", "3D_contact_patch_nonmatching_test.mdpa", 3,
         {"model_part_name": "Structure", "contact_type": "Frictionless",
          "contact_model_part": {"0": ["Contact_Part"]},
          "assume_master_slave": {"0": ["Parts_Part_punch"]}}),
        ("double_curvature_triangle", "test_double_curvature_integration_triangle.mdpa", 3,
         {"model_part_name": "Structure", "contact_type": "Frictionless",
          "contact_model_part": {"0": ["DISPLACEMENT_Displacement_Auto2"]},
          "assume_master_slave": {"0": ["Parts_Parts_Auto1"]}}),
        ("double_curvature_quadrilateral", "test_double_curvature_integration_quadrilateral.mdpa", 3,
         {"model_part_name": "Structure", "contact_type": "Frictionless",
          "contact_model_part": {"0": ["DISPLACEMENT_Displacement_Auto2"]},
          "assume_master_slave": {"0": ["Parts_Parts_Auto1"]}}),
    ]


# Kratos test meshes kept in this repository (tests/data/kratos/, SOURCES.md there), run with the
# roles decided automatically (`assume_master_slave` absent: predefined_master_slave false,
# reference §12). One interface.json per scene compares the generated conditions of every run,
# flags included, so a scene runs with one kind of roles only.
REPO_KRATOS_DIR = "tests/data/kratos"
AUTO_BASE = {"model_part_name": "Structure", "contact_type": "Frictionless",
             "contact_model_part": {"0": ["Contact_Part"]}}


def repo_kratos_meshes():
    """(scene, mdpa path, dimension, setups) of the meshes of tests/data/kratos."""
    return [
        ("kratos_simplest_patch", "%s/3D_contact_simplest_patch_matching_test.mdpa" % REPO_KRATOS_DIR, 3,
         list(kratos_mesh_setups(AUTO_BASE, "auto_roles__"))),
        ("kratos_hertz", "%s/hertz_simple_test.mdpa" % REPO_KRATOS_DIR, 2,
         list(kratos_mesh_setups(AUTO_BASE, "auto_roles__"))),
        # Its contact parts list conditions, which get no role: Kratos raises.
        ("kratos_self_contact", "%s/self_contact_test.mdpa" % REPO_KRATOS_DIR, 3,
         list(kratos_mesh_setups(self_contact_base(), "auto_roles__"))[4:5]),
        # The same mesh with node-only contact parts: Kratos generates the faces (all MASTER)
        # and the self-contact pairing decides the roles of each of the two pairs.
        ("kratos_self_contact_nodes_only", "%s/self_contact_nodes_only.mdpa" % REPO_KRATOS_DIR, 3,
         list(kratos_mesh_setups(self_contact_base(), "auto_roles__"))),
        # Every node listed: the faces Kratos generates are the skin csm's robust skin detection
        # finds (tests/it/seed_features.rs compares the two).
        ("kratos_simplest_patch_all_nodes", "%s/simplest_patch_all_nodes.mdpa" % REPO_KRATOS_DIR, 3,
         list(kratos_mesh_setups(dict(AUTO_BASE, contact_model_part={"0": ["All_Nodes"]}),
                                 "auto_roles__"))),
        # A generated self-contact scene: one C-shaped body whose arms face each other.
        ("kratos_folded_strip", "%s/folded_strip.mdpa" % SCENES_DIR, 3,
         list(kratos_mesh_setups(dict(AUTO_BASE, contact_model_part={"0": ["Contact_Fold"]}),
                                 "auto_roles__"))),
    ]


def self_contact_base():
    """The contact process Parameters of self_contact_test's ProjectParameters file."""
    path = os.path.join(ROOT, REPO_KRATOS_DIR, "self_contact_test_parameters.json")
    with open(path) as f:
        project = json.load(f)
    (process,) = [p for p in project["processes"]["contact_process_list"] if p["process_name"] == "ALMContactProcess"]
    return {k: v for k, v in process["Parameters"].items() if k != "search_parameters"}


def kratos_mesh_setups(base, prefix=""):
    for ts in KRATOS_TYPES:
        for check in CHECKS:
            for simple in (False, True):
                sp = {"type_search": ts, "check_gap": check, "simple_search": simple}
                setup = dict(base)
                setup["search_parameters"] = sp
                yield "%s%s__%s__%s" % (prefix, ts, check, "simple" if simple else "advanced"), setup


def interface_fixture(mesh, setup, interface, runs, error=None):
    """interface.json: the conditions of Contact/ContactSub0 after ExecuteInitialize, i.e. those
    InterfacePreprocessCondition generated, after NormalCheckProcess (the same in every run of the
    mesh; `setup` is the first run's). Where ExecuteInitialize raised, `error` is its message and
    the conditions are those generated before it raised."""
    obj = {"format": "csm-interface/1", "mesh": mesh, "setup": setup, "kratos": VERSION}
    if error is not None:
        obj["error"] = error
    obj.update({"slave_conditions": sum(1 for c in interface if c["slave"]),
                "master_conditions": sum(1 for c in interface if c["master"]),
                "same_in_runs": runs, "conditions": interface})
    return obj


def dumps_interface(obj):
    out = ["{"]
    items = list(obj.items())
    for i, (k, v) in enumerate(items):
        comma = "," if i + 1 < len(items) else ""
        if k == "conditions":
            out.append(" %s:[" % json.dumps(k))
            for j, c in enumerate(v):
                out.append("  %s%s" % (json.dumps(c, separators=(",", ":")), "," if j + 1 < len(v) else ""))
            out.append(" ]%s" % comma)
        else:
            out.append(" %s:%s%s" % (json.dumps(k), json.dumps(v, separators=(",", ":")), comma))
    out.append("}")
    return "\n".join(out) + "\n"


def cpp_setups():
    for name, params in CPP_TESTS.items():
        yield name, {"model_part_name": "Structure",
                     "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
                     "assume_master_slave": {"0": ["Parts_Slave"]},
                     "contact_type": "Frictionless",
                     "cpp_search_parameters": params,
                     "nodal_h": 1.0,
                     "process_info": dict(CPP_PROCESS_INFO)}


def dumps(obj):
    """Compact JSON with one line per pair / node entry (diff-friendly, small)."""
    def enc(v):
        return json.dumps(v, separators=(",", ":"))
    out = ["{"]
    items = list(obj.items())
    for i, (k, v) in enumerate(items):
        comma = "," if i + 1 < len(items) else ""
        if k in ("pairs", "nodes") and isinstance(v, dict):
            out.append(" %s:{" % enc(k))
            if k == "pairs":
                keys = list(v.items())
                for j, (pk, pv) in enumerate(keys):
                    out.append("  %s:{" % enc(pk))
                    entries = list(pv.items())
                    for e, (sk, sv) in enumerate(entries):
                        out.append("   %s:%s%s" % (enc(sk), enc(sv), "," if e + 1 < len(entries) else ""))
                    out.append("  }%s" % ("," if j + 1 < len(keys) else ""))
            else:
                entries = list(v.items())
                for e, (sk, sv) in enumerate(entries):
                    out.append("  %s:%s%s" % (enc(sk), enc(sv), "," if e + 1 < len(entries) else ""))
            out.append(" }%s" % comma)
        else:
            out.append(" %s:%s%s" % (enc(k), enc(v), comma))
    out.append("}")
    return "\n".join(out) + "\n"


def fixture(mesh, setup, result):
    obj = {"format": "csm-result/1", "mesh": mesh, "setup": setup, "kratos": VERSION}
    if "error" in result:
        obj["error"] = result["error"]
        obj["warnings"] = result["warnings"]
        return obj
    for k in ("pairs", "nodes", "paired_conditions", "master_slave_constraints", "warnings"):
        if k in result:
            obj[k] = result[k]
    obj["timings_s"] = {k: round(v, 6) for k, v in result["timings_s"].items()}
    return obj


def count_faces(mesh):
    model, mp = read_structure(mesh, [KM.DISPLACEMENT])
    if not mp.HasSubModelPart("Parts_Slave"):
        return (None, None, mp.NumberOfNodes(), mp.NumberOfElements())
    return (mp.GetSubModelPart("Parts_Slave").NumberOfConditions(),
            mp.GetSubModelPart("Parts_Master").NumberOfConditions(),
            mp.NumberOfNodes(), mp.NumberOfElements())


def count_elements(mesh):
    """(None, None, nodes, elements) of a Kratos test mesh (the faces are generated by Kratos)."""
    model, mp = read_structure(mesh, [KM.DISPLACEMENT])
    return (None, None, mp.NumberOfNodes(), mp.NumberOfElements())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "fixtures", "search"))
    ap.add_argument("--scenes", default="")
    ap.add_argument("--quick", action="store_true", help="one setup per scene (no files written)")
    args = ap.parse_args()
    KM.Logger.GetDefaultOutput().SetSeverity(KM.Logger.Severity.WARNING)
    only = set(s for s in args.scenes.split(",") if s)
    jobs = [(scene, "%s/%s.mdpa" % (SCENES_DIR, scene), dim, python_setups(scene)) for scene, dim in PYTHON_SCENES]
    jobs.append(("plane_cylinder_cpp", "%s/plane_cylinder_cpp.mdpa" % SCENES_DIR, 3, cpp_setups()))
    for short, mdpa, dim, base in kratos_meshes():
        jobs.append(("kratos_" + short, "%s/%s" % (KRATOS_TESTS_DIR, mdpa), dim, kratos_mesh_setups(base)))
    jobs.extend(repo_kratos_meshes())
    for scene, dim in (("stacked_blocks", 3), ("sphere_on_plate_mixed", 3), ("cylinder_on_block_2d", 2)):
        jobs.append((scene + "_processes", "%s/%s.mdpa" % (SCENES_DIR, scene), dim,
                     other_process_setups(scene)))
    # Every contact_model_part list empty: Kratos detects the skin into Structure.ContactSub0,
    # not Contact.ContactSub0, and raises (csm's kratos mode too; robust mode searches the skin).
    jobs.append(("skin_detection", "%s/3D_contact_simplest_patch_matching_test.mdpa" % REPO_KRATOS_DIR, 3,
                 [("skin__in_radius__mapping_check__advanced", {
                     "model_part_name": "Structure", "contact_type": "Frictionless",
                     "search_parameters": {"type_search": "in_radius"}})]))
    jobs.append(("condition_ids_10_20", "%s/condition_ids_10_20.mdpa" % REPO_KRATOS_DIR, 3,
                 [("in_radius__mapping_check__advanced", {
                     "model_part_name": "Structure", "contact_type": "Frictionless",
                     "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
                     "assume_master_slave": {"0": ["Parts_Slave"]},
                     "search_parameters": {"type_search": "in_radius"}})]))
    rows = []
    sizes = {}
    interfaces = {}
    start = time.perf_counter()
    failures = []
    for scene, mesh, dim, setups in jobs:
        if only and scene not in only:
            continue
        generated = scene.startswith("kratos_")
        sizes[scene] = count_elements(mesh) if generated else count_faces(mesh)
        os.makedirs(os.path.join(args.out, scene), exist_ok=True)
        for name, setup in setups:
            if scene == "plane_cylinder_cpp":
                result, info = run_cpp(mesh, name)
            elif "process" in setup:
                result, info = run_other_process(mesh, dim, setup)
            else:
                result, info = run_python(mesh, dim, setup)
            if generated and "interface" in info:
                if scene not in interfaces:
                    interfaces[scene] = interface_fixture(mesh, setup, info["interface"], [name],
                                                          info.get("interface_error"))
                elif interfaces[scene]["conditions"] == info["interface"]:
                    interfaces[scene]["same_in_runs"].append(name)
                else:
                    failures.append((scene, name, "generated interface differs from the first run's"))
            if not args.quick:
                with open(os.path.join(args.out, scene, name + ".json"), "w", newline="\n") as f:
                    f.write(dumps(fixture(mesh, setup, result)))
            if "error" in result:
                row = (scene, name, info.get("class", ""), None, None, None, None, None, result["error"])
            else:
                pairs = {(k, sid): v for k, ps in result["pairs"].items() for sid, v in ps.items()}
                row = (scene, name, info.get("class", ""), sum(1 for v in pairs.values() if v),
                       sum(len(v) for v in pairs.values()),
                       sum(1 for v in result["nodes"].values() if v["active"]),
                       result["paired_conditions"], result["timings_s"]["search"], info.get("crosscheck", ""))
                if not info.get("crosscheck_ok", True):
                    failures.append((scene, name, {k: v for k, v in info.items() if k != "interface"}))
            rows.append(row)
            print(fmt_row(row), flush=True)
            if args.quick:
                break
    total = time.perf_counter() - start
    for scene, obj in interfaces.items():
        nn, ne = sizes[scene][2:]
        sizes[scene] = (obj["slave_conditions"], obj["master_conditions"], nn, ne)
        if not args.quick:
            with open(os.path.join(args.out, scene, "interface.json"), "w", newline="\n") as f:
                f.write(dumps_interface(obj))
        print("%s: %d generated interface conditions (%d slave, %d master), same in %d runs" % (
            scene, len(obj["conditions"]), obj["slave_conditions"], obj["master_conditions"],
            len(obj["same_in_runs"])))
    if not args.quick and not only:
        write_readme(args.out, sizes, rows, total)
    print("total %.1f s" % total)
    for f in failures:
        print("CROSS-CHECK FAILED:", f, file=sys.stderr)
    return 1 if any(f[1].startswith("cpp_") or isinstance(f[2], str) for f in failures) else 0


def fmt_row(r):
    scene, name, cls, with_pairs, total_pairs, active, paired, search, note = r
    if with_pairs is None:
        return "%-22s %-40s %-38s ERROR: %s" % (scene, name, cls, note)
    return "%-22s %-40s %-38s %5d %6d %5d %6d %8.4f  %s" % (
        scene, name, cls, with_pairs, total_pairs, active, paired, search, note)


def write_readme(out, sizes, rows, total):
    lines = ["# Kratos search fixtures (generated by tools/kratos_fixtures_search.py — do not edit)", "",
             "Kratos %s, one thread. One JSON per scene and setup, format `csm-result/1` plus `mesh`, "
             "`setup` (the SETUP.json given to csm, exactly what Kratos got), `kratos`, and `error` "
             "where Kratos raised. Scenes: `tests/data/scenes/` (tools/gen_scenes.py), and the `kratos_*` "
             "scenes: Kratos' own test meshes in `../shared/data/kratos-tests/` (SOURCES.md there; "
             "`mesh` is relative to the repository root)." % VERSION, "",
             "## Scenes", "", "| scene | nodes | elements | slave faces | master faces |", "|---|---|---|---|---|"]
    for scene, (ns, nm, nn, ne) in sizes.items():
        if ns is None:  # a Kratos mesh whose run raised before generating anything
            lines.append("| %s | %d | %d | | |" % (scene, nn, ne))
        else:
            lines.append("| %s | %d | %d | %d | %d |" % (scene, nn, ne, ns, nm))
    lines += ["", "## Kratos test meshes (`kratos_*`)", "",
              "Their contact parts list nodes only, so ALMContactProcess.ExecuteInitialize generates the "
              "interface conditions itself (InterfacePreprocessCondition; reference §13); the slave/master "
              "faces above are the generated conditions. Setups: type_search {in_radius, "
              "in_radius_with_obb} x check_gap {no_check, direct_check, mapping_check} (always written) x "
              "simple_search, on top of:", "",
              "* `kratos_triquad` (`3D_contact_simplest_patch_matching_triquad_test.mdpa`): the "
              "ALMContactProcess Parameters of its own ProjectParameters file (slave Parts_Parts_Auto2, "
              "the tetrahedron block; `<3,3>` slave / `<4>` master, class suffix 3D3N4N).",
              "* `kratos_patch_nonmatching` (`3D_contact_patch_nonmatching_test.mdpa`; its ProjectParameters "
              "is an older format Kratos 10.4.4 rejects): contact part Contact_Part, slave Parts_Part_punch. "
              "Kratos 10.4.4 raises in NormalCheckProcess (CalculateUnitNormals over all root conditions): "
              "the mesh's 64 SurfaceLoadCondition3D4N are self-crossing quadrilaterals whose normal at the "
              "centre is zero. Every fixture carries that error; interface.json holds the 8 conditions "
              "generated before it.",
              "* `kratos_double_curvature_{triangle,quadrilateral}` (MembraneElement3D3N / 3D4N; the "
              "element geometries become the conditions): as test_dynamic_search.py (reference §20.2): "
              "contact part DISPLACEMENT_Displacement_Auto2 (all nodes), slave Parts_Parts_Auto1; no "
              "dynamic search. Listing DISPLACEMENT_Displacement_Auto1 as well would make Kratos generate "
              "the elements inside it a second time (duplicate conditions). NODAL_H is finite on every "
              "node (every node is in an element; Q33 does not apply).", "",
              "`kratos_*/interface.json` (format `csm-interface/1`): the conditions of "
              "Contact/ContactSub0 after ExecuteInitialize (after NormalCheckProcess), by id: "
              "`{\"id\", \"nodes\" (in order), \"slave\", \"master\"}` with flags true/false/null "
              "(null = never set), plus the counts, the first run's `setup`, `same_in_runs` (the runs that "
              "generated exactly the same list: all of them) and `error` where ExecuteInitialize raised. "
              "Properties without YOUNG_MODULUS make ALMVariablesCalculationProcess warn (it uses 0; the "
              "search does not use it)."]
    lines += ["", "## The seed's other processes and options", "",
              "`kratos_simplest_patch`, `kratos_simplest_patch_all_nodes`, `kratos_hertz`, "
              "`kratos_self_contact`, `kratos_self_contact_nodes_only`, `kratos_folded_strip` and "
              "`stacked_blocks/auto_roles__*`: roles decided automatically (`assume_master_slave` "
              "absent; Kratos raises where the contact parts have conditions of their own). "
              "`skin_detection`: every contact_model_part list empty (Kratos 10.4.4 raises). "
              "`*_processes`: MeshTyingProcess (`mesh_tying__*`) and MPCContactProcess (`mpc__*`, "
              "with `master_slave_constraints`). `condition_ids_10_20`: contact conditions 10 and "
              "20, which Kratos renumbers 1 and 2 (`pairs` holds Kratos' ids). Meshes: "
              "`tests/data/kratos/` (SOURCES.md there) and `tests/data/scenes/folded_strip.mdpa`."]
    lines += ["", "Total Kratos time (all runs, including reading and initialisation): %.1f s "
              "(timings vary from run to run; everything else is reproducible)." % total, "",
              "plane_cylinder_cpp calibration (reference §20.1): every INDEX_MAP as in the C++ test, only "
              "slave nodes 1 and 2 ACTIVE with NORMAL_GAP = -0.0011945660046527 (asserted by the script).",
              "",
              "note: `non-slave conditions with a map` = master conditions whose INDEX_MAP Kratos' octree "
              "path filled (No/DirectCheck); they are not in `pairs`, their paired conditions are in "
              "`paired`.", "",
              "## Summary", "",
              "slaves = slave conditions with at least one pair; pairs = INDEX_MAP entries; active = ACTIVE "
              "slave nodes; paired = conditions in ComputingContact; search = ExecuteInitializeSolutionStep (s).",
              "", "| scene | setup | Kratos class | slaves | pairs | active | paired | search s | note |",
              "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        scene, name, cls, with_pairs, total_pairs, active, paired, search, note = r
        if with_pairs is None:
            lines.append("| %s | %s | %s | | | | | | error: %s |" % (scene, name, cls, note.replace("|", "/")))
        else:
            lines.append("| %s | %s | %s | %d | %d | %d | %d | %.4f | %s |" % (
                scene, name, cls, with_pairs, total_pairs, active, paired, search, note))
    with open(os.path.join(out, "README.md"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
