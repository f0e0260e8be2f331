#!/usr/bin/env python3
"""Generates the small Gmsh test meshes of csm-io into tests/data/ (deterministic).

Run from the repository root:  python3 tools/gen_meshes.py   (needs `pip install gmsh`)

Meshes:
- boxes.*: two stacked, non-conforming boxes (3D). The lower box [0,1]x[0,1]x[0,0.5] is meshed
  with tetrahedra, the upper box [0.125,0.875]^2x[0.5,1] with hexahedra (transfinite, recombined).
  Physical groups: surfaces "slave" (bottom of the upper box), "master" (top of the lower box),
  "interface" (both: in MSH 2.2 these faces are listed twice), volumes "block_lower",
  "block_upper", and an unnamed curve group (tag 7: one edge of the master face; its nodes only).
  Written as MSH 4.1 ASCII/binary and 2.2 ASCII/binary, and as boxes.mdpa (same ids).
- rects.*: the 2D analogue (triangles below, quadrilaterals above, lines "slave"/"master"),
  the same four MSH variants and rects.mdpa.
- boxes_order2.msh / boxes_order2_serendipity.msh: the boxes at second order (Tetrahedra3D10 +
  Hexahedra3D27 + Triangle/Quadrilateral 3D6/3D9 faces; and Hexahedra3D20 + Quadrilateral3D8),
  MSH 4.1 ASCII, to check the node permutation Gmsh -> Kratos.

Every node is snapped to a multiple of 1/1024 so that the ASCII files (printed with %.16g)
hold exactly the binary files' doubles.
"""
import os
import gmsh

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data")
Q = 1024.0


def snap():
    tags, coords, _ = gmsh.model.mesh.getNodes()
    for i, t in enumerate(tags):
        c = [round(coords[3 * i + k] * Q) / Q for k in range(3)]
        gmsh.model.mesh.setNode(int(t), c, [])


def entity_at(dim, pred):
    for d, t in gmsh.model.getEntities(dim):
        if pred(gmsh.model.getBoundingBox(d, t)):
            return t
    raise RuntimeError("entity not found")


def save_all(stem, versions=("4.1", "2.2"), binaries=(0, 1)):
    for v in versions:
        for b in binaries:
            gmsh.option.setNumber("Mesh.MshFileVersion", float(v))
            gmsh.option.setNumber("Mesh.Binary", b)
            suffix = "%s_%s" % (v.replace(".", ""), "bin" if b else "ascii")
            gmsh.write(os.path.join(OUT, "%s_%s.msh" % (stem, suffix)))


def write_mdpa(path, dim, elem_names, cond_names):
    """Writes the current mesh as .mdpa: cells of `dim` as elements, of dim-1 as conditions,
    one SubModelPart per physical group (named groups only), ids = Gmsh tags."""
    ntags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = {int(t): coords[3 * i:3 * i + 3] for i, t in enumerate(ntags)}
    cells = {}  # tag -> (dim, gmsh type, nodes)
    groups = []
    for gdim, gtag in gmsh.model.getPhysicalGroups():
        name = gmsh.model.getPhysicalName(gdim, gtag)
        ents = gmsh.model.getEntitiesForPhysicalGroup(gdim, gtag)
        members = []
        for e in ents:
            types, etags, enodes = gmsh.model.mesh.getElements(gdim, e)
            for ty, tl, nl in zip(types, etags, enodes):
                n = len(nl) // len(tl)
                for k, t in enumerate(tl):
                    cells[int(t)] = (gdim, int(ty), [int(x) for x in nl[k * n:(k + 1) * n]])
                    members.append(int(t))
        groups.append((name, gdim, members))
    with open(path, "w", newline="\n") as f:
        f.write("Begin ModelPartData\n//  VARIABLE_NAME value\nEnd ModelPartData\n\n")
        f.write("Begin Properties 0\nEnd Properties\n\n")
        f.write("Begin Nodes\n")
        for t in sorted(xyz):
            f.write("%d %r %r %r\n" % (t, float(xyz[t][0]), float(xyz[t][1]), float(xyz[t][2])))
        f.write("End Nodes\n\n")
        for block, d, names in (("Elements", dim, elem_names), ("Conditions", dim - 1, cond_names)):
            by_type = {}
            for t in sorted(cells):
                cd, ty, nodes = cells[t]
                if cd == d:
                    by_type.setdefault(ty, []).append((t, nodes))
            for ty in sorted(by_type):
                f.write("Begin %s %s\n" % (block, names[ty]))
                for t, nodes in by_type[ty]:
                    f.write("%d 0 %s\n" % (t, " ".join(str(n) for n in nodes)))
                f.write("End %s\n\n" % block)
        for name, gdim, members in groups:
            if not name:
                continue
            nodes = sorted({n for t in members for n in cells[t][2]})
            f.write("Begin SubModelPart %s\n" % name)
            f.write("  Begin SubModelPartNodes\n")
            f.writelines("    %d\n" % n for n in nodes)
            f.write("  End SubModelPartNodes\n")
            kind = "Elements" if gdim == dim else "Conditions"
            f.write("  Begin SubModelPart%s\n" % kind)
            f.writelines("    %d\n" % t for t in sorted(members))
            f.write("  End SubModelPart%s\n" % kind)
            f.write("End SubModelPart\n\n")


