#!/usr/bin/env python3
"""Benchmark scenes for `cargo xtask bench` (deterministic, written to a directory given).

    python tools/bench_scenes.py OUT_DIR SCENE:SLAVE_FACES [SCENE:SLAVE_FACES ...]

Scenes (the targets of the performance issue):

  sphere_on_plate  a unit sphere pressed 0.1 h into a plate: gmsh triangulates the lower
                   hemisphere (slave, SurfaceCondition3D3N) and the plate's top square
                   [-1.2, 1.2]^2 (master) with the same element size h, chosen so that the
                   hemisphere has about SLAVE_FACES triangles (the plate gets ~0.9 as many).
                   Each surface triangle is extruded into one layer of prisms (Element3D6N,
                   thickness h, towards the body's inside), so the bodies have volume elements
                   (NODAL_H, the normal check) without millions of tetrahedra.
  stacked_blocks   two non-matching structured hexahedral slabs (Element3D8N, one layer) whose
                   faces all touch: upper [0, 1]^2 x [0, h] with n x n slave quads
                   (SurfaceCondition3D4N, n^2 ~ SLAVE_FACES), lower [-0.05, 1.05]^2 x [-h, 0]
                   with m x m master quads, m = round(0.83 n); interface exactly on z = 0.

Parts as in tests/data/scenes: Parts_Slave / Parts_Master (conditions and their nodes) and one
part per body (its elements). Coordinates are written with `repr` (17 significant digits), so
csm and Kratos read the same doubles. gmsh (PyPI `gmsh`) runs with one thread and a fixed seed.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gen_scenes import Mesh, cross, dot, sub  # noqa: E402

# gmsh's triangles of size h have about this area, in units of h^2 (calibrated on the
# generated hemispheres: 0.62 gave 1.47–1.56 times the asked slave faces; an equilateral
# triangle of side h has 0.433 h^2).
TRIANGLE_AREA_PER_H2 = 0.42


def norm(v):
    return math.sqrt(dot(v, v))


def gmsh_triangles(build, h):
    """Nodes and triangles of the surfaces `build(gmsh)` returns (OCC), meshed with size h."""
    import gmsh
    gmsh.model.add("surface")
    surfaces = build(gmsh)
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(2)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = {int(t): (coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]) for i, t in enumerate(tags)}
    tris = []
    for s in surfaces:
        types, _, enodes = gmsh.model.mesh.getElements(2, s)
        for ty, en in zip(types, enodes):
            if ty != 2:
                continue
            tris.extend([int(en[3 * k]), int(en[3 * k + 1]), int(en[3 * k + 2])] for k in range(len(en) // 3))
    gmsh.model.remove()
    return xyz, tris


def prism_shell(mesh, xyz, tris, outward, h, keep):
    """Adds the triangles `keep` accepts as outward-oriented conditions and one layer of prisms
    under every triangle (thickness h along -outward(x) at each node); returns (elements,
    conditions)."""
    outer, inner = {}, {}
    elements, conditions = [], []
    for tri in tris:
        pts = [xyz[t] for t in tri]
        n = cross(sub(pts[1], pts[0]), sub(pts[2], pts[0]))
        c = tuple(sum(p[k] for p in pts) / 3.0 for k in range(3))
        if dot(n, outward(c)) < 0.0:
            tri = [tri[0], tri[2], tri[1]]
        for t in tri:
            if t not in outer:
                x = xyz[t]
                d = outward(x)
                outer[t] = mesh.add_node(x)
                inner[t] = mesh.add_node(tuple(x[k] - h * d[k] for k in range(3)))
        # Prism3D6: the inner triangle (normal towards the outer one), then the outer one.
        elements.append(mesh.add_element("Element3D6N", [inner[t] for t in tri] + [outer[t] for t in tri]))
        if keep([xyz[t] for t in tri]):
            conditions.append(mesh.add_condition("SurfaceCondition3D3N", [outer[t] for t in tri]))
    return elements, conditions


def sphere_on_plate(slave_faces):
    hemisphere = 2.0 * math.pi
    h = math.sqrt(hemisphere / (TRIANGLE_AREA_PER_H2 * slave_faces))
    pen = 0.1 * h
    zc = 1.0 - pen
    m = Mesh(3)

    def sphere(g):
        # The lower hemisphere (latitudes -90..0 degrees): its curved surface only.
        v = g.model.occ.addSphere(0.0, 0.0, zc, 1.0, -1, -math.pi / 2, 0.0)
        g.model.occ.synchronize()
        faces = [t for d, t in g.model.getBoundary([(3, v)], oriented=False) if d == 2]
        return [f for f in faces if g.model.getType(2, f) != "Plane"]

    xyz, tris = gmsh_triangles(sphere, h)

    def radial(x):
        d = (x[0], x[1], x[2] - zc)
        r = norm(d)
        return (d[0] / r, d[1] / r, d[2] / r)

    s_elems, slave = prism_shell(m, xyz, tris, radial, h, lambda p: True)

    def plate(g):
        return [g.model.occ.addRectangle(-1.2, -1.2, 0.0, 2.4, 2.4)]

    xyz, tris = gmsh_triangles(plate, h)
    p_elems, master = prism_shell(m, xyz, tris, lambda x: (0.0, 0.0, 1.0), h, lambda p: True)
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Sphere", s_elems, [], []), ("Parts_Plate", p_elems, [], [])]
    return m, h


def quad_slab(mesh, x0, x1, n, z_face, z_back):
    """n x n hexahedra over [x0, x1]^2 between z_face (the contact face) and z_back; returns
    (elements, the contact-face quads oriented away from the slab)."""
    top, bottom = {}, {}
    for j in range(n + 1):
        for i in range(n + 1):
            x = x0 + (x1 - x0) * i / n
            y = x0 + (x1 - x0) * j / n
            top[i, j] = mesh.add_node((x, y, max(z_face, z_back)))
            bottom[i, j] = mesh.add_node((x, y, min(z_face, z_back)))
    elems, faces = [], []
    up = z_face > z_back
    for j in range(n):
        for i in range(n):
            q = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            elems.append(mesh.add_element("Element3D8N", [bottom[k] for k in q] + [top[k] for k in q]))
            face = [top[k] for k in q] if up else [bottom[k] for k in reversed(q)]
            faces.append(mesh.add_condition("SurfaceCondition3D4N", face))
    return elems, faces


def stacked_blocks(slave_faces):
    n = max(2, int(round(math.sqrt(slave_faces))))
    mm = max(2, int(round(0.83 * n)))
    h = 1.0 / n
    m = Mesh(3)
    up, slave = quad_slab(m, 0.0, 1.0, n, 0.0, h)
    lo, master = quad_slab(m, -0.05, 1.05, mm, 0.0, -h)
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Upper", up, [], []), ("Parts_Lower", lo, [], [])]
    return m, h


SCENES = {"sphere_on_plate": sphere_on_plate, "stacked_blocks": stacked_blocks}


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    import gmsh
    gmsh.initialize(["gmsh", "-nopopup"])
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        for spec in sys.argv[2:]:
            name, size = spec.split(":")
            m, h = SCENES[name](int(float(size)))
            slave = len(dict((p[0], p) for p in m.parts)["Parts_Slave"][2])
            master = len(dict((p[0], p) for p in m.parts)["Parts_Master"][2])
            path = os.path.join(out, "%s_%s.mdpa" % (name, size))
            head = ("csm benchmark scene '%s' (tools/bench_scenes.py, do not edit), h = %r\n"
                    "%d nodes, %d elements, %d slave and %d master faces"
                    % (name, h, len(m.nodes), len(m.elements), slave, master))
            m.write(path, head)
            print("%s %d %d %d %d" % (path, slave, master, len(m.nodes), len(m.elements)), flush=True)
    finally:
        gmsh.finalize()


if __name__ == "__main__":
    main()
