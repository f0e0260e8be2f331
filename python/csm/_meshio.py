"""`Mesh.from_meshio`: a meshio mesh as the keyword arguments of `Mesh.from_arrays`.

meshio has no ids and no elements/conditions split. Nodes get ids 1..n in order and cells
1..m in block order (as Gmsh numbers them). The cells of the mesh's dimension are elements;
the cells one dimension lower are conditions (the faces contact is searched on). Each cell
set becomes a sub model part with its cells and their nodes.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Tuple

import numpy as np

# meshio cell type -> (Kratos geometry in 3D, in 2D, local dimension).
_KINDS: Dict[str, Tuple[Optional[str], Optional[str], int]] = {
    "line": (None, "Line2D2", 1),
    "line3": (None, "Line2D3", 1),
    "triangle": ("Triangle3D3", "Triangle2D3", 2),
    "triangle6": ("Triangle3D6", "Triangle2D6", 2),
    "quad": ("Quadrilateral3D4", "Quadrilateral2D4", 2),
    "quad8": ("Quadrilateral3D8", "Quadrilateral2D8", 2),
    "quad9": ("Quadrilateral3D9", "Quadrilateral2D9", 2),
    "tetra": ("Tetrahedra3D4", None, 3),
    "tetra10": ("Tetrahedra3D10", None, 3),
    "hexahedron": ("Hexahedra3D8", None, 3),
    "hexahedron20": ("Hexahedra3D20", None, 3),
    "hexahedron27": ("Hexahedra3D27", None, 3),
    "wedge": ("Prism3D6", None, 3),
}


def _cell_blocks(mesh: Any) -> List[Tuple[str, np.ndarray]]:
    return [(block.type, np.asarray(block.data)) for block in mesh.cells]


def arrays(mesh: Any, dim: Optional[int] = None) -> Dict[str, Any]:
    """The keyword arguments of `Mesh.from_arrays` for the meshio mesh `mesh`; `dim` (2 or 3)
    overrides the dimension read from the cells (3 with a volume cell or a non-zero z)."""
    from . import Error

    points = np.asarray(mesh.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise Error(f"meshio points: expected shape (n, 2) or (n, 3), got {points.shape}")
    if points.shape[1] == 2:
        points = np.hstack([points, np.zeros((len(points), 1))])
    blocks = _cell_blocks(mesh)
    for kind, _ in blocks:
        if kind not in _KINDS:
            known = ", ".join(sorted(_KINDS))
            raise Error(f"meshio cell type `{kind}` has no csm geometry; the types are: {known}")
    if dim is None:
        volume = any(_KINDS[kind][2] == 3 for kind, _ in blocks)
        dim = 3 if volume or bool(np.any(points[:, 2] != 0.0)) else 2
    if dim not in (2, 3):
        raise Error(f"dim: 2 or 3, got {dim}")
    node_ids = np.arange(1, len(points) + 1, dtype=np.int64)
    elements: Dict[str, List[Tuple[np.ndarray, np.ndarray]]] = {}
    conditions: Dict[str, List[Tuple[np.ndarray, np.ndarray]]] = {}
    # Per block: its cells' ids (None for cells of no use: points, lines in 3D, ...).
    block_ids: List[Optional[np.ndarray]] = []
    next_id = 1
    for kind, data in blocks:
        ids = np.arange(next_id, next_id + len(data), dtype=np.int64)
        next_id += len(data)
        name_3d, name_2d, local = _KINDS[kind]
        name = name_3d if dim == 3 else name_2d
        if name is None or local < dim - 1:
            block_ids.append(None)
            continue
        target = elements if local == dim else conditions
        target.setdefault(name, []).append((ids, data.astype(np.int64) + 1))
        block_ids.append(ids)

    def merged(by_kind: Dict[str, List[Tuple[np.ndarray, np.ndarray]]]) -> Dict[str, Any]:
        return {
            name: (np.concatenate([i for i, _ in parts]), np.concatenate([c for _, c in parts]))
            for name, parts in by_kind.items()
        }

    parts: Dict[str, Dict[str, np.ndarray]] = {}
    for set_name, per_block in getattr(mesh, "cell_sets", {}).items():
        members_e: List[np.ndarray] = []
        members_c: List[np.ndarray] = []
        nodes: List[np.ndarray] = []
        for (kind, data), ids, selected in zip(blocks, block_ids, per_block):
            if ids is None or selected is None or len(selected) == 0:
                continue
            selected = np.asarray(selected, dtype=np.int64)
            chosen = ids[selected]
            is_element = _KINDS[kind][2] == dim
            (members_e if is_element else members_c).append(chosen)
            nodes.append(np.unique(data[selected].astype(np.int64) + 1))
        empty = np.zeros(0, dtype=np.int64)
        parts[str(set_name)] = {
            "nodes": np.unique(np.concatenate(nodes)) if nodes else empty,
            "elements": np.concatenate(members_e) if members_e else empty,
            "conditions": np.concatenate(members_c) if members_c else empty,
        }
    return {
        "node_ids": node_ids,
        "points": points,
        "elements": merged(elements),
        "conditions": merged(conditions),
        "parts": parts,
        "domain_size": dim,
    }
