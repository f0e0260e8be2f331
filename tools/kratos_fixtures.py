"""Reference fixtures from Kratos 10.4.4 for csm's tests (run by `cargo xtask fixtures`).

Drives Kratos with one thread on the meshes in ../shared/data/kratos-tests and writes JSON into
tests/fixtures/. CI never runs this: the fixtures are committed data.

Fixtures written:
  nodal_h/<mesh>.json  NODAL_H of every node after FindNodalHProcess on the root model part
                       (Kratos' reading of §17.3 / Q40), keyed by node id; nodes in no element
                       are written as null (Kratos leaves DBL_MAX).
  faces.json           the node order of the conditions InterfacePreprocessCondition generates
                       on one element of each solid kind (Kratos' GenerateBoundariesEntities
                       order), as local node indices.
  normals/<mesh>.json  after NormalCalculationUtils().CalculateUnitNormals on the root model
                       part (conditions): the condition NORMAL (non-historical) per condition id
                       and the nodal NORMAL (historical) per node id of the conditions.

Usage: OMP_NUM_THREADS=1 python tools/kratos_fixtures.py [--shared ../shared] [--out tests/fixtures]
"""
import argparse
import json
import os
import sys

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

import KratosMultiphysics as KM  # noqa: E402
import KratosMultiphysics.StructuralMechanicsApplication  # noqa: E402,F401
import KratosMultiphysics.ContactStructuralMechanicsApplication  # noqa: E402,F401

MESHES = [
    "3D_contact_patch_nonmatching_test",
    "3D_contact_simplest_patch_matching_triquad_test",
    "test_double_curvature_integration_triangle",
    "test_double_curvature_integration_quadrilateral",
]


def read(path_without_ext):
    model = KM.Model()
    mp = model.CreateModelPart("Structure", 2)
    for var in (KM.DISPLACEMENT, KM.NORMAL, KM.NODAL_H):
        mp.AddNodalSolutionStepVariable(var)
    KM.ModelPartIO(path_without_ext).ReadModelPart(mp)
    return model, mp


def vec(v):
    return [float(v[0]), float(v[1]), float(v[2])]


FACE_CASES = {
    "Tetrahedra3D4": ("Element3D4N", [1, 2, 4, 5], 3),
    "Hexahedra3D8": ("Element3D8N", [1, 2, 3, 4, 5, 6, 7, 8], 3),
    "Prism3D6": ("Element3D6N", [1, 2, 4, 5, 6, 8], 3),
    "Triangle2D3": ("Element2D3N", [1, 2, 4], 2),
    "Quadrilateral2D4": ("Element2D4N", [1, 2, 3, 4], 2),
}
CUBE = {1: (0, 0, 0), 2: (1, 0, 0), 3: (1, 1, 0), 4: (0, 1, 0),
        5: (0, 0, 1), 6: (1, 0, 1), 7: (1, 1, 1), 8: (0, 1, 1)}


def faces():
    import KratosMultiphysics.ContactStructuralMechanicsApplication as CSMA
    out = {}
    for name, (element, ids, dim) in FACE_CASES.items():
        model = KM.Model()
        mp = model.CreateModelPart("M")
        mp.ProcessInfo[KM.DOMAIN_SIZE] = dim
        for i in ids:
            mp.CreateNewNode(i, *CUBE[i])
        mp.CreateNewElement(element, 1, ids, mp.CreateNewProperties(1))
        part = mp.CreateSubModelPart("P")
        part.AddNodes(ids)
        for node in mp.Nodes:
            node.Set(KM.INTERFACE, True)
        params = KM.Parameters('{"simplify_geometry": false}')
        CSMA.InterfacePreprocessCondition(mp).GenerateInterfacePart(part, params)
        out[name] = [[ids.index(n.Id) for n in c.GetNodes()] for c in mp.Conditions]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared"))
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "tests", "fixtures"))
    args = ap.parse_args()
    data = os.path.join(args.shared, "data", "kratos-tests")
    for sub in ("nodal_h", "normals"):
        os.makedirs(os.path.join(args.out, sub), exist_ok=True)
    write(os.path.join(args.out, "faces.json"),
          {"kratos": KM.KratosGlobals.Kernel.Version(), "faces": faces()})
    for name in MESHES:
        model, mp = read(os.path.join(data, name))
        KM.FindNodalHProcess(mp).Execute()
        h = {}
        for node in mp.Nodes:
            value = node.GetSolutionStepValue(KM.NODAL_H)
            h[str(node.Id)] = None if value > 1e300 else repr_float(value)
        write(os.path.join(args.out, "nodal_h", name + ".json"),
              {"mesh": name, "kratos": KM.KratosGlobals.Kernel.Version(), "nodal_h": h})
        if mp.NumberOfConditions() > 0:
            try:
                KM.NormalCalculationUtils().CalculateUnitNormals(mp, True)
            except RuntimeError as e:
                first = [l for l in str(e).splitlines() if "ERROR" in l or "Error:" in l]
                write(os.path.join(args.out, "normals", name + ".json"),
                      {"mesh": name, "kratos": KM.KratosGlobals.Kernel.Version(),
                       "error": first[-1].strip() if first else str(e)[:200]})
                continue
            conds = {str(c.Id): vec(c.GetValue(KM.NORMAL)) for c in mp.Conditions}
            ids = sorted({n.Id for c in mp.Conditions for n in c.GetNodes()})
            nodes = {str(i): vec(mp.GetNode(i).GetSolutionStepValue(KM.NORMAL)) for i in ids}
            write(os.path.join(args.out, "normals", name + ".json"),
                  {"mesh": name, "kratos": KM.KratosGlobals.Kernel.Version(),
                   "conditions": conds, "nodes": nodes})
        print(f"{name}: {mp.NumberOfNodes()} nodes, {mp.NumberOfElements()} elements, "
              f"{mp.NumberOfConditions()} conditions", file=sys.stderr)


def repr_float(x):
    return float(x)


def write(path, obj):
    with open(path, "w") as f:
        json.dump(obj, f, indent=1, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
