"""Kratos and csm side by side on one Kratos ModelPart.

Reads a mesh with Kratos, takes its nodes, elements, conditions and sub model parts into
arrays, runs Kratos' own contact search (ALMContactProcess: ExecuteInitialize and
ExecuteInitializeSolutionStep) and csm's on those arrays, and prints both: pairs, ACTIVE
flags, NORMAL_GAP and times, and where they differ.

    pip install KratosMultiphysics==10.4.4 KratosStructuralMechanicsApplication==10.4.4 \\
        KratosContactStructuralMechanicsApplication==10.4.4
    pip install .          # csm, from the root of this repository
    OMP_NUM_THREADS=1 python examples/kratos_compare.py tests/data/scenes/stacked_blocks.mdpa

`--setup SETUP.json` gives the contact process's Parameters (default: the parts
`Parts_Slave` and `Parts_Master`, ALM defaults). Not run in CI (CI has no Kratos); the
fixtures under `tests/fixtures/` hold the same comparison for every scene and setup.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections import defaultdict

import numpy as np

import KratosMultiphysics as KM
import KratosMultiphysics.StructuralMechanicsApplication  # noqa: F401 (registers elements)
import KratosMultiphysics.ContactStructuralMechanicsApplication as CSMA
from KratosMultiphysics.ContactStructuralMechanicsApplication import alm_contact_process

import csm

DEFAULT_SETUP = {
    "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
    "assume_master_slave": {"0": ["Parts_Slave"]},
}
# The nodal variables a contact solver adds before reading the mesh.
VARIABLES = [KM.DISPLACEMENT, KM.REACTION, KM.VOLUME_ACCELERATION, KM.VELOCITY, KM.ACCELERATION,
             KM.NORMAL, KM.NODAL_H, CSMA.WEIGHTED_GAP, CSMA.LAGRANGE_MULTIPLIER_CONTACT_PRESSURE,
             CSMA.WEIGHTED_SCALAR_RESIDUAL]
# Kratos' "not mapped" NORMAL_GAP.
NOT_MAPPED = 1.0e12


def geometry_name(entity) -> str:
    """Kratos' geometry name (`Kratos_Triangle3D3` -> `Triangle3D3`), csm's kind names."""
    return str(entity.GetGeometry().GetGeometryType()).split("Kratos_")[-1]


def model_part_arrays(mp: KM.ModelPart) -> dict:
    """The ModelPart's mesh as the keyword arguments of `csm.Mesh.from_arrays`."""
    nodes = sorted(mp.Nodes, key=lambda n: n.Id)

    def by_kind(entities):
        groups = defaultdict(lambda: ([], [], []))
        for e in sorted(entities, key=lambda e: e.Id):
            ids, conn, props = groups[geometry_name(e)]
            ids.append(e.Id)
            conn.append([n.Id for n in e.GetNodes()])
            props.append(e.Properties.Id)
        arrays = {k: (np.array(i), np.array(c)) for k, (i, c, _) in groups.items()}
        properties = {k: np.array(p) for k, (_, _, p) in groups.items()}
        return arrays, properties

    parts = {}

    def add_parts(part, prefix=""):
        for sub in part.SubModelParts:
            path = prefix + sub.Name
            parts[path] = {
                "nodes": np.array(sorted(n.Id for n in sub.Nodes), dtype=np.int64),
                "elements": np.array(sorted(e.Id for e in sub.Elements), dtype=np.int64),
                "conditions": np.array(sorted(c.Id for c in sub.Conditions), dtype=np.int64),
            }
            add_parts(sub, path + ".")

    add_parts(mp)
    elements, element_properties = by_kind(mp.Elements)
    conditions, condition_properties = by_kind(mp.Conditions)
    return {
        "node_ids": np.array([n.Id for n in nodes]),
        "points": np.array([[n.X, n.Y, n.Z] for n in nodes]),
        "elements": elements,
        "conditions": conditions,
        "parts": parts,
        "properties": {"elements": element_properties, "conditions": condition_properties},
        "domain_size": mp.ProcessInfo[KM.DOMAIN_SIZE],
    }


