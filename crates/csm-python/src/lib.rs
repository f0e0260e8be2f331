//! The Python module `csm` (its native part, `csm._csm`): a thin binding over the csm facade.
//!
//! It converts arguments (paths, setup dicts, numpy arrays) and results (numpy arrays, dicts)
//! and calls the facade — the same functions the `csm` binary calls, so a search from Python
//! has the command line's semantics, defaults, errors and RESULT.json text. Every error is a
//! `csm.Error` carrying csm's own message. The GIL is released while csm reads, searches and
//! builds meshes.
//!
//! **Architecture Invariant:** no algorithm lives here (STYLE.md 22); the Python side
//! (`python/csm/`) adds `plan` and `info` as dicts and meshio's cells as arrays
//! (`_meshio.py`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use csm::geometry::GeometryKind;
use csm::model::{EntityArrays, MeshArrays, ModelPart, PartArrays};
use csm::search::{SearchResult, SearchSetup};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

pyo3::create_exception!(
    csm,
    Error,
    PyException,
    "An error of csm: a bad mesh, setup or array, with csm's own message (`file:line: what \
     was expected`)."
);

/// A csm error message as a `csm.Error`.
fn error(message: impl std::fmt::Display) -> PyErr {
    Error::new_err(message.to_string())
}

/// A mesh: nodes, elements, conditions and sub model parts, as csm reads them.
#[pyclass(module = "csm", name = "Mesh", frozen)]
struct Mesh {
    model: ModelPart,
}

#[pymethods]
impl Mesh {
    /// The mesh as arrays: `node_ids` (int64 (n,)); `points` (float64 (n, 3), the current
    /// coordinates); `elements` and `conditions` (`{kind: (ids, connectivity)}`, `kind` a
    /// Kratos geometry name such as `Triangle3D3`, connectivity in node ids); `parts`
    /// (`{full path: {"nodes": ids, "elements": ids, "conditions": ids}}`); `properties`
    /// (`{"elements": {kind: ids}, "conditions": {kind: ids}}`); `domain_size` (2 or 3).
    /// `Mesh.from_arrays(**arrays)` gives the same mesh back, and the same search results.
    fn to_arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let arrays = py.detach(|| self.model.to_arrays());
        arrays_to_dict(py, arrays)
    }

    /// The mesh of the arrays of `to_arrays()`: `node_ids`, `points` (n, 3), and optionally
    /// `elements`, `conditions`, `parts`, `properties` (default 0) and `domain_size` (default:
    /// 2 when every geometry is 2D, else 3, as the readers decide it). Raises `csm.Error` on a
    /// wrong shape or dtype, an unknown geometry kind, a duplicate id, a NaN or infinite
    /// coordinate, a connectivity naming a missing node, or a part listing a missing entity.
    // The arguments are the Python keyword arguments, the keys of `to_arrays()`.
    #[allow(clippy::too_many_arguments)]
    #[staticmethod]
    #[pyo3(signature = (node_ids, points, elements=None, conditions=None, parts=None, properties=None, domain_size=None))]
    fn from_arrays(
        py: Python<'_>,
        node_ids: &Bound<'_, PyAny>,
        points: &Bound<'_, PyAny>,
        elements: Option<&Bound<'_, PyAny>>,
        conditions: Option<&Bound<'_, PyAny>>,
        parts: Option<&Bound<'_, PyAny>>,
        properties: Option<&Bound<'_, PyAny>>,
        domain_size: Option<u32>,
    ) -> PyResult<Mesh> {
        let mut arrays = dict_to_arrays(
            py,
            (node_ids, points),
            (elements, conditions),
            parts,
            properties,
        )?;
        arrays.domain_size = domain_size;
        let model = py
            .detach(|| ModelPart::from_arrays("Structure", &arrays))
            .map_err(error)?;
        Ok(Mesh { model })
    }

    /// The mesh of a meshio mesh: nodes 1..n, cells 1..m in block order; the cells of the
    /// mesh's dimension (3 with a volume cell or a non-zero z, else 2; `dim` overrides) are
    /// elements, the cells one dimension lower conditions; each cell set becomes a sub model
    /// part with its cells and their nodes.
    #[staticmethod]
    #[pyo3(signature = (mesh, dim=None))]
    fn from_meshio(py: Python<'_>, mesh: &Bound<'_, PyAny>, dim: Option<usize>) -> PyResult<Mesh> {
        let kwargs = py
            .import("csm._meshio")?
            .call_method1("arrays", (mesh, dim))?;
        let kwargs = dict(&kwargs, "meshio arrays")?;
        let get = |key: &str| kwargs.get_item(key);
        let required =
            |key: &str| get(key)?.ok_or_else(|| error(format!("meshio arrays: no `{key}`")));
        Mesh::from_arrays(
            py,
            &required("node_ids")?,
            &required("points")?,
            get("elements")?.as_ref(),
            get("conditions")?.as_ref(),
            get("parts")?.as_ref(),
            None,
            get("domain_size")?.map(|d| d.extract()).transpose()?,
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "csm.Mesh({} nodes, {} elements, {} conditions, {} sub model parts)",
            self.model.nodes().len(),
            self.model.elements().len(),
            self.model.conditions().len(),
            self.model.parts().len()
        )
    }
}