def boxes(order=1, serendipity=False):
    gmsh.model.add("boxes")
    occ = gmsh.model.occ
    lower = occ.addBox(0, 0, 0, 1, 1, 0.5)
    upper = occ.addBox(0.125, 0.125, 0.5, 0.75, 0.75, 0.5)
    occ.synchronize()
    h = 0.3 if order == 1 else 0.5
    gmsh.model.mesh.setSize(gmsh.model.getBoundary([(3, lower)], False, False, True), h)
    n = 4 if order == 1 else 2
    up_surfs = [s for _, s in gmsh.model.getBoundary([(3, upper)], False, False, False)]
    up_curves = set()
    for s in up_surfs:
        up_curves |= {abs(c) for _, c in gmsh.model.getBoundary([(2, s)], False, False, False)}
    for c in sorted(up_curves):
        bb = gmsh.model.getBoundingBox(1, c)
        vertical = abs(bb[2] - bb[5]) > 1e-5
        gmsh.model.mesh.setTransfiniteCurve(c, (n // 2 + 1) if vertical else n + 1)
    for s in up_surfs:
        gmsh.model.mesh.setTransfiniteSurface(abs(s))
        gmsh.model.mesh.setRecombine(2, abs(s))
    gmsh.model.mesh.setTransfiniteVolume(upper)
    gmsh.model.mesh.setRecombine(3, upper)

    slave = entity_at(2, lambda b: abs(b[2] - 0.5) < 1e-5 and abs(b[5] - 0.5) < 1e-5 and b[0] > 0.1)
    master = entity_at(2, lambda b: abs(b[2] - 0.5) < 1e-5 and abs(b[5] - 0.5) < 1e-5 and b[0] < 0.1)
    edge = entity_at(1, lambda b: abs(b[2] - 0.5) < 1e-5 and abs(b[5] - 0.5) < 1e-5
                     and b[1] < 1e-5 and b[4] < 1e-5 and b[0] < 1e-5)
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [slave], 1), "slave")
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [master], 2), "master")
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [slave, master], 3), "interface")
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [lower], 4), "block_lower")
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [upper], 5), "block_upper")
    gmsh.model.addPhysicalGroup(1, [edge], 7)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.model.mesh.generate(3)
    snap()
    if order == 2:
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1 if serendipity else 0)
        gmsh.model.mesh.setOrder(2)


def rects():
    gmsh.model.add("rects")
    occ = gmsh.model.occ
    lower = occ.addRectangle(0, 0, 0, 1, 0.5)
    upper = occ.addRectangle(0.125, 0.5, 0, 0.75, 0.375)
    occ.synchronize()
    gmsh.model.mesh.setSize(gmsh.model.getBoundary([(2, lower)], False, False, True), 0.15)
    gmsh.model.mesh.setSize(gmsh.model.getBoundary([(2, upper)], False, False, True), 0.125)
    gmsh.model.mesh.setRecombine(2, upper)
    slave = entity_at(1, lambda b: abs(b[1] - 0.5) < 1e-5 and abs(b[4] - 0.5) < 1e-5 and b[0] > 0.1)
    master = entity_at(1, lambda b: abs(b[1] - 0.5) < 1e-5 and abs(b[4] - 0.5) < 1e-5 and b[0] < 0.1)
    gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [slave], 1), "slave")
    gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [master], 2), "master")
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [lower], 3), "block_lower")
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [upper], 4), "block_upper")
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.model.mesh.generate(2)
    snap()


def main():
    os.makedirs(OUT, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MaxNumThreads3D", 1)

    boxes()
    save_all("boxes")
    write_mdpa(os.path.join(OUT, "boxes.mdpa"), 3,
               {4: "Element3D4N", 5: "Element3D8N"},
               {2: "SurfaceCondition3D3N", 3: "SurfaceCondition3D4N"})
    gmsh.model.remove()

    rects()
    save_all("rects")
    write_mdpa(os.path.join(OUT, "rects.mdpa"), 2,
               {2: "Element2D3N", 3: "Element2D4N"}, {1: "LineCondition2D2N"})
    gmsh.model.remove()

    for serendipity, stem in ((False, "boxes_order2"), (True, "boxes_order2_serendipity")):
        boxes(order=2, serendipity=serendipity)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(os.path.join(OUT, stem + ".msh"))
        gmsh.model.remove()
    gmsh.finalize()


if __name__ == "__main__":
    main()
