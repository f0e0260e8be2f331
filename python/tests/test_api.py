"""The Python API against the command line (same RESULT.json, plan and info), the round trip
through arrays, meshio meshes, and the errors of bad input."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import csm
from conftest import ROOT, load, search_fixtures, without_timings

SCENES = ROOT / "tests" / "data" / "scenes"
SETUP = {
    "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
    "assume_master_slave": {"0": ["Parts_Slave"]},
}


def run_cli(csm_bin: Path, *args: str) -> str:
    done = subprocess.run([str(csm_bin), *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.mark.parametrize(
    "mesh, setup",
    [
        ("stacked_blocks.mdpa", SETUP),
        ("cylinder_on_block_2d.mdpa", SETUP),
        ("sphere_on_plate_mixed.mdpa", {**SETUP, "search_parameters": {"type_search": "in_box"}}),
    ],
)
def test_to_json_is_the_cli_result(csm_bin: Path, tmp_path: Path, mesh: str, setup: dict) -> None:
    setup_file = tmp_path / "setup.json"
    setup_file.write_text(json.dumps(setup))
    out = tmp_path / "RESULT.json"
    run_cli(csm_bin, "search", str(SCENES / mesh), "--setup", str(setup_file), "-o", str(out), "--quiet")
    cli = out.read_text()
    for given in (setup, setup_file, str(setup_file)):
        ours = csm.search(SCENES / mesh, given).to_json()
        assert without_timings(ours) == without_timings(cli)
        # The same text, line for line, but the times.
        strip = lambda t: [l for l in t.splitlines() if not l.lstrip().startswith(('"read"', '"initialize"', '"search"', '"total"'))]
        assert strip(ours) == strip(cli)


def test_default_setup_is_the_cli_default(csm_bin: Path, tmp_path: Path) -> None:
    mesh = ROOT / "tests" / "data" / "boxes.mdpa"
    out = tmp_path / "RESULT.json"
    run_cli(csm_bin, "search", str(mesh), "-o", str(out), "--quiet")
    assert without_timings(csm.search(mesh).to_json()) == without_timings(out.read_text())


def test_plan_and_info_are_the_cli_json(csm_bin: Path, tmp_path: Path) -> None:
    mesh = SCENES / "stacked_blocks.mdpa"
    setup_file = tmp_path / "setup.json"
    setup_file.write_text(json.dumps(SETUP))
    assert csm.plan(mesh, SETUP) == json.loads(run_cli(csm_bin, "plan", str(mesh), "--setup", str(setup_file), "--json"))
    assert csm.info(mesh) == json.loads(run_cli(csm_bin, "info", str(mesh), "--json"))
    assert csm.info(csm.read_mesh(mesh)) == csm.info(mesh)


def test_result_arrays_agree_with_its_json() -> None:
    result = csm.search(SCENES / "stacked_blocks.mdpa", SETUP, threads=1)
    value = json.loads(result.to_json())
    pairs = [[int(s), m] for s, ms in value["pairs"]["0"].items() for m in ms]
    assert result.pairs["0"].tolist() == pairs
    assert result.node_ids.tolist() == [int(k) for k in value["nodes"]]
    assert result.active.tolist() == [n["active"] for n in value["nodes"].values()]
    gaps = [np.nan if n["normal_gap"] is None else n["normal_gap"] for n in value["nodes"].values()]
    np.testing.assert_array_equal(result.normal_gap, np.array(gaps))
    assert result.paired_conditions == value["paired_conditions"]
    assert result.warnings == value["warnings"]
    assert set(result.timings) == {"read", "initialize", "search", "total"}
    assert result.steps == []
    # Every thread count gives the same result.
    two = csm.search(SCENES / "stacked_blocks.mdpa", SETUP, threads=2)
    assert without_timings(two.to_json()) == without_timings(result.to_json())


def fixture_meshes():
    seen = {}
    for path in search_fixtures():
        fixture = load(path)
        if "error" not in fixture:
            seen.setdefault(fixture["mesh"], fixture["setup"])
    return sorted(seen.items())


@pytest.mark.parametrize("mesh, setup", fixture_meshes(), ids=lambda v: Path(v).stem if isinstance(v, str) else "")
def test_round_trip_through_arrays_gives_identical_results(mesh: str, setup: dict) -> None:
    original = csm.read_mesh(ROOT / mesh)
    arrays = original.to_arrays()
    assert arrays["points"].shape == (len(arrays["node_ids"]), 3)
    for kind, (ids, conn) in {**arrays["elements"], **arrays["conditions"]}.items():
        assert ids.dtype == np.int64 and conn.shape[0] == len(ids)
    rebuilt = csm.Mesh.from_arrays(**arrays)
    again = rebuilt.to_arrays()
    assert again.keys() == arrays.keys()
    np.testing.assert_array_equal(again["points"], arrays["points"])
    expected = without_timings(csm.search(original, setup).to_json())
    assert without_timings(csm.search(rebuilt, setup).to_json()) == expected
    # The search left the mesh as it was.
    assert without_timings(csm.search(original, setup).to_json()) == expected


def tetra_on_block():
    """Two tetrahedra stacked along z, 0.01 apart, their facing faces as parts."""
    points = np.array(
        [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, -1], [0, 0, 0.01], [1, 0, 0.01], [0, 1, 0.01], [0, 0, 1]],
        dtype=float,
    )
    return {
        "node_ids": np.arange(1, 9),
        "points": points,
        "elements": {"Tetrahedra3D4": (np.array([1, 2]), np.array([[1, 3, 2, 4], [5, 6, 7, 8]]))},
        "conditions": {"Triangle3D3": (np.array([1, 2]), np.array([[1, 2, 3], [5, 7, 6]]))},
        "parts": {
            "Master": {"nodes": np.array([1, 2, 3]), "conditions": np.array([1]), "elements": np.array([1])},
            "Slave": {"nodes": np.array([5, 6, 7]), "conditions": np.array([2]), "elements": np.array([2])},
        },
    }


def test_mesh_from_arrays_searches() -> None:
    arrays = tetra_on_block()
    mesh = csm.Mesh.from_arrays(**arrays)
    assert repr(mesh) == "csm.Mesh(8 nodes, 2 elements, 2 conditions, 2 sub model parts)"
    result = csm.search(mesh)
    assert result.pairs["0"].tolist() == [[2, 1]]
    assert result.node_ids.tolist() == [5, 6, 7]
    # Open by 0.01: inactive, and Kratos zeroes an inactive node's NORMAL_GAP (Q24).
    assert result.active.tolist() == [False] * 3
    np.testing.assert_array_equal(result.normal_gap, [0.0, 0.0, 0.0])
    # Pressed in by 0.01: the two slave nodes off the master's corner are active at -0.01.
    arrays["points"][4:7, 2] = -0.01
    pressed = csm.search(csm.Mesh.from_arrays(**arrays))
    assert pressed.active.tolist() == [False, True, True]
    np.testing.assert_allclose(pressed.normal_gap[1:], [-0.01, -0.01], rtol=1e-9)


def test_empty_id_lists_of_any_dtype_are_accepted() -> None:
    arrays = tetra_on_block()
    arrays["parts"]["Master"]["elements"] = np.array([])  # float64, as numpy makes it
    arrays["parts"]["Slave"]["elements"] = []
    mesh = csm.Mesh.from_arrays(**arrays)
    assert mesh.to_arrays()["parts"]["Master"]["elements"].tolist() == []


def test_mesh_from_meshio_gives_the_same_search() -> None:
    meshio = pytest.importorskip("meshio")
    a = tetra_on_block()
    m = meshio.Mesh(
        a["points"],
        [("tetra", a["elements"]["Tetrahedra3D4"][1] - 1), ("triangle", a["conditions"]["Triangle3D3"][1] - 1)],
        cell_sets={"Master": [np.array([], dtype=int), np.array([0])], "Slave": [np.array([], dtype=int), np.array([1])]},
    )
    mesh = csm.Mesh.from_meshio(m)
    arrays = mesh.to_arrays()
    # meshio cells are numbered in block order: the triangles are cells 3 and 4.
    assert arrays["conditions"]["Triangle3D3"][0].tolist() == [3, 4]
    assert arrays["parts"]["Slave"]["nodes"].tolist() == [5, 6, 7]
    result = csm.search(mesh)
    assert result.pairs["0"].tolist() == [[4, 3]]
    for part in a["parts"].values():
        del part["elements"]
    reference = csm.search(csm.Mesh.from_arrays(**a))
    np.testing.assert_array_equal(result.normal_gap, reference.normal_gap)
    np.testing.assert_array_equal(result.active, reference.active)


def error_of(**changes) -> str:
    a = tetra_on_block()
    a.update(changes)
    with pytest.raises(csm.Error) as e:
        csm.Mesh.from_arrays(**a)
    return str(e.value)


def test_bad_arrays_give_clear_errors() -> None:
    points = tetra_on_block()["points"]
    assert error_of(points=points[:, :2]) == "points: expected shape (8, 3), got (8, 2)"
    assert error_of(node_ids=np.arange(1, 8)) == "points: expected shape (7, 3), got (8, 3)"
    nan = points.copy()
    nan[4, 2] = np.nan
    assert error_of(points=nan) == "node 5 has a NaN or infinite coordinate"
    assert error_of(node_ids=np.arange(1, 9) * 1.5).startswith("node_ids: expected integers, got dtype float64")
    assert error_of(node_ids=np.arange(-1, 7)).startswith("node_ids: value -1 at flat position 0 is not an id")
    assert error_of(elements={"Tetrahedra3D5": (np.array([1]), np.array([[1, 2, 3, 4]]))}).startswith(
        "elements: unknown geometry kind `Tetrahedra3D5`; the kinds are: Line2D2,"
    )
    assert error_of(conditions={"Triangle3D3": (np.array([1]), np.array([[1, 2, 99]]))}) == (
        "condition 1 refers to node 99, which does not exist"
    )
    assert error_of(conditions={"Triangle3D3": (np.array([1, 2]), np.array([[1, 2, 3, 4]]))}) == (
        'conditions["Triangle3D3"] connectivity: expected shape (2, 3), got (1, 4)'
    )
    assert error_of(conditions={"Triangle3D3": np.array([1])}) == (
        'conditions["Triangle3D3"]: expected a tuple (ids, connectivity)'
    )
    assert error_of(parts={"Slave": {"conditions": np.array([7])}}) == (
        "sub model part `Slave` lists condition 7, which does not exist"
    )
    assert error_of(parts=[1]) == "parts: expected a dict, got list"


def test_bad_files_and_arguments_give_the_cli_errors(tmp_path: Path) -> None:
    with pytest.raises(csm.Error, match="missing.mdpa"):
        csm.read_mesh(tmp_path / "missing.mdpa")
    broken = tmp_path / "broken.mdpa"
    broken.write_text("Begin Nodes\n1 0.0 0.0\nEnd Nodes\n")
    with pytest.raises(csm.Error, match=r"broken\.mdpa:3: expected a finite z coordinate"):
        csm.read_mesh(broken)
    mesh = SCENES / "stacked_blocks.mdpa"
    with pytest.raises(csm.Error, match="no part named `slave`"):
        csm.search(mesh)
    with pytest.raises(csm.Error, match="setup:1: expected a known setup key, found `tolerance`"):
        csm.search(mesh, {**SETUP, "tolerance": 1e-3})
    with pytest.raises(csm.Error, match="nosetup.json: cannot read"):
        csm.search(mesh, tmp_path / "nosetup.json")
    with pytest.raises(csm.Error, match="threads: at least 1"):
        csm.search(mesh, SETUP, threads=0)
    with pytest.raises(csm.Error, match="mesh: expected a path or a csm.Mesh, got int"):
        csm.search(3, SETUP)
    with pytest.raises(csm.Error, match="setup: expected a dict, a path or None, got list"):
        csm.search(mesh, [1])


def test_vtk_binary_and_ascii_hold_the_same_grid(csm_bin: Path, tmp_path: Path) -> None:
    mesh = SCENES / "stacked_blocks.mdpa"
    binary, ascii_ = tmp_path / "b.vtu", tmp_path / "a.vtu"
    csm.search(mesh, SETUP, vtk=binary)
    csm.search(mesh, SETUP, vtk=ascii_, vtk_ascii=True)
    assert b'format="appended"' in binary.read_bytes()[:4000]
    assert binary.stat().st_size < ascii_.stat().st_size
    # Every array, read here from both forms. (meshio 5.3 cannot be the reader: it mixes up
    # the data arrays of raw appended files as it renumbers their offsets.)
    raw, text = appended_arrays(binary.read_bytes()), ascii_arrays(ascii_.read_text())
    assert [name for name, _ in raw] == [name for name, _ in text]
    for (name, values), (_, expected) in zip(raw, text):
        np.testing.assert_array_equal(values, expected, err_msg=name)
    arrays = dict(raw)
    mesh_arrays = csm.read_mesh(mesh).to_arrays()
    n = len(mesh_arrays["node_ids"])
    np.testing.assert_array_equal(arrays["node_id"][:n], mesh_arrays["node_ids"])
    np.testing.assert_array_equal(arrays["Points"].reshape(-1, 3)[:n], mesh_arrays["points"])
    # The CLI writes the same bytes.
    cli = tmp_path / "cli.vtu"
    setup_file = tmp_path / "setup.json"
    setup_file.write_text(json.dumps(SETUP))
    run_cli(csm_bin, "search", str(mesh), "--setup", str(setup_file), "-o", str(tmp_path / "r.json"), "--vtk", str(cli), "--quiet")
    assert cli.read_bytes() == binary.read_bytes()


def appended_arrays(data: bytes):
    """(name, values) of every DataArray of a raw appended VTU, in file order."""
    import re

    start = data.index(b'<AppendedData encoding="raw">\n   _') + len(b'<AppendedData encoding="raw">\n   _')
    header = data[:start].decode()
    types = {"Int64": "<i8", "Int32": "<i4", "Int8": "i1", "Float64": "<f8", "UInt8": "u1"}
    out = []
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="\d+" format="appended" offset="(\d+)"/>', header):
        at = start + int(m.group(3))
        size = int(np.frombuffer(data[at : at + 8], "<u8")[0])
        out.append((m.group(2), np.frombuffer(data[at + 8 : at + 8 + size], types[m.group(1)])))
    return out


def ascii_arrays(text: str):
    """(name, values) of every DataArray of an ASCII VTU, in file order."""
    import re

    out = []
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="ascii">(.*?)</DataArray>', text, re.S):
        dtype = np.float64 if m.group(1) == "Float64" else np.int64
        out.append((m.group(2), np.array(m.group(3).split(), dtype=dtype)))
    return out