/// The result of a search.
#[pyclass(module = "csm", name = "Result", frozen)]
struct SearchOutcome {
    result: SearchResult,
    /// RESULT.json's `timings_s`.
    timings: Vec<(&'static str, f64)>,
}

#[pymethods]
impl SearchOutcome {
    /// Per pair key, the pairs as an int64 array (n, 2) of `[slave, master]` condition ids.
    #[getter]
    fn pairs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        for (key, slaves) in &self.result.pairs {
            let mut flat = Vec::new();
            for (&slave, masters) in slaves {
                for &master in masters {
                    flat.extend([i64::from(slave), i64::from(master)]);
                }
            }
            let n = flat.len() / 2;
            out.set_item(key, flat.into_pyarray(py).reshape([n, 2])?)?;
        }
        Ok(out)
    }

    /// The ids of the slave-side nodes (int64, ascending).
    #[getter]
    fn node_ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let ids: Vec<i64> = self.result.nodes.keys().map(|&i| i64::from(i)).collect();
        ids.into_pyarray(py).into_any()
    }

    /// NORMAL_GAP of every node of `node_ids` (float64, NaN where never written).
    #[getter]
    fn normal_gap<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let gaps: Vec<f64> = self
            .result
            .nodes
            .values()
            .map(|n| n.normal_gap.unwrap_or(f64::NAN))
            .collect();
        gaps.into_pyarray(py).into_any()
    }

    /// The ACTIVE flag of every node of `node_ids` (bool).
    #[getter]
    fn active<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let active: Vec<bool> = self.result.nodes.values().map(|n| n.active).collect();
        active.into_pyarray(py).into_any()
    }

    /// The number of paired conditions created (Kratos' ComputingContact count).
    #[getter]
    fn paired_conditions(&self) -> usize {
        self.result.paired_conditions
    }

    /// The warnings of the setup and of the run.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.result.warnings.clone()
    }

    /// Wall times of the phases in seconds (RESULT.json's `timings_s`).
    #[getter]
    fn timings(&self) -> BTreeMap<&'static str, f64> {
        self.timings.iter().copied().collect()
    }

    /// Contact condition ids Kratos renumbers (file id → Kratos id; empty when none).
    #[getter]
    fn kratos_condition_ids(&self) -> BTreeMap<u32, u32> {
        self.result.kratos_condition_ids.clone()
    }

    /// MPCContactProcess: the master-slave constraints created; `None` for the others.
    #[getter]
    fn master_slave_constraints(&self) -> Option<usize> {
        self.result.master_slave_constraints
    }

    /// The results of the steps of a multi-step run, in order (empty for one step).
    #[getter]
    fn steps(&self) -> Vec<SearchOutcome> {
        self.result
            .steps
            .iter()
            .map(|s| SearchOutcome {
                result: s.result.clone(),
                timings: vec![("search", s.search_s)],
            })
            .collect()
    }

    /// RESULT.json (`csm-result/1`): exactly the text `csm search` writes.
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        py.detach(|| {
            let mut text = Vec::new();
            self.result
                .write_json(&self.timings, &mut text)
                .map_err(|e| format!("cannot format JSON: {e}"))?;
            String::from_utf8(text).map_err(|e| format!("cannot format JSON: {e}"))
        })
        .map_err(error)
    }

    fn __repr__(&self) -> String {
        format!(
            "csm.Result({} pairs, {} slave nodes, {} active, {} paired conditions)",
            self.result.n_pairs(),
            self.result.nodes.len(),
            self.result.nodes.values().filter(|n| n.active).count(),
            self.result.paired_conditions
        )
    }
}

