#!/usr/bin/env python3
"""Generates the contact-search reference scenes into tests/data/scenes/ (deterministic).

Run by hand from the repository root (not by `cargo xtask fixtures`):

    OMP_NUM_THREADS=1 /work/kratos-venv/bin/python tools/gen_scenes.py

(needs `pip install gmsh` in that interpreter; gmsh meshes the sphere, the tetrahedral plate and
the half-disc, with one thread and a fixed random seed). Then regenerate the Kratos fixtures with
`cargo xtask fixtures` (or `tools/kratos_fixtures_search.py`).

Every scene is a Kratos `.mdpa` whose coordinates are written with `repr` (17 significant digits),
so csm and Kratos read the same doubles. Every body has volume (3D) / surface (2D) elements
(generic `Element3D4N`, `Element3D8N`, `Element2D3N`, `Element2D4N`) so that FindNodalHProcess
gives every node a finite NODAL_H. The contact faces are conditions (`SurfaceCondition3D3N`,
`SurfaceCondition3D4N`, `LineCondition2D2N`) oriented with their normal pointing out of their
element; they form the sub model parts `Parts_Slave` / `Parts_Master` (conditions + nodes); the
bodies are `Parts_<Body>` (elements + nodes). Element ids and condition ids both start at 1.

Scenes:
  sphere_on_plate_tri    sphere of tetrahedra (radius 1, graded mesh, h ~ 0.06 at the south pole),
                         penetrating 0.006 (0.1 h) a tetrahedral plate [-1.2,1.2]^2 x [-0.3,0];
                         slave = lower-hemisphere triangles, master = plate top triangles (3D3N).
  sphere_on_plate_mixed  the same sphere on a structured hexahedral plate (30 x 30 x 2);
                         slave triangles, master quadrilaterals (the 3D3N4N instance).
  stacked_blocks         hexahedral blocks: upper [0,1]^2 x [0,0.5] (12 x 12 x 6, slave quads) on
                         lower [-0.1,1.1]^2 x [-0.5,0] (10 x 10 x 5, master quads); interface
                         exactly on z = 0 (gap 0).
  stacked_blocks_pen     the same blocks with the upper one lowered by 1e-4 (its slave face on
                         z = -1e-4, a tiny penetration): with DOMAIN_SIZE unset Kratos' octree
                         finds no pair here (reference header), with DOMAIN_SIZE = 3 it does.
  cylinder_on_block_2d   2D: half-disc of triangles (radius 1, lower half, size 0.05) penetrating
                         0.005 a rectangle [-1.5,1.5] x [-0.5,0] of 60 x 10 quadrilaterals;
                         slave = arc lines, master = rectangle top lines (LineCondition2D2N).
  plane_cylinder_cpp     the plane/cylinder strip of Kratos' C++ test_search_process.cpp
                         (reference §20.1): 3D, 18 + 26 nodes, SurfaceCondition3D4N 1..8 (slave
                         plane y = 0) and 9..20 (master cylinder), ids as in the test; no elements
                         (the test sets NODAL_H = 1 by hand).
  stacked_blocks_rotated two non-matching stacked hexahedral blocks rotated against each other:
                         upper [-0.5,0.5]^2 x [-1e-4,0.5] (11 x 11 x 5, slave quads) rotated by 17
                         degrees about the vertical axis x = y = 0, on lower [-0.7,0.7]^2 x
                         [-0.5,0] (9 x 9 x 4, master quads); penetration 1e-4 (~1e-3 h).
  cylinder_on_plate_quads a cylinder on a plate (quads): hexahedral lower half of the unit
                         cylinder of axis along y (y in [-0.8,0.8], 16 layers; cross-section: core
                         16 x 8 + ring 32 x 3, 32 arc faces), lowest line penetrating 0.005 a
                         hexahedral plate [-1.2,1.2] x [-1,1] x [-0.3,0] (25 x 21 x 2); slave =
                         curved-surface quads, master = plate top quads (3D4N).
"""
import math
import os
import sys

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "scenes")


