"""csm: finite-element contact search.

Given the surface meshes of bodies that may touch, csm finds every slave/master face pair that
can come into contact, computes the normal gap and decides which slave nodes are active — the
contact search of Kratos Multiphysics' ContactStructuralMechanicsApplication (10.4.4),
reimplemented in Rust.

>>> import csm
>>> result = csm.search("mesh.mdpa", {"contact_model_part": {"0": ["Slave", "Master"]},
...                                   "assume_master_slave": {"0": ["Slave"]}})
>>> result.pairs["0"]        # int64 (n, 2): [slave, master] condition ids
>>> result.normal_gap        # float64 per result.node_ids, NaN where never written

Every function has the semantics, defaults and errors of the command line (`csm search`,
`csm plan --json`, `csm info --json`); errors are `csm.Error` with csm's own message.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Optional, Union

from ._csm import Error, Mesh, Result, read_mesh, search
from ._csm import info_json as _info_json
from ._csm import plan_json as _plan_json

__all__ = ["Error", "Mesh", "Result", "info", "plan", "read_mesh", "search"]

MeshLike = Union[str, "os.PathLike[str]", Mesh]
SetupLike = Union[None, Dict[str, Any], str, "os.PathLike[str]"]


def plan(mesh: MeshLike, setup: SetupLike = None) -> Dict[str, Any]:
    """Which stages a search of `mesh` with `setup` runs and which structures it builds, and
    why the others are left out: the dict of `csm plan --json`."""
    return json.loads(_plan_json(mesh, setup))


def info(mesh: MeshLike) -> Dict[str, Any]:
    """The sub model parts with their node, element and condition counts and geometry kinds:
    the dict of `csm info --json`."""
    return json.loads(_info_json(mesh))