/// Reads a `.msh` (Gmsh 2.2, 4.1) or `.mdpa` (Kratos) file.
#[pyfunction]
fn read_mesh(py: Python<'_>, path: PathBuf) -> PyResult<Mesh> {
    let model = py.detach(|| csm::io::read_mesh(&path)).map_err(error)?;
    Ok(Mesh { model })
}

/// Runs the search as `csm search MESH --setup SETUP --threads N` does: one search step, or
/// every step of the setup's `steps`, and returns a `csm.Result`. `mesh`: a path (`.mdpa`,
/// `.msh`) or a `csm.Mesh` (searched on a copy, left unchanged). `setup`: the Parameters of a
/// Kratos contact process (or a whole ProjectParameters) as a dict or a JSON file; `None`
/// searches the parts named `slave` and `master` (any case) with the defaults. `threads`:
/// worker threads (`None`: every core). `vtk`: also write the mesh, flags and pairs for
/// ParaView (VTU with raw binary data; `vtk_ascii=True` for text). The GIL is released while
/// it runs; errors raise `csm.Error` with csm's message.
#[pyfunction]
#[pyo3(signature = (mesh, setup=None, threads=None, vtk=None, vtk_ascii=false))]
fn search(
    py: Python<'_>,
    mesh: &Bound<'_, PyAny>,
    setup: Option<&Bound<'_, PyAny>>,
    threads: Option<usize>,
    vtk: Option<PathBuf>,
    vtk_ascii: bool,
) -> PyResult<SearchOutcome> {
    let mesh = MeshArg::new(mesh)?;
    let setup = SetupArg::new(py, setup)?;
    let pool = match threads {
        Some(0) => return Err(error("threads: at least 1 (None: every core)")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| error(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    let run = || -> Result<SearchOutcome, String> {
        let start = std::time::Instant::now();
        let mut model = mesh.model()?;
        let read = start.elapsed().as_secs_f64();
        let setup = setup.setup(&model)?;
        let (result, timings) = csm::cli::run_search(&mut model, &setup, read)?;
        if let Some(path) = &vtk {
            let format = if vtk_ascii {
                csm::io::VtuFormat::Ascii
            } else {
                csm::io::VtuFormat::Binary
            };
            csm::cli::write_search_vtu(&model, &result, path, format)?;
        }
        Ok(SearchOutcome {
            result,
            timings: timings.entries().to_vec(),
        })
    };
    py.detach(|| match &pool {
        Some(pool) => pool.install(run),
        None => run(),
    })
    .map_err(error)
}

/// `csm plan --json`: which stages a search would run and which structures it would build.
#[pyfunction]
#[pyo3(signature = (mesh, setup=None))]
fn plan_json(
    py: Python<'_>,
    mesh: &Bound<'_, PyAny>,
    setup: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let mesh = MeshArg::new(mesh)?;
    let setup = SetupArg::new(py, setup)?;
    py.detach(|| -> Result<String, String> {
        let model = mesh.model()?;
        let setup = setup.setup(&model)?;
        let plan = csm::cli::search_plan(&model, &setup)?;
        Ok(plan.to_json().to_string())
    })
    .map_err(error)
}

/// `csm info --json`: parts, counts and geometry kinds.
#[pyfunction]
fn info_json(py: Python<'_>, mesh: &Bound<'_, PyAny>) -> PyResult<String> {
    let mesh = MeshArg::new(mesh)?;
    py.detach(|| -> Result<String, String> {
        let model = mesh.model()?;
        Ok(csm::cli::mesh_info(&model).to_json().to_string())
    })
    .map_err(error)
}

/// A mesh argument: a `csm.Mesh` (searched on a copy) or a path to read.
enum MeshArg {
    Mesh(Py<Mesh>),
    Path(PathBuf),
}

impl MeshArg {
    fn new(mesh: &Bound<'_, PyAny>) -> PyResult<MeshArg> {
        if let Ok(m) = mesh.cast::<Mesh>() {
            return Ok(MeshArg::Mesh(m.clone().unbind()));
        }
        mesh.extract::<PathBuf>().map(MeshArg::Path).map_err(|_| {
            error(format!(
                "mesh: expected a path or a csm.Mesh, got {}",
                type_name(mesh)
            ))
        })
    }

    /// The model to search: the file read, or a copy of the mesh (a search changes it).
    fn model(&self) -> Result<ModelPart, String> {
        match self {
            MeshArg::Mesh(m) => Ok(m.get().model.clone()),
            MeshArg::Path(path) => csm::io::read_mesh(path).map_err(|e| e.to_string()),
        }
    }
}

/// A setup argument: none (the parts named slave and master), a path, or a dict (the JSON of
/// SETUP.json).
enum SetupArg {
    Default,
    Path(PathBuf),
    Text(String),
}

impl SetupArg {
    fn new(py: Python<'_>, setup: Option<&Bound<'_, PyAny>>) -> PyResult<SetupArg> {
        let Some(setup) = setup.filter(|s| !s.is_none()) else {
            return Ok(SetupArg::Default);
        };
        if setup.cast::<PyDict>().is_ok() {
            let text: String = py
                .import("json")?
                .call_method1("dumps", (setup,))
                .map_err(|e| error(format!("setup: not JSON: {e}")))?
                .extract()?;
            return Ok(SetupArg::Text(text));
        }
        setup.extract::<PathBuf>().map(SetupArg::Path).map_err(|_| {
            error(format!(
                "setup: expected a dict, a path or None, got {}",
                type_name(setup)
            ))
        })
    }

    /// The setup as `csm search --setup` reads it (the parts named slave and master without).
    fn setup(&self, model: &ModelPart) -> Result<SearchSetup, String> {
        match self {
            SetupArg::Default => csm::cli::setup_for(None, model),
            SetupArg::Path(path) => csm::cli::setup_for(Some(path), model),
            SetupArg::Text(text) => csm::cli::load_setup(text, "setup"),
        }
    }
}

/// The Python type name of `obj`, for messages.
fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "?".to_owned(), |n| n.to_string())
}

/// [`MeshArrays`] as the dict of `Mesh.to_arrays()`.
fn arrays_to_dict(py: Python<'_>, arrays: MeshArrays) -> PyResult<Bound<'_, PyDict>> {
    let ids = |v: Vec<u32>| -> Bound<'_, PyAny> {
        let v: Vec<i64> = v.into_iter().map(i64::from).collect();
        v.into_pyarray(py).into_any()
    };
    let out = PyDict::new(py);
    let n = arrays.points.len();
    let flat: Vec<f64> = arrays.points.into_iter().flatten().collect();
    out.set_item("node_ids", ids(arrays.node_ids))?;
    out.set_item("points", flat.into_pyarray(py).reshape([n, 3])?)?;
    let properties = PyDict::new(py);
    for (name, by_kind) in [
        ("elements", arrays.elements),
        ("conditions", arrays.conditions),
    ] {
        let entities = PyDict::new(py);
        let props = PyDict::new(py);
        for (kind, a) in by_kind {
            let nn = kind.n_nodes();
            let count = a.ids.len();
            let conn: Vec<i64> = a.connectivity.into_iter().map(i64::from).collect();
            let conn = conn.into_pyarray(py).reshape([count, nn])?;
            entities.set_item(kind.name(), (ids(a.ids), conn))?;
            props.set_item(kind.name(), ids(a.properties))?;
        }
        out.set_item(name, entities)?;
        properties.set_item(name, props)?;
    }
    let parts = PyDict::new(py);
    for (path, p) in arrays.parts {
        let part = PyDict::new(py);
        part.set_item("nodes", ids(p.nodes))?;
        part.set_item("elements", ids(p.elements))?;
        part.set_item("conditions", ids(p.conditions))?;
        parts.set_item(path, part)?;
    }
    out.set_item("parts", parts)?;
    out.set_item("properties", properties)?;
    out.set_item("domain_size", arrays.domain_size)?;
    Ok(out)
}

/// `numpy.asarray(obj)` checked to hold integers (`integers`) or numbers, converted to
/// int64 / float64, C-contiguous.
fn numeric<'py, T: numpy::Element>(
    py: Python<'py>,
    obj: &Bound<'py, PyAny>,
    integers: bool,
    what: &str,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let np = py.import("numpy")?;
    let array = np
        .call_method1("asarray", (obj,))
        .map_err(|e| error(format!("{what}: not an array: {e}")))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let allowed = if integers { "iu" } else { "iuf" };
    // An empty array holds no value of a wrong kind (`np.array([])` is float64).
    let empty = array.getattr("size")?.extract::<usize>()? == 0;
    if !empty && (!allowed.contains(kind.as_str()) || kind.is_empty()) {
        let dtype = array.getattr("dtype")?.str()?.to_string();
        let expected = if integers { "integers" } else { "numbers" };
        return Err(error(format!(
            "{what}: expected {expected}, got dtype {dtype}"
        )));
    }
    let dtype = if integers { "int64" } else { "float64" };
    let array = np.call_method1("ascontiguousarray", (array, dtype))?;
    Ok(array.cast_into::<PyArrayDyn<T>>()?)
}