# ----------------------------------------------------------------------------------------------
# Small mesh container and .mdpa writer
# ----------------------------------------------------------------------------------------------
class Mesh:
    def __init__(self, dim):
        self.dim = dim
        self.nodes = {}          # id -> (x, y, z)
        self.elements = []       # (name, id, [nodes])
        self.conditions = []     # (name, id, [nodes])
        self.parts = []          # (name, element ids, condition ids, extra node ids)

    def add_node(self, xyz):
        i = len(self.nodes) + 1
        self.nodes[i] = tuple(float(c) for c in xyz)
        return i

    def add_element(self, name, nodes):
        i = len(self.elements) + 1
        self.elements.append((name, i, list(nodes)))
        return i

    def add_condition(self, name, nodes):
        i = len(self.conditions) + 1
        self.conditions.append((name, i, list(nodes)))
        return i

    def write(self, path, comment):
        emap = {i: n for _, i, n in self.elements}
        cmap = {i: n for _, i, n in self.conditions}
        with open(path, "w", newline="\n") as f:
            for line in comment.strip().splitlines():
                f.write("// %s\n" % line)
            f.write("Begin ModelPartData\n//  VARIABLE_NAME value\nEnd ModelPartData\n\n")
            f.write("Begin Properties 0\nEnd Properties\n\n")
            f.write("Begin Nodes\n")
            for i in sorted(self.nodes):
                x, y, z = self.nodes[i]
                f.write("%d %r %r %r\n" % (i, x, y, z))
            f.write("End Nodes\n\n")
            for block, entities in (("Elements", self.elements), ("Conditions", self.conditions)):
                names = []
                for name, _, _ in entities:
                    if name not in names:
                        names.append(name)
                for name in names:
                    f.write("Begin %s %s\n" % (block, name))
                    for n, i, nodes in entities:
                        if n == name:
                            f.write("%d 0 %s\n" % (i, " ".join(str(k) for k in nodes)))
                    f.write("End %s\n\n" % block)
            for name, elems, conds, extra in self.parts:
                nodes = set(extra)
                for e in elems:
                    nodes.update(emap[e])
                for c in conds:
                    nodes.update(cmap[c])
                f.write("Begin SubModelPart %s\n" % name)
                f.write("  Begin SubModelPartNodes\n")
                f.writelines("    %d\n" % n for n in sorted(nodes))
                f.write("  End SubModelPartNodes\n")
                f.write("  Begin SubModelPartElements\n")
                f.writelines("    %d\n" % e for e in sorted(elems))
                f.write("  End SubModelPartElements\n")
                f.write("  Begin SubModelPartConditions\n")
                f.writelines("    %d\n" % c for c in sorted(conds))
                f.write("  End SubModelPartConditions\n")
                f.write("End SubModelPart\n\n")


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def centroid(pts):
    n = float(len(pts))
    return tuple(sum(p[k] for p in pts) / n for k in range(3))


# Faces of the linear solids, each oriented outward for a positively oriented element
# (Kratos/Gmsh node numbering).
TET_FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
TRI_EDGES = [(0, 1), (1, 2), (2, 0)]
QUAD_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0)]


def boundary_faces(mesh, elem_ids, local_faces):
    """Faces of the given elements that belong to exactly one of them, oriented outward
    (checked against the element centroid), as lists of node ids."""
    count = {}
    first = {}
    for name, i, nodes in mesh.elements:
        if i not in elem_ids:
            continue
        for lf in local_faces[len(nodes)]:
            face = [nodes[k] for k in lf]
            key = tuple(sorted(face))
            count[key] = count.get(key, 0) + 1
            first.setdefault(key, (face, nodes))
    out = []
    for key in sorted(first):
        if count[key] != 1:
            continue
        face, nodes = first[key]
        c_el = centroid([mesh.nodes[n] for n in nodes])
        pts = [mesh.nodes[n] for n in face]
        c_f = centroid(pts)
        if len(face) == 2:  # 2D line: Kratos normal = tangent x e_z = (t_y, -t_x)
            t = sub(pts[1], pts[0])
            normal = (t[1], -t[0], 0.0)
        else:
            normal = cross(sub(pts[1], pts[0]), sub(pts[-1], pts[0]))
        if dot(normal, sub(c_f, c_el)) < 0.0:
            raise RuntimeError("inward face %s" % (face,))
        out.append(face)
    return out


