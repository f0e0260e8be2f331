"""Reference fixtures from Kratos 10.4.4 for stages 1 and 2 of csm's search.

Stage 1 is Kratos' `InterfacePreprocessCondition.GenerateInterfacePart` (reference §13), stage 2
its `NormalCheckProcess` (reference §14). CI never runs this script: its output is committed data.

Every fixture carries its input model (nodes, elements, conditions, properties, flags), so the
Rust tests rebuild the model in code without a mesh reader (csm-search may not use csm-io).

Fixtures written:
  interface/<mesh>.json      input model of a Kratos test mesh (INTERFACE on the contact part's
                             nodes, MASTER/SLAVE as stage 0 sets them), and for simplify_geometry
                             false and true: every root condition after GenerateInterfacePart
                             (id, name, geometry, node ids, SLAVE/MASTER tri-state, properties
                             id), the part's condition ids and the properties blocks.
                             One extra case, `contact_property_id.json`, uses a fixed property id.
  normal_check/<case>.json   input model (for the Kratos meshes: the model after
                             GenerateInterfacePart without simplification) and, after
                             NormalCheckProcess: node order of every element and condition, the
                             condition NORMAL, the nodal NORMAL of condition nodes and the MARKER
                             tri-state of nodes, elements and conditions.

Usage (from the repository root):
  OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive /work/kratos-venv/bin/python \
      tools/kratos_fixtures_interface.py [--shared ../shared] [--out tests/fixtures]
"""
import argparse
import json
import os
import sys

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

import KratosMultiphysics as KM  # noqa: E402
import KratosMultiphysics.StructuralMechanicsApplication  # noqa: E402,F401
import KratosMultiphysics.ContactStructuralMechanicsApplication as CSMA  # noqa: E402

# mesh, contact part, slave part (stage 0's assume_master_slave).
# 3D_contact_patch_nonmatching_test_parameters.json (old format) names no assume_master_slave;
# the punch is the slave side, as in the newer versions of that test.
MESHES = [
    ("3D_contact_patch_nonmatching_test", "Contact_Part", "Parts_Part_punch"),
    ("3D_contact_simplest_patch_matching_triquad_test", "DISPLACEMENT_Displacement_Auto3",
     "Parts_Parts_Auto2"),
]
PROPERTY_VARS = [("YOUNG_MODULUS", KM.YOUNG_MODULUS), ("THICKNESS", KM.THICKNESS),
                 ("FRICTION_COEFFICIENT", KM.FRICTION_COEFFICIENT),
                 ("DENSITY", KM.DENSITY), ("POISSON_RATIO", KM.POISSON_RATIO)]


def tri(entity, flag):
    return entity.Is(flag) if entity.IsDefined(flag) else None


def vec(v):
    return [float(v[0]), float(v[1]), float(v[2])]


def new_model(dim):
    model = KM.Model()
    mp = model.CreateModelPart("Structure", 2)
    for var in (KM.DISPLACEMENT, KM.NORMAL):
        mp.AddNodalSolutionStepVariable(var)
    mp.ProcessInfo[KM.DOMAIN_SIZE] = dim
    return model, mp


def properties_of(mp):
    out = {}
    for p in mp.Properties:
        vals = {}
        for name, var in PROPERTY_VARS:
            if p.Has(var):
                vals[name] = p.GetValue(var)
        out[str(p.Id)] = vals
    return out


def dump_input(mp, part_nodes):
    """The whole model as plain data (nodes of entities and of the part only; flags that are
    defined)."""
    used = set(part_nodes)
    for e in list(mp.Elements) + list(mp.Conditions):
        used.update(n.Id for n in e.GetNodes())
    nodes = [[n.Id, n.X, n.Y, n.Z] for n in mp.Nodes if n.Id in used]
    flags = {}
    for n in mp.Nodes:
        if n.Id not in used:
            continue
        f = {k: tri(n, v) for k, v in (("INTERFACE", KM.INTERFACE), ("SLAVE", KM.SLAVE),
                                       ("MASTER", KM.MASTER), ("MARKER", KM.MARKER))}
        f = {k: v for k, v in f.items() if v is not None}
        if f:
            flags[str(n.Id)] = f
    return {
        "domain_size": mp.ProcessInfo[KM.DOMAIN_SIZE],
        "nodes": nodes,
        "node_flags": flags,
        "elements": [[e.Id, str(e.GetGeometry().GetGeometryType()).split("Kratos_")[-1], e.Properties.Id, [n.Id for n in e.GetNodes()]]
                     for e in mp.Elements],
        "conditions": [[c.Id, str(c.GetGeometry().GetGeometryType()).split("Kratos_")[-1], c.Properties.Id,
                        [n.Id for n in c.GetNodes()]] for c in mp.Conditions],
        "properties": properties_of(mp),
        "element_flags": {str(e.Id): {"MARKER": tri(e, KM.MARKER)} for e in mp.Elements
                          if tri(e, KM.MARKER) is not None},
        "condition_flags": {str(c.Id): {"MARKER": tri(c, KM.MARKER)} for c in mp.Conditions
                            if tri(c, KM.MARKER) is not None},
    }