def kratos_search(model: KM.Model, mp: KM.ModelPart, setup: dict):
    """Kratos' search: {(slave, master)}, {node id: (normal gap or NaN, active)}, seconds."""
    for var, value in ((KM.STEP, 1), (KM.TIME, 1.0), (KM.DELTA_TIME, 1.0)):
        mp.ProcessInfo[var] = value
    process = alm_contact_process.ALMContactProcess(model, KM.Parameters(json.dumps(setup)))
    start = time.perf_counter()
    process.ExecuteInitialize()
    process.ExecuteInitializeSolutionStep()
    seconds = time.perf_counter() - start
    contact = mp.GetSubModelPart("Contact")
    by_nodes = {tuple(sorted(n.Id for n in c.GetNodes())): c.Id for c in contact.Conditions}
    key = lambda g: tuple(sorted(g[i].Id for i in range(len(g))))
    pairs = set()
    for paired in mp.GetSubModelPart("ComputingContact").Conditions:
        g = paired.GetGeometry()
        pairs.add((by_nodes[key(g.GetGeometryPart(0))], by_nodes[key(g.GetGeometryPart(1))]))
    nodes = {}
    for n in contact.Nodes:
        if n.Is(KM.SLAVE):
            gap = n.GetValue(CSMA.NORMAL_GAP) if n.Has(CSMA.NORMAL_GAP) else float("nan")
            nodes[n.Id] = (float("nan") if abs(gap) >= NOT_MAPPED * 0.999 else gap, n.Is(KM.ACTIVE))
    return pairs, nodes, seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", help="a Kratos .mdpa file")
    parser.add_argument("--setup", help="the contact process's Parameters (JSON)")
    parser.add_argument("--threads", type=int, default=None, help="csm's threads (default: all)")
    args = parser.parse_args()
    setup = DEFAULT_SETUP
    if args.setup:
        with open(args.setup, encoding="utf-8") as f:
            setup = json.load(f)

    model = KM.Model()
    mp = model.CreateModelPart(setup.get("model_part_name", "Structure"), 2)
    for var in VARIABLES:
        mp.AddNodalSolutionStepVariable(var)
    KM.ModelPartIO(os.path.splitext(args.mesh)[0]).ReadModelPart(mp)
    mp.ProcessInfo[KM.DOMAIN_SIZE] = 2 if all(
        geometry_name(e).endswith(("2D2", "2D3", "2D4")) for e in mp.Elements
    ) and mp.NumberOfElements() else 3

    # csm first, on arrays taken before Kratos' process adds its parts and conditions.
    arrays = model_part_arrays(mp)
    start = time.perf_counter()
    result = csm.search(csm.Mesh.from_arrays(**arrays), setup, threads=args.threads)
    csm_seconds = time.perf_counter() - start
    renumber = result.kratos_condition_ids
    csm_pairs = {(renumber.get(s, s), renumber.get(m, m)) for p in result.pairs.values() for s, m in p.tolist()}
    csm_nodes = {i: (g, a) for i, g, a in zip(result.node_ids.tolist(), result.normal_gap.tolist(), result.active.tolist())}

    kratos_pairs, kratos_nodes, kratos_seconds = kratos_search(model, mp, setup)

    print(f"{args.mesh}: Kratos {kratos_seconds:.3f} s (initialize + search), csm {csm_seconds:.3f} s (all of it)")
    print(f"pairs: Kratos {len(kratos_pairs)}, csm {len(csm_pairs)}, "
          f"only Kratos {len(kratos_pairs - csm_pairs)}, only csm {len(csm_pairs - kratos_pairs)}")
    active_k = {i for i, (_, a) in kratos_nodes.items() if a}
    active_c = {i for i, (_, a) in csm_nodes.items() if a}
    print(f"ACTIVE nodes: Kratos {len(active_k)}, csm {len(active_c)}, differing {len(active_k ^ active_c)}")
    common = sorted(set(kratos_nodes) & set(csm_nodes))
    k = np.array([kratos_nodes[i][0] for i in common])
    c = np.array([csm_nodes[i][0] for i in common])
    both = ~np.isnan(k) & ~np.isnan(c)
    worst = float(np.max(np.abs(k[both] - c[both]), initial=0.0))
    print(f"NORMAL_GAP on {len(common)} slave nodes: largest difference {worst:.3e}, "
          f"NaN (never mapped) differs on {int(np.sum(np.isnan(k) != np.isnan(c)))}")
    print(f"{'node':>8} {'Kratos gap':>14} {'csm gap':>14}  active (K/c)")
    for i in common[:10]:
        (kg, ka), (cg, ca) = kratos_nodes[i], csm_nodes[i]
        print(f"{i:>8} {kg:>14.6e} {cg:>14.6e}  {ka!s:>5}/{ca!s:<5}")
    same = kratos_pairs == csm_pairs and active_k == active_c
    print("identical pairs and flags" if same else "DIFFERENT (see above)")


if __name__ == "__main__":
    main()