def fix_orientation(mesh, pts_ids):
    """Returns the node list of a linear simplex/hex with positive orientation."""
    p = [mesh.nodes[n] for n in pts_ids]
    if len(pts_ids) == 4 and mesh.dim == 3:  # tetrahedron
        if dot(cross(sub(p[1], p[0]), sub(p[2], p[0])), sub(p[3], p[0])) < 0.0:
            return [pts_ids[0], pts_ids[2], pts_ids[1], pts_ids[3]]
    elif len(pts_ids) == 3:  # triangle in the xy plane
        if cross(sub(p[1], p[0]), sub(p[2], p[0]))[2] < 0.0:
            return [pts_ids[0], pts_ids[2], pts_ids[1]]
    return list(pts_ids)


# ----------------------------------------------------------------------------------------------
# Bodies
# ----------------------------------------------------------------------------------------------
def gmsh_body(mesh, build, dim, elem_name):
    """Meshes one gmsh model built by `build()` (OCC), adds its nodes and its linear
    simplices of dimension `dim` to `mesh`; returns the new element ids."""
    import gmsh
    gmsh.model.add("body")
    build(gmsh)
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(dim)
    gmsh.model.mesh.removeDuplicateNodes()
    tags, coords, _ = gmsh.model.mesh.getNodes()
    etype = 4 if dim == 3 else 2
    _, enodes = gmsh.model.mesh.getElementsByType(etype)
    used = sorted({int(t) for t in enodes})
    xyz = {int(t): (coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]) for i, t in enumerate(tags)}
    new_id = {}
    for t in used:
        x, y, z = xyz[t]
        new_id[t] = mesh.add_node((x, y, 0.0 if dim == 2 else z))
    ids = []
    k = dim + 1
    for e in range(len(enodes) // k):
        nodes = [new_id[int(t)] for t in enodes[e * k:(e + 1) * k]]
        ids.append(mesh.add_element(elem_name, fix_orientation(mesh, nodes)))
    gmsh.model.remove()
    return set(ids)


def sphere(mesh, zc, h0, grade):
    """Tetrahedral unit sphere centred at (0, 0, zc); size h0 at the south pole growing with z."""
    zb = zc - 1.0

    def build(g):
        g.model.occ.addSphere(0.0, 0.0, zc, 1.0)
        g.model.occ.synchronize()
        f = g.model.mesh.field.add("MathEval")
        g.model.mesh.field.setString(f, "F", "%r + %r * (z - (%r))" % (h0, grade, zb))
        g.model.mesh.field.setAsBackgroundMesh(f)
    return gmsh_body(mesh, build, 3, "Element3D4N")


def tet_plate(mesh, half, thick, h0, grade):
    def build(g):
        g.model.occ.addBox(-half, -half, -thick, 2 * half, 2 * half, thick)
        g.model.occ.synchronize()
        f = g.model.mesh.field.add("MathEval")
        g.model.mesh.field.setString(f, "F", "%r + %r * Sqrt(x*x + y*y) + %r * (-z)" % (h0, grade, grade))
        g.model.mesh.field.setAsBackgroundMesh(f)
    return gmsh_body(mesh, build, 3, "Element3D4N")


def half_disc(mesh, yc, h):
    def build(g):
        occ = g.model.occ
        d = occ.addDisk(0.0, yc, 0.0, 1.0, 1.0)
        r = occ.addRectangle(-1.5, yc, 0.0, 3.0, 1.5)
        occ.cut([(2, d)], [(2, r)])
        occ.synchronize()
        f = g.model.mesh.field.add("MathEval")
        g.model.mesh.field.setString(f, "F", "%r" % h)
        g.model.mesh.field.setAsBackgroundMesh(f)
    return gmsh_body(mesh, build, 2, "Element2D3N")


def hex_block(mesh, x0, x1, y0, y1, z0, z1, nx, ny, nz, angle=0.0):
    """Structured hexahedral block; with `angle` (radians) its nodes are rotated about the
    vertical axis x = y = 0 (counter-clockwise seen from +z)."""
    c, s = math.cos(angle), math.sin(angle)
    ids = {}
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                x = x0 + (x1 - x0) * i / nx
                y = y0 + (y1 - y0) * j / ny
                z = z0 + (z1 - z0) * k / nz
                if angle != 0.0:
                    x, y = c * x - s * y, s * x + c * y
                ids[i, j, k] = mesh.add_node((x, y, z))
    elems = set()
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                n = [ids[i, j, k], ids[i + 1, j, k], ids[i + 1, j + 1, k], ids[i, j + 1, k],
                     ids[i, j, k + 1], ids[i + 1, j, k + 1], ids[i + 1, j + 1, k + 1], ids[i, j + 1, k + 1]]
                elems.add(mesh.add_element("Element3D8N", n))
    return elems


def positive_hex(mesh, nodes):
    """The hexahedron's node list with positive orientation (bottom face reversed if needed)."""
    p = [mesh.nodes[n] for n in nodes]
    if dot(cross(sub(p[1], p[0]), sub(p[3], p[0])), sub(p[4], p[0])) < 0.0:
        return [nodes[k] for k in (0, 3, 2, 1, 4, 7, 6, 5)]
    return list(nodes)


def half_cylinder_hex(mesh, zc, n, m, a, y0, y1, ny):
    """Hexahedral lower half of the unit cylinder of axis (x, z) = (0, zc), y in [y0, y1].
    Cross-section (x, z - zc): a core [-a, a] x [-a, 0] of 2n x n quadrilaterals and a ring of
    4n x m quadrilaterals blending the core's lower boundary (left side, bottom, right side) into
    the arc (4n equal angles from (-1, 0) through (0, -1) to (1, 0)); extruded in ny layers."""
    def arc(t):  # mirror-symmetric, exact at both ends and at the bottom
        if t > 2 * n:
            x, z = arc(4 * n - t)
            return (-x, z)
        if t == 0:
            return (-1.0, 0.0)
        if t == 2 * n:
            return (0.0, -1.0)
        th = math.pi * t / (4 * n)
        return (-math.cos(th), -math.sin(th))

    def core(i, k):
        return (-a + a * i / n, -a + a * k / n)
    boundary = [(0, k) for k in range(n, 0, -1)] + [(i, 0) for i in range(2 * n + 1)] + \
        [(2 * n, k) for k in range(1, n + 1)]
    pts = {}  # 2D key -> (x, z relative to the axis)
    for i in range(2 * n + 1):
        for k in range(n + 1):
            pts["c", i, k] = core(i, k)
    key = {}
    quads = []
    for i in range(2 * n):
        for k in range(n):
            quads.append([("c", i, k), ("c", i + 1, k), ("c", i + 1, k + 1), ("c", i, k + 1)])
    for t in range(4 * n + 1):
        key[t, 0] = ("c",) + boundary[t]
        for r in range(1, m + 1):
            s = float(r) / m
            (cx, cz), (ax, az) = core(*boundary[t]), arc(t)
            key[t, r] = ("r", t, r)
            pts["r", t, r] = (ax if r == m else (1.0 - s) * cx + s * ax,
                              az if r == m else (1.0 - s) * cz + s * az)
    for t in range(4 * n):
        for r in range(m):
            quads.append([key[t, r], key[t + 1, r], key[t + 1, r + 1], key[t, r + 1]])
    ids = {}
    for j in range(ny + 1):
        y = y0 + (y1 - y0) * j / ny
        for q in sorted(pts):
            x, z = pts[q]
            ids[q, j] = mesh.add_node((x, y, zc + z))
    elems = set()
    for j in range(ny):
        for q in quads:
            nodes = [ids[k, j] for k in q] + [ids[k, j + 1] for k in q]
            elems.add(mesh.add_element("Element3D8N", positive_hex(mesh, nodes)))
    return elems


def quad_rect(mesh, x0, x1, y0, y1, nx, ny):
    ids = {}
    for j in range(ny + 1):
        for i in range(nx + 1):
            ids[i, j] = mesh.add_node((x0 + (x1 - x0) * i / nx, y0 + (y1 - y0) * j / ny, 0.0))
    elems = set()
    for j in range(ny):
        for i in range(nx):
            elems.add(mesh.add_element("Element2D4N", [ids[i, j], ids[i + 1, j], ids[i + 1, j + 1], ids[i, j + 1]]))
    return elems


FACES3D = {4: TET_FACES, 8: HEX_FACES}
EDGES2D = {3: TRI_EDGES, 4: QUAD_EDGES}


def contact_faces(mesh, elems, local, pred):
    faces = [f for f in boundary_faces(mesh, elems, local) if pred([mesh.nodes[n] for n in f])]
    return faces


def add_conditions(mesh, faces):
    names = {2: "LineCondition2D2N", 3: "SurfaceCondition3D3N", 4: "SurfaceCondition3D4N"}
    return [mesh.add_condition(names[len(f)], f) for f in faces]


# ----------------------------------------------------------------------------------------------
# Scenes
# ----------------------------------------------------------------------------------------------
SPHERE_H0 = 0.06
SPHERE_PEN = 0.1 * SPHERE_H0          # penetration of the south pole into the plate (z = 0)
SPHERE_ZC = 1.0 - SPHERE_PEN


def sphere_slave(mesh, elems):
    return contact_faces(mesh, elems, FACES3D, lambda p: centroid(p)[2] < SPHERE_ZC)


def top_faces(mesh, elems, top, local):
    return contact_faces(mesh, elems, local, lambda p: all(abs(q[2] - top) < 1e-12 for q in p))


def scene_sphere_on_plate_tri():
    m = Mesh(3)
    s = sphere(m, SPHERE_ZC, SPHERE_H0, 0.3)
    p = tet_plate(m, 1.2, 0.3, 0.05, 0.15)
    slave = add_conditions(m, sphere_slave(m, s))
    master = add_conditions(m, top_faces(m, p, 0.0, FACES3D))
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Sphere", sorted(s), [], []), ("Parts_Plate", sorted(p), [], [])]
    return m


def scene_sphere_on_plate_mixed():
    m = Mesh(3)
    s = sphere(m, SPHERE_ZC, SPHERE_H0, 0.3)
    p = hex_block(m, -1.2, 1.2, -1.2, 1.2, -0.3, 0.0, 30, 30, 2)
    slave = add_conditions(m, sphere_slave(m, s))
    master = add_conditions(m, top_faces(m, p, 0.0, FACES3D))
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Sphere", sorted(s), [], []), ("Parts_Plate", sorted(p), [], [])]
    return m


def scene_stacked_blocks(pen=0.0):
    m = Mesh(3)
    up = hex_block(m, 0.0, 1.0, 0.0, 1.0, -pen, 0.5, 12, 12, 6)
    lo = hex_block(m, -0.1, 1.1, -0.1, 1.1, -0.5, 0.0, 10, 10, 5)
    slave = add_conditions(m, contact_faces(m, up, FACES3D, lambda p: all(abs(q[2] + pen) < 1e-12 for q in p)))
    master = add_conditions(m, top_faces(m, lo, 0.0, FACES3D))
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Upper", sorted(up), [], []), ("Parts_Lower", sorted(lo), [], [])]
    return m


ROTATED_ANGLE = math.radians(17.0)
ROTATED_PEN = 1.0e-4                  # ~1.1e-3 h of the upper block (h = 1/11)


def scene_stacked_blocks_rotated():
    m = Mesh(3)
    pen = ROTATED_PEN
    up = hex_block(m, -0.5, 0.5, -0.5, 0.5, -pen, 0.5, 11, 11, 5, angle=ROTATED_ANGLE)
    lo = hex_block(m, -0.7, 0.7, -0.7, 0.7, -0.5, 0.0, 9, 9, 4)
    slave = add_conditions(m, contact_faces(m, up, FACES3D, lambda p: all(abs(q[2] + pen) < 1e-12 for q in p)))
    master = add_conditions(m, top_faces(m, lo, 0.0, FACES3D))
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Upper", sorted(up), [], []), ("Parts_Lower", sorted(lo), [], [])]
    return m


CYL_PEN = 0.005                       # penetration of the lowest cylinder line into the plate


def scene_cylinder_on_plate_quads():
    m = Mesh(3)
    zc = 1.0 - CYL_PEN
    c = half_cylinder_hex(m, zc, 8, 3, 0.6, -0.8, 0.8, 16)
    p = hex_block(m, -1.2, 1.2, -1.0, 1.0, -0.3, 0.0, 25, 21, 2)

    def on_arc(pts):
        return all(abs(math.hypot(q[0], q[2] - zc) - 1.0) < 1e-9 for q in pts) and centroid(pts)[2] < zc - 1e-9
    slave = add_conditions(m, contact_faces(m, c, FACES3D, on_arc))
    master = add_conditions(m, top_faces(m, p, 0.0, FACES3D))
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Cylinder", sorted(c), [], []), ("Parts_Plate", sorted(p), [], [])]
    return m


def scene_cylinder_on_block_2d():
    m = Mesh(2)
    pen = 0.005
    yc = 1.0 - pen
    d = half_disc(m, yc, 0.05)
    r = quad_rect(m, -1.5, 1.5, -0.5, 0.0, 60, 10)

    def on_arc(p):
        return all(abs(math.hypot(q[0], q[1] - yc) - 1.0) < 1e-9 for q in p) and centroid(p)[1] < yc - 1e-9
    slave = add_conditions(m, contact_faces(m, d, EDGES2D, on_arc))
    master = add_conditions(m, contact_faces(m, r, EDGES2D, lambda p: all(abs(q[1]) < 1e-12 for q in p)))
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, []),
               ("Parts_Disc", sorted(d), [], []), ("Parts_Block", sorted(r), [], [])]
    return m