def read_mesh(data, name, part_name, slave_name):
    model, mp = new_model(3)
    KM.ModelPartIO(os.path.join(data, name)).ReadModelPart(mp)
    part = mp.GetSubModelPart(part_name)
    slave = mp.GetSubModelPart(slave_name)
    # Stage 0 (reference §1.3): part nodes MASTER, slave-part nodes SLAVE, INTERFACE on the part.
    for n in part.Nodes:
        n.Set(KM.SLAVE, False)
        n.Set(KM.MASTER, True)
    for n in slave.Nodes:
        n.Set(KM.SLAVE, True)
        n.Set(KM.MASTER, False)
    for n in part.Nodes:
        n.Set(KM.INTERFACE, True)
    return model, mp, part


def generated(mp, part):
    return {
        "conditions": [{"id": c.Id, "geometry": str(c.GetGeometry().GetGeometryType()).split("Kratos_")[-1],
                        "nodes": [n.Id for n in c.GetNodes()],
                        "slave": tri(c, KM.SLAVE), "master": tri(c, KM.MASTER),
                        "properties": c.Properties.Id} for c in mp.Conditions],
        "part_conditions": sorted(c.Id for c in part.Conditions),
        "properties": properties_of(mp),
    }


def interface_case(data, name, part_name, slave_name):
    out = {"kratos": KM.KratosGlobals.Kernel.Version(), "mesh": name, "part": part_name,
           "slave_part": slave_name}
    for simplify in (False, True):
        model, mp, part = read_mesh(data, name, part_name, slave_name)
        if not simplify:
            out["input"] = dump_input(mp, [n.Id for n in part.Nodes])
            out["input"]["part_nodes"] = [n.Id for n in part.Nodes]
        params = KM.Parameters(json.dumps({"simplify_geometry": simplify}))
        CSMA.InterfacePreprocessCondition(mp).GenerateInterfacePart(part, params)
        out["simplify_" + str(simplify).lower()] = generated(mp, part)
    return out


def contact_property_case(data):
    """contact_property_id != 0 on the triquad mesh (two element properties, 19 elements)."""
    name, part_name, slave_name = MESHES[1]
    model, mp, part = read_mesh(data, name, part_name, slave_name)
    params = KM.Parameters('{"simplify_geometry": false, "contact_property_id": 7}')
    try:
        CSMA.InterfacePreprocessCondition(mp).GenerateInterfacePart(part, params)
        res = generated(mp, part)
    except RuntimeError as e:
        lines = [l.strip() for l in str(e).splitlines() if l.strip()]
        res = {"error": lines[0] if lines else str(e)[:200],
               "conditions_before_error": generated(mp, part)["conditions"]}
    return {"kratos": KM.KratosGlobals.Kernel.Version(), "mesh": name, "part": part_name,
            "contact_property_id": 7, "result": res}


# ---------------------------------------------------------------------------------------------
# Normal check


def normal_check_result(mp):
    ids = sorted({n.Id for c in mp.Conditions for n in c.GetNodes()})
    return {
        "elements": [[e.Id, [n.Id for n in e.GetNodes()]] for e in mp.Elements],
        "conditions": [[c.Id, [n.Id for n in c.GetNodes()]] for c in mp.Conditions],
        "condition_normals": {str(c.Id): vec(c.GetValue(KM.NORMAL)) for c in mp.Conditions},
        "nodal_normals": {str(i): vec(mp.GetNode(i).GetSolutionStepValue(KM.NORMAL))
                          for i in ids},
        "marker": {
            "nodes": {str(n.Id): tri(n, KM.MARKER) for n in mp.Nodes},
            "elements": {str(e.Id): tri(e, KM.MARKER) for e in mp.Elements},
            "conditions": {str(c.Id): tri(c, KM.MARKER) for c in mp.Conditions},
        },
    }


def run_normal_check(mp, case):
    inp = dump_input(mp, [])
    try:
        CSMA.NormalCheckProcess(mp, KM.Parameters('{"length_proportion": 0.1}')).Execute()
        res = normal_check_result(mp)
    except RuntimeError as e:
        lines = [l.strip() for l in str(e).splitlines() if "Error:" in l]
        res = {"error": lines[-1] if lines else str(e)[:200]}
    return {"kratos": KM.KratosGlobals.Kernel.Version(), "case": case, "input": inp,
            "result": res}