/// An id array of shape `shape` (`None`: any length there) as `u32` ids.
fn ids_of(
    py: Python<'_>,
    obj: &Bound<'_, PyAny>,
    shape: &[Option<usize>],
    what: &str,
) -> PyResult<(Vec<u32>, Vec<usize>)> {
    let array = numeric::<i64>(py, obj, true, what)?;
    let dims = check_shape(array.shape(), shape, what)?;
    let readonly = array.readonly();
    let values = readonly.as_slice().map_err(error)?;
    let mut out = Vec::with_capacity(values.len());
    for (i, &v) in values.iter().enumerate() {
        let id = u32::try_from(v).map_err(|_| {
            error(format!(
                "{what}: value {v} at flat position {i} is not an id (0 to {})",
                u32::MAX
            ))
        })?;
        out.push(id);
    }
    Ok((out, dims))
}

/// `actual` against `expected` (`None`: any size), or an error naming `what`.
fn check_shape(actual: &[usize], expected: &[Option<usize>], what: &str) -> PyResult<Vec<usize>> {
    let fits = actual.len() == expected.len()
        && actual
            .iter()
            .zip(expected)
            .all(|(a, e)| e.is_none_or(|e| e == *a));
    if fits {
        return Ok(actual.to_vec());
    }
    let shape = |dims: Vec<String>| {
        if dims.len() == 1 {
            format!("({},)", dims[0])
        } else {
            format!("({})", dims.join(", "))
        }
    };
    let want = shape(
        expected
            .iter()
            .map(|e| e.map_or_else(|| "n".to_owned(), |e| e.to_string()))
            .collect(),
    );
    let got = shape(actual.iter().map(|a| a.to_string()).collect());
    Err(error(format!("{what}: expected shape {want}, got {got}")))
}