def scene_plane_cylinder_cpp():
    """CreatePlaneCilynderProblemForSearch(divisions 8, length 4.0, radius 6.0, angle pi/6,
    slope 0) of test_search_process.cpp (reference §20.1), same node and condition ids."""
    m = Mesh(3)
    divisions, length, radius, angle = 8, 4.0, 6.0, math.pi / 6.0
    dx = length / divisions
    for i in range(divisions + 1):
        m.nodes[2 * i + 1] = (dx * i, 0.0, 0.0)
        m.nodes[2 * i + 2] = (dx * i, 0.0, 1.0)
    dtheta = angle / divisions
    k = 0
    x_prev = 0.0
    while x_prev < length and k * dtheta < math.pi / 2.0:
        t = k * dtheta
        x, y = radius * math.sin(t), radius * (1.0 - math.cos(t))
        m.nodes[19 + 2 * k] = (x, y, 0.0)
        m.nodes[20 + 2 * k] = (x, y, 1.0)
        x_prev = x
        k += 1
    stations = k
    slave = [m.add_condition("SurfaceCondition3D4N", [2 * i + 1, 2 * i + 2, 2 * i + 4, 2 * i + 3])
             for i in range(divisions)]
    master = [m.add_condition("SurfaceCondition3D4N", [21 + 2 * i, 22 + 2 * i, 20 + 2 * i, 19 + 2 * i])
              for i in range(stations - 1)]
    assert slave == list(range(1, 9)) and master == list(range(9, 21)), (slave, master)
    m.parts = [("Parts_Slave", [], slave, []), ("Parts_Master", [], master, [])]
    return m