def grid_nodes(mp, nx, ny, nz, first=1, x0=0.0):
    """Nodes of an (nx+1)×(ny+1)×(nz+1) grid, ids from `first` with x fastest; returns
    id(i, j, k). The block is a frustum, wider at the bottom (so the point just below a top
    node is inside the body), and slightly irregular so nothing is symmetric by accident."""
    def nid(i, j, k):
        return first + i + (nx + 1) * (j + (ny + 1) * k)
    for k in range(nz + 1):
        s = 1.0 + 0.2 * (nz - k)
        for j in range(ny + 1):
            for i in range(nx + 1):
                mp.CreateNewNode(nid(i, j, k), x0 + (i - 0.5 * nx) * s + 0.05 * j * k,
                                 (j - 0.5 * ny) * s + 0.03 * i, 0.7 * k + 0.02 * i * j)
    return nid


HEX_FLIP = [4, 5, 6, 7, 0, 1, 2, 3]  # swaps bottom and top: a mirrored (inverted) hexahedron


def hexa_conn(nid, i, j):
    return [nid(i, j, 0), nid(i + 1, j, 0), nid(i + 1, j + 1, 0), nid(i, j + 1, 0),
            nid(i, j, 1), nid(i + 1, j, 1), nid(i + 1, j + 1, 1), nid(i, j + 1, 1)]


def top_bottom(nid, i, j):
    """Outward top and bottom quadrilaterals of cell (i, j) of a positive hexahedron."""
    top = [nid(i, j, 1), nid(i + 1, j, 1), nid(i + 1, j + 1, 1), nid(i, j + 1, 1)]
    bottom = [nid(i, j, 0), nid(i, j + 1, 0), nid(i + 1, j + 1, 0), nid(i + 1, j, 0)]
    return top, bottom


def hexa_block():
    """Two bodies. A: 2×2×1 hexahedra (nodes 1..18, elements 1..4) with SurfaceCondition3D4N
    on the top (11..14, all pointing inwards) and the bottom (21..24, outwards). B: one
    mirrored (inverted) hexahedron (nodes 101..108, element 5) whose top and bottom conditions
    (31, 32) were generated from the mirrored element (so they point inwards too). INTERFACE on
    every condition node; MARKER preset on nodes 1 (true), 2 (false), 101 (true), element 3
    (true) and condition 21 (false)."""
    model, mp = new_model(3)
    nid = grid_nodes(mp, 2, 2, 1)
    prop = mp.CreateNewProperties(1)
    eid = 0
    for j in range(2):
        for i in range(2):
            eid += 1
            mp.CreateNewElement("Element3D8N", eid, hexa_conn(nid, i, j), prop)
    for j in range(2):
        for i in range(2):
            top, bottom = top_bottom(nid, i, j)
            mp.CreateNewCondition("SurfaceCondition3D4N", 11 + i + 2 * j, top[::-1], prop)
            mp.CreateNewCondition("SurfaceCondition3D4N", 21 + i + 2 * j, bottom, prop)
    nid_b = grid_nodes(mp, 1, 1, 1, first=101, x0=5.0)
    conn = hexa_conn(nid_b, 0, 0)
    mp.CreateNewElement("Element3D8N", 5, [conn[k] for k in HEX_FLIP], prop)
    top, bottom = top_bottom(nid_b, 0, 0)
    mp.CreateNewCondition("SurfaceCondition3D4N", 31, top[::-1], prop)
    mp.CreateNewCondition("SurfaceCondition3D4N", 32, bottom[::-1], prop)
    for c in mp.Conditions:
        for n in c.GetNodes():
            n.Set(KM.INTERFACE, True)
    mp.GetNode(1).Set(KM.MARKER, True)
    mp.GetNode(2).Set(KM.MARKER, False)
    mp.GetNode(101).Set(KM.MARKER, True)
    mp.GetElement(3).Set(KM.MARKER, True)
    mp.GetCondition(21).Set(KM.MARKER, False)
    return model, mp


# Kuhn split of a cube into 6 positively oriented tetrahedra (local cube corners 0..7 as
# (i, j, k) bits: corner c = i + 2j + 4k).
KUHN = [(0, 1, 3, 7), (0, 3, 2, 7), (0, 2, 6, 7), (0, 6, 4, 7), (0, 4, 5, 7), (0, 5, 1, 7)]


