"""Type stubs of the native module `csm._csm` (re-exported by `csm`)."""

import os
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "os.PathLike[str]"]
_Ids = npt.NDArray[np.int64]

class Error(Exception):
    """An error of csm: a bad mesh, setup or array, with csm's own message
    (`file:line: what was expected`)."""

class Mesh:
    """A mesh: nodes, elements, conditions and sub model parts, as csm reads them."""

    def to_arrays(self) -> Dict[str, Any]:
        """The mesh as arrays:

        - `node_ids`: int64 (n,); `points`: float64 (n, 3), the current coordinates;
        - `elements`, `conditions`: `{kind: (ids int64 (m,), connectivity int64 (m, k))}`,
          `kind` a Kratos geometry name (`Triangle3D3`, `Hexahedra3D8`, …), connectivity in
          node ids;
        - `parts`: `{full path: {"nodes": ids, "elements": ids, "conditions": ids}}`;
        - `properties`: `{"elements": {kind: ids}, "conditions": {kind: ids}}`, the
          properties id of every entity;
        - `domain_size`: ProcessInfo DOMAIN_SIZE (2 or 3).

        `Mesh.from_arrays(**arrays)` gives the same mesh back (and the same search results).
        """

    @staticmethod
    def from_arrays(
        node_ids: npt.ArrayLike,
        points: npt.ArrayLike,
        elements: Optional[Mapping[str, Tuple[npt.ArrayLike, npt.ArrayLike]]] = None,
        conditions: Optional[Mapping[str, Tuple[npt.ArrayLike, npt.ArrayLike]]] = None,
        parts: Optional[Mapping[str, Mapping[str, npt.ArrayLike]]] = None,
        properties: Optional[Mapping[str, Mapping[str, npt.ArrayLike]]] = None,
        domain_size: Optional[int] = None,
    ) -> "Mesh":
        """The mesh of the arrays of `to_arrays` (properties default to 0; `domain_size`
        to 2 when every geometry is 2D, else 3, as the readers decide it). Raises `Error` on
        a wrong shape or dtype, an unknown geometry kind, a duplicate id, a NaN or infinite
        coordinate, a connectivity naming a missing node, a part listing a missing entity."""

    @staticmethod
    def from_meshio(mesh: Any, dim: Optional[int] = None) -> "Mesh":
        """The mesh of a meshio mesh: nodes 1..n, cells 1..m in block order; cells of the
        mesh's dimension (3 with a volume cell or a non-zero z, else 2; `dim` overrides) are
        elements, cells one dimension lower are conditions; each cell set is a sub model part
        with its cells and their nodes."""

class Result:
    """The result of a search (the content of RESULT.json)."""

    @property
    def pairs(self) -> Dict[str, npt.NDArray[np.int64]]:
        """Per pair key, an int64 array (n, 2) of [slave, master] condition ids (the file's
        ids), sorted."""
    @property
    def node_ids(self) -> _Ids:
        """The slave-side node ids, ascending."""
    @property
    def normal_gap(self) -> npt.NDArray[np.float64]:
        """NORMAL_GAP per node of `node_ids`; NaN where it was never written."""
    @property
    def active(self) -> npt.NDArray[np.bool_]:
        """The ACTIVE flag per node of `node_ids`."""
    @property
    def paired_conditions(self) -> int:
        """The paired conditions created (Kratos' ComputingContact count)."""
    @property
    def warnings(self) -> List[str]:
        """The warnings of the setup and of the run."""
    @property
    def timings(self) -> Dict[str, float]:
        """Wall times in seconds: read, initialize, search, total (a step: search)."""
    @property
    def kratos_condition_ids(self) -> Dict[int, int]:
        """Contact condition ids Kratos renumbers (file id -> Kratos id)."""
    @property
    def master_slave_constraints(self) -> Optional[int]:
        """MPCContactProcess: the constraints created; None for the other processes."""
    @property
    def steps(self) -> List["Result"]:
        """The result of every step of a multi-step run (setup `steps`); empty otherwise."""
    def to_json(self) -> str:
        """RESULT.json (`csm-result/1`): exactly the text `csm search` writes."""

def read_mesh(path: _Path) -> Mesh:
    """Reads a `.msh` (Gmsh 2.2, 4.1, ASCII or binary) or `.mdpa` (Kratos) file."""

def search(
    mesh: Union[_Path, Mesh],
    setup: Union[None, Mapping[str, Any], _Path] = None,
    threads: Optional[int] = None,
    vtk: Optional[_Path] = None,
    vtk_ascii: bool = False,
) -> Result:
    """Runs the search as `csm search MESH --setup SETUP --threads N --vtk OUT.vtu` does: one search step,
    or every step of the setup's `steps`. `setup`: the Parameters of a Kratos contact process
    (or a whole ProjectParameters) as a dict or a JSON file; None searches the parts named
    `slave` and `master` (any case) with the default parameters. `threads`: worker threads
    (None: every core). `vtk`: also write the mesh, flags and pairs for ParaView (VTU, raw
    binary arrays; `vtk_ascii` for text). A `Mesh` is left unchanged (the search runs on a copy). The GIL is
    released while it runs."""

def plan_json(mesh: Union[_Path, Mesh], setup: Union[None, Mapping[str, Any], _Path] = None) -> str: ...
def info_json(mesh: Union[_Path, Mesh]) -> str: ...