def scene_folded_strip():
    """Self-contact: one C-shaped body of hexahedra whose two arms face each other across a gap
    of 1e-3. A bottom bar (z 0..0.5) and a top bar (z 0.5+g..1+g) of 8 x 3 x 2 cells, joined at
    x in [0, 0.25] by a column of thin cells spanning the gap; the top bar's nodes beyond the
    joint are shifted by 0.3 cell in x, so the arms do not match. The node-only part
    Contact_Fold lists the nodes of both inner faces beyond the joint (Kratos generates the
    faces; the roles are decided automatically)."""
    m = Mesh(3)
    nx, ny, dx, dy, g = 8, 3, 0.25, 0.25, 1.0e-3
    levels = [0.0, 0.25, 0.5, 0.5 + g, 0.75 + g, 1.0 + g]
    ids = {}
    for k, z in enumerate(levels):
        for j in range(ny + 1):
            for i in range(nx + 1):
                x = i * dx + (0.3 * dx if k >= 3 and i >= 2 else 0.0)
                ids[i, j, k] = m.add_node((x, j * dy, z))
    elems = set()
    for k in range(len(levels) - 1):
        for j in range(ny):
            for i in range(nx):
                if k == 2 and i > 0:
                    continue  # the gap, except the joint column
                n = [ids[i, j, k], ids[i + 1, j, k], ids[i + 1, j + 1, k], ids[i, j + 1, k],
                     ids[i, j, k + 1], ids[i + 1, j, k + 1], ids[i + 1, j + 1, k + 1], ids[i, j + 1, k + 1]]
                elems.add(m.add_element("Element3D8N", n))
    fold = set()
    for k in (2, 3):
        for j in range(ny + 1):
            for i in range(1, nx + 1):
                fold.add(ids[i, j, k])
    m.parts.append(("Parts_Body", elems, set(), set()))
    m.parts.append(("Contact_Fold", set(), set(), fold))
    return m