def tetra_block():
    """Two separate cubes of 6 tetrahedra (Kuhn split) with SurfaceCondition3D3N on their top
    faces; INTERFACE on the condition nodes. Cube A (nodes 1..8, elements 1..6, conditions
    101, 102): top conditions point inwards. Cube B (nodes 11..18, elements 7..12, conditions
    103, 104): tetrahedron 9 has two nodes swapped (inverted), tetrahedron 10 is written with
    std::reverse of a correct order (same orientation), conditions point outwards."""
    model, mp = new_model(3)
    prop = mp.CreateNewProperties(1)
    eid = 0
    cid = 100
    for body, (first, x0) in enumerate(((1, 0.0), (11, 3.0))):
        nid = grid_nodes(mp, 1, 1, 1, first=first, x0=x0)
        corner = [nid(c & 1, (c >> 1) & 1, (c >> 2) & 1) for c in range(8)]
        for t in KUHN:
            eid += 1
            conn = [corner[c] for c in t]
            if eid == 9:
                conn = [conn[0], conn[2], conn[1], conn[3]]
            if eid == 10:
                conn = conn[::-1]
            mp.CreateNewElement("Element3D4N", eid, conn, prop)
        c = [corner[4], corner[5], corner[7], corner[6]]
        for tri_nodes in ([c[0], c[1], c[2]], [c[0], c[2], c[3]]):
            cid += 1
            if body == 0:
                tri_nodes = tri_nodes[::-1]
            mp.CreateNewCondition("SurfaceCondition3D3N", cid, tri_nodes, prop)
    for c in mp.Conditions:
        for n in c.GetNodes():
            n.Set(KM.INTERFACE, True)
    return model, mp


def plane_2d():
    """2D, three separate bodies with LineCondition2D2N on their bottom edges (y = 0),
    INTERFACE on the condition nodes. A: quadrilateral 1, clockwise (inverted), condition 31
    generated from it (inwards). B: quadrilateral 2 and triangle 3, conditions 32, 33 inwards.
    C: triangle 4, clockwise, condition 34 from it (inwards)."""
    model, mp = new_model(2)
    # Body B is wider at the top, so the point just above each bottom node is inside it.
    pts = {1: (0, 0), 2: (1, 0), 5: (0, 1), 6: (1, 1.1),
           11: (3, 0), 12: (4, 0), 13: (5, 0), 16: (4.2, 1.1), 17: (2.8, 1), 18: (5.3, 1),
           21: (7, 0), 22: (8, 0), 23: (7.5, 1)}
    for i, (x, y) in pts.items():
        mp.CreateNewNode(i, x, y, 0.0)
    prop = mp.CreateNewProperties(1)
    mp.CreateNewElement("Element2D4N", 1, [1, 5, 6, 2], prop)  # clockwise
    mp.CreateNewElement("Element2D4N", 2, [11, 12, 16, 17], prop)
    mp.CreateNewElement("Element2D3N", 3, [12, 13, 18], prop)
    mp.CreateNewElement("Element2D3N", 4, [21, 23, 22], prop)  # clockwise
    # The normal of a line is right of its direction: going +x gives (0, -1), outwards here.
    mp.CreateNewCondition("LineCondition2D2N", 31, [2, 1], prop)
    mp.CreateNewCondition("LineCondition2D2N", 32, [12, 11], prop)
    mp.CreateNewCondition("LineCondition2D2N", 33, [13, 12], prop)
    mp.CreateNewCondition("LineCondition2D2N", 34, [22, 21], prop)
    for c in mp.Conditions:
        for n in c.GetNodes():
            n.Set(KM.INTERFACE, True)
    return model, mp


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared"))
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "tests", "fixtures"))
    args = ap.parse_args()
    data = os.path.join(args.shared, "data", "kratos-tests")
    for sub in ("interface", "normal_check"):
        os.makedirs(os.path.join(args.out, sub), exist_ok=True)
    for name, part_name, slave_name in MESHES:
        write(os.path.join(args.out, "interface", name + ".json"),
              interface_case(data, name, part_name, slave_name))
        model, mp, part = read_mesh(data, name, part_name, slave_name)
        CSMA.InterfacePreprocessCondition(mp).GenerateInterfacePart(
            part, KM.Parameters('{"simplify_geometry": false}'))
        write(os.path.join(args.out, "normal_check", name + ".json"), run_normal_check(mp, name))
        print(name, file=sys.stderr)
    write(os.path.join(args.out, "interface", "contact_property_id.json"),
          contact_property_case(data))
    for case, build in (("hexa_block", hexa_block), ("tetra_block", tetra_block),
                        ("plane_2d", plane_2d)):
        model, mp = build()
        write(os.path.join(args.out, "normal_check", case + ".json"), run_normal_check(mp, case))
        print(case, file=sys.stderr)


def write(path, obj):
    with open(path, "w") as f:
        json.dump(obj, f, indent=None, separators=(",", ":"), sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