/// The keyword arguments of `Mesh.from_arrays` as [`MeshArrays`].
fn dict_to_arrays(
    py: Python<'_>,
    (node_ids, points): (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
    (elements, conditions): (Option<&Bound<'_, PyAny>>, Option<&Bound<'_, PyAny>>),
    parts: Option<&Bound<'_, PyAny>>,
    properties: Option<&Bound<'_, PyAny>>,
) -> PyResult<MeshArrays> {
    let (node_ids, _) = ids_of(py, node_ids, &[None], "node_ids")?;
    let n = node_ids.len();
    let points_array = numeric::<f64>(py, points, false, "points")?;
    check_shape(points_array.shape(), &[Some(n), Some(3)], "points")?;
    let readonly = points_array.readonly();
    let flat = readonly.as_slice().map_err(error)?;
    let points: Vec<[f64; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut arrays = MeshArrays {
        node_ids,
        points,
        ..MeshArrays::default()
    };
    let properties = match properties.filter(|p| !p.is_none()) {
        Some(p) => Some(dict(p, "properties")?),
        None => None,
    };
    for (name, given) in [("elements", elements), ("conditions", conditions)] {
        let Some(given) = given.filter(|g| !g.is_none()) else {
            continue;
        };
        let by_kind = dict(given, name)?;
        let props = match &properties {
            Some(p) => match p.get_item(name)? {
                Some(d) if !d.is_none() => Some(dict(&d, &format!("properties[{name:?}]"))?),
                _ => None,
            },
            None => None,
        };
        let target = if name == "elements" {
            &mut arrays.elements
        } else {
            &mut arrays.conditions
        };
        for (key, value) in by_kind.iter() {
            let kind_name: String = key
                .extract()
                .map_err(|_| error(format!("{name}: keys are geometry names (str)")))?;
            let kind = GeometryKind::from_name(&kind_name).ok_or_else(|| {
                let known: Vec<&str> = GeometryKind::ALL.iter().map(|k| k.name()).collect();
                error(format!(
                    "{name}: unknown geometry kind `{kind_name}`; the kinds are: {}",
                    known.join(", ")
                ))
            })?;
            let what = format!("{name}[{kind_name:?}]");
            let pair = value
                .cast::<PyTuple>()
                .ok()
                .filter(|t| t.len() == 2)
                .ok_or_else(|| error(format!("{what}: expected a tuple (ids, connectivity)")))?;
            let (ids, _) = ids_of(py, &pair.get_item(0)?, &[None], &format!("{what} ids"))?;
            let count = ids.len();
            let (connectivity, _) = ids_of(
                py,
                &pair.get_item(1)?,
                &[Some(count), Some(kind.n_nodes())],
                &format!("{what} connectivity"),
            )?;
            let entity_properties = match props.as_ref().map(|p| p.get_item(&kind_name)) {
                Some(Ok(Some(p))) => {
                    ids_of(
                        py,
                        &p,
                        &[Some(count)],
                        &format!("properties[{name:?}][{kind_name:?}]"),
                    )?
                    .0
                }
                Some(Err(e)) => return Err(e),
                _ => vec![0; count],
            };
            target.insert(
                kind,
                EntityArrays {
                    ids,
                    connectivity,
                    properties: entity_properties,
                },
            );
        }
    }
    if let Some(parts) = parts.filter(|p| !p.is_none()) {
        for (key, value) in dict(parts, "parts")?.iter() {
            let path: String = key
                .extract()
                .map_err(|_| error("parts: keys are part paths (str)"))?;
            let members = dict(&value, &format!("parts[{path:?}]"))?;
            let mut part = PartArrays::default();
            for (field, target) in [
                ("nodes", &mut part.nodes),
                ("elements", &mut part.elements),
                ("conditions", &mut part.conditions),
            ] {
                if let Some(v) = members.get_item(field)? {
                    *target = ids_of(py, &v, &[None], &format!("parts[{path:?}][{field:?}]"))?.0;
                }
            }
            arrays.parts.insert(path, part);
        }
    }
    Ok(arrays)
}

/// `obj` as a dict, or an error naming `what`.
fn dict<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyDict>> {
    obj.cast::<PyDict>()
        .cloned()
        .map_err(|_| error(format!("{what}: expected a dict, got {}", type_name(obj))))
}

/// The native module `csm._csm`; `csm/__init__.py` re-exports it.
#[pymodule]
fn _csm(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Error", m.py().get_type::<Error>())?;
    m.add_class::<Mesh>()?;
    m.add_class::<SearchOutcome>()?;
    m.add_function(wrap_pyfunction!(read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(search, m)?)?;
    m.add_function(wrap_pyfunction!(plan_json, m)?)?;
    m.add_function(wrap_pyfunction!(info_json, m)?)?;
    Ok(())
}