SCENES = [
    ("sphere_on_plate_tri", scene_sphere_on_plate_tri),
    ("sphere_on_plate_mixed", scene_sphere_on_plate_mixed),
    ("stacked_blocks", scene_stacked_blocks),
    ("cylinder_on_block_2d", scene_cylinder_on_block_2d),
    ("stacked_blocks_pen", lambda: scene_stacked_blocks(1.0e-4)),
    ("plane_cylinder_cpp", scene_plane_cylinder_cpp),
    ("stacked_blocks_rotated", scene_stacked_blocks_rotated),
    ("cylinder_on_plate_quads", scene_cylinder_on_plate_quads),
    ("folded_strip", scene_folded_strip),
]


def main():
    only = set(sys.argv[1:])
    os.makedirs(OUT, exist_ok=True)
    import gmsh
    gmsh.initialize(["gmsh", "-nopopup"])
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        for name, fn in SCENES:
            if only and name not in only:
                continue
            m = fn()
            by_name = dict((p[0], p) for p in m.parts)
            n_slave = len(by_name["Parts_Slave"][2]) if "Parts_Slave" in by_name else 0
            n_master = len(by_name["Parts_Master"][2]) if "Parts_Master" in by_name else 0
            head = ("csm contact-search scene '%s', generated by tools/gen_scenes.py (do not edit)\n"
                    "%d nodes, %d elements, %d conditions (%d slave, %d master)"
                    % (name, len(m.nodes), len(m.elements), len(m.conditions), n_slave, n_master))
            path = os.path.join(OUT, name + ".mdpa")
            m.write(path, head)
            print("%-24s %6d nodes %6d elements %5d slave %5d master  %7.0f kB"
                  % (name, len(m.nodes), len(m.elements), n_slave, n_master, os.path.getsize(path) / 1024.0))
    finally:
        gmsh.finalize()


if __name__ == "__main__":
    main()
