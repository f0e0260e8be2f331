//! The VTU writer: a model part as a VTK XML UnstructuredGrid, binary (raw appended data, what
//! ParaView reads fastest) or ASCII (diff-friendly).
//!
//! Points are the nodes in dense order (current coordinates), then the extra points (e.g.
//! condition centres) in the order given. Cells are the elements, then the conditions, then
//! the line cells, each in dense order. Built-in arrays: point data `node_id` (−1 on extra
//! points); cell data `entity_id` (the file id; the index of the line for line cells) and
//! `entity_kind` (0 element, 1 condition, 2 line cell). A point data array holds one tuple per
//! point, or one per node only: then it is padded on the extra points with NaN (`Float64`) or
//! −1 (`Int64`). In the ASCII form floats are written in Rust's
//! shortest round-trip scientific form (`{:e}`, e.g. `2.5e-1`), NaN as `nan`, infinities as
//! `inf`/`-inf`; the output is byte-identical for the same input.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use csm_geometry::math::Point;
use csm_model::{ModelPart, NodeIdx};

use crate::error::{Error, ErrorKind, Location};
use crate::vtu::cell_type::{vtk_cell_type, vtk_permutation};

/// Values of a data array: `components` values per point or cell, flattened.
#[derive(Debug, Clone, PartialEq)]
pub enum DataArray {
    /// `Float64` values.
    F64 {
        /// Components per tuple (1 scalar, 3 vector).
        components: usize,
        /// The values, tuple after tuple.
        values: Vec<f64>,
    },
    /// `Int64` values.
    I64 {
        /// Components per tuple.
        components: usize,
        /// The values, tuple after tuple.
        values: Vec<i64>,
    },
}

impl DataArray {
    fn type_name(&self) -> &'static str {
        match self {
            DataArray::F64 { .. } => "Float64",
            DataArray::I64 { .. } => "Int64",
        }
    }

    fn components(&self) -> usize {
        match self {
            DataArray::F64 { components, .. } | DataArray::I64 { components, .. } => {
                (*components).max(1)
            }
        }
    }

    fn len(&self) -> usize {
        match self {
            DataArray::F64 { values, .. } => values.len(),
            DataArray::I64 { values, .. } => values.len(),
        }
    }
}

/// Writes a model part and caller-supplied data as a `.vtu` file.
#[derive(Debug)]
pub struct VtuWriter<'a> {
    model: &'a ModelPart,
    point_data: Vec<(String, DataArray)>,
    cell_data: Vec<(String, DataArray)>,
    extra_points: Vec<Point>,
    /// Line cells as point indices (nodes, then extra points).
    lines: Vec<[usize; 2]>,
}

fn push_f64(out: &mut String, x: f64) {
    if x.is_nan() {
        out.push_str("nan");
    } else if x.is_infinite() {
        out.push_str(if x > 0.0 { "inf" } else { "-inf" });
    } else {
        let _ = write!(out, "{x:e}");
    }
}

fn escape(name: &str) -> String {
    name.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn write_array(out: &mut String, name: &str, a: &DataArray) {
    let (ty, n) = match a {
        DataArray::F64 { .. } => ("Float64", a.components()),
        DataArray::I64 { .. } => ("Int64", a.components()),
    };
    let _ = writeln!(
        out,
        "        <DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{n}\" format=\"ascii\">",
        escape(name)
    );
    let per_line = n.max(1);
    match a {
        DataArray::F64 { values, .. } => {
            for chunk in values.chunks(per_line) {
                out.push_str("          ");
                for (k, &x) in chunk.iter().enumerate() {
                    if k > 0 {
                        out.push(' ');
                    }
                    push_f64(out, x);
                }
                out.push('\n');
            }
        }
        DataArray::I64 { values, .. } => {
            for chunk in values.chunks(per_line) {
                out.push_str("          ");
                for (k, x) in chunk.iter().enumerate() {
                    if k > 0 {
                        out.push(' ');
                    }
                    let _ = write!(out, "{x}");
                }
                out.push('\n');
            }
        }
    }
    out.push_str("        </DataArray>\n");
}

impl<'a> VtuWriter<'a> {
    /// A writer of `model`'s nodes, elements and conditions.
    pub fn new(model: &'a ModelPart) -> VtuWriter<'a> {
        VtuWriter {
            model,
            point_data: Vec::new(),
            cell_data: Vec::new(),
            extra_points: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// Adds line cells between the given node pairs (e.g. contact pairs), after the
    /// conditions.
    pub fn line_cells(&mut self, lines: &[[NodeIdx; 2]]) -> &mut Self {
        self.lines
            .extend(lines.iter().map(|l| [l[0].index(), l[1].index()]));
        self
    }

    /// Appends points after the nodes (and after the extra points added before): the first
    /// gets the point index `n_points()` at the time of the call.
    pub fn extra_points(&mut self, points: &[Point]) -> &mut Self {
        self.extra_points.extend_from_slice(points);
        self
    }

    /// Adds line cells between point indices: `0..n_nodes` are the nodes, then come the extra
    /// points. An index past the last point is an error of [`VtuWriter::to_xml`].
    pub fn point_line_cells(&mut self, lines: &[[usize; 2]]) -> &mut Self {
        self.lines.extend_from_slice(lines);
        self
    }

    /// Number of points written: nodes + extra points.
    pub fn n_points(&self) -> usize {
        self.model.nodes().len() + self.extra_points.len()
    }

    /// Adds a point data array: one tuple per point, or one per node (dense order), padded on
    /// the extra points with NaN (`Float64`) or −1 (`Int64`).
    pub fn point_data(&mut self, name: &str, data: DataArray) -> &mut Self {
        self.point_data.push((name.to_owned(), data));
        self
    }

    /// Adds a cell data array (one tuple per cell: elements, conditions, line cells).
    pub fn cell_data(&mut self, name: &str, data: DataArray) -> &mut Self {
        self.cell_data.push((name.to_owned(), data));
        self
    }

    /// Number of cells written: elements + conditions + line cells.
    pub fn n_cells(&self) -> usize {
        self.model.elements().len() + self.model.conditions().len() + self.lines.len()
    }

    /// The arrays of the file, checked: errors if a data array has the wrong length or a
    /// line cell names a point that does not exist.
    fn grid(&self, file_name: &str) -> Result<Grid<'_>, Error> {
        let n_nodes = self.model.nodes().len();
        let n_points = self.n_points();
        let n_cells = self.n_cells();
        for (name, a) in &self.point_data {
            let c = a.components();
            if a.len() != n_points * c && a.len() != n_nodes * c {
                return Err(Error::new(
                    file_name,
                    Location::None,
                    ErrorKind::ArrayLength {
                        name: name.clone(),
                        expected: n_points * c,
                        found: a.len(),
                    },
                ));
            }
        }
        if let Some(l) = self
            .lines
            .iter()
            .find(|l| l[0] >= n_points || l[1] >= n_points)
        {
            return Err(Error::new(
                file_name,
                Location::None,
                ErrorKind::Expected {
                    expected: format!("line cells between point indices below {n_points}"),
                    found: format!("a line cell {} – {}", l[0], l[1]),
                },
            ));
        }
        for (name, a) in &self.cell_data {
            if a.len() != n_cells * a.components() {
                return Err(Error::new(
                    file_name,
                    Location::None,
                    ErrorKind::ArrayLength {
                        name: name.clone(),
                        expected: n_cells * a.components(),
                        found: a.len(),
                    },
                ));
            }
        }
        let node_ids = self
            .model
            .nodes()
            .ids()
            .iter()
            .map(|&i| i64::from(i))
            .chain(std::iter::repeat_n(-1, self.extra_points.len()))
            .collect();
        let mut point_data = vec![Array::owned(
            "node_id",
            DataArray::I64 {
                components: 1,
                values: node_ids,
            },
        )];
        for (name, a) in &self.point_data {
            point_data.push(if a.len() == n_points * a.components() {
                Array::borrowed(name, a)
            } else {
                Array::owned(name, padded(a, n_points))
            });
        }
        let (mut ids, mut kinds) = (Vec::with_capacity(n_cells), Vec::with_capacity(n_cells));
        for (k, ents) in [self.model.elements(), self.model.conditions()]
            .into_iter()
            .enumerate()
        {
            ids.extend(ents.ids().iter().map(|&i| i64::from(i)));
            kinds.extend(std::iter::repeat_n(k as i64, ents.len()));
        }
        ids.extend((0..self.lines.len()).map(|i| i as i64));
        kinds.extend(std::iter::repeat_n(2, self.lines.len()));
        let mut cell_data = vec![
            Array::owned(
                "entity_id",
                DataArray::I64 {
                    components: 1,
                    values: ids,
                },
            ),
            Array::owned(
                "entity_kind",
                DataArray::I64 {
                    components: 1,
                    values: kinds,
                },
            ),
        ];
        cell_data.extend(
            self.cell_data
                .iter()
                .map(|(name, a)| Array::borrowed(name, a)),
        );
        let xyz: Vec<f64> = self
            .model
            .nodes()
            .coordinates()
            .iter()
            .chain(&self.extra_points)
            .flat_map(|p| [p.x, p.y, p.z])
            .collect();
        let mut conn: Vec<i64> = Vec::new();
        let mut offsets: Vec<i64> = Vec::with_capacity(n_cells);
        let mut types: Vec<u8> = Vec::with_capacity(n_cells);
        for ents in [self.model.elements(), self.model.conditions()] {
            for i in 0..ents.len() {
                let nodes = ents.nodes(i);
                let kind = ents.kind(i);
                match vtk_permutation(kind) {
                    Some(p) if p.len() == nodes.len() => {
                        conn.extend(p.iter().map(|&k| nodes[k].index() as i64));
                    }
                    _ => conn.extend(nodes.iter().map(|n| n.index() as i64)),
                }
                offsets.push(conn.len() as i64);
                types.push(vtk_cell_type(kind));
            }
        }
        for l in &self.lines {
            conn.extend([l[0] as i64, l[1] as i64]);
            offsets.push(conn.len() as i64);
            types.push(3);
        }
        Ok(Grid {
            n_points,
            n_cells,
            point_data,
            cell_data,
            points: xyz,
            connectivity: conn,
            offsets,
            types,
        })
    }

    /// The `.vtu` text in the ASCII form; errors as [`write_file`](Self::write_file).
    pub fn to_xml(&self, file_name: &str) -> Result<String, Error> {
        let g = self.grid(file_name)?;
        let mut out = String::new();
        out.push_str(HEADER);
        let _ = writeln!(
            out,
            "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            g.n_points, g.n_cells
        );
        out.push_str("      <PointData>\n");
        for a in &g.point_data {
            write_array(&mut out, &a.name, a.data.as_ref());
        }
        out.push_str("      </PointData>\n");
        out.push_str("      <CellData>\n");
        for a in &g.cell_data {
            write_array(&mut out, &a.name, a.data.as_ref());
        }
        out.push_str("      </CellData>\n");
        out.push_str("      <Points>\n");
        let points = DataArray::F64 {
            components: 3,
            values: g.points,
        };
        write_array(&mut out, "Points", &points);
        out.push_str("      </Points>\n");
        out.push_str("      <Cells>\n");
        write_cells(&mut out, "connectivity", &g.connectivity, &g.offsets);
        let offsets = DataArray::I64 {
            components: 1,
            values: g.offsets,
        };
        write_array(&mut out, "offsets", &offsets);
        out.push_str(
            "        <DataArray type=\"UInt8\" Name=\"types\" NumberOfComponents=\"1\" format=\"ascii\">\n",
        );
        for t in g.types {
            let _ = writeln!(out, "          {t}");
        }
        out.push_str("        </DataArray>\n");
        out.push_str("      </Cells>\n");
        out.push_str(FOOTER);
        Ok(out)
    }

    /// Writes the `.vtu` file in the binary form to `out`: every array as raw little-endian
    /// bytes in one appended block (`<AppendedData encoding="raw">`, each array preceded by
    /// its byte count as a `UInt64`), what ParaView reads fastest. Errors as
    /// [`write_file`](Self::write_file); `file_name` names the file in them.
    pub fn write_binary(&self, file_name: &str, out: &mut impl Write) -> Result<(), Error> {
        let g = self.grid(file_name)?;
        let io =
            |e: std::io::Error| Error::new(file_name, Location::None, ErrorKind::Io(e.to_string()));
        let points = Array::owned(
            "Points",
            DataArray::F64 {
                components: 3,
                values: g.points,
            },
        );
        let connectivity = Array::owned(
            "connectivity",
            DataArray::I64 {
                components: 1,
                values: g.connectivity,
            },
        );
        let offsets = Array::owned(
            "offsets",
            DataArray::I64 {
                components: 1,
                values: g.offsets,
            },
        );
        // The XML first, each array with its offset into the appended block.
        let mut xml = String::from(HEADER);
        let _ = writeln!(
            xml,
            "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            g.n_points, g.n_cells
        );
        let mut offset = 0usize;
        let mut tag = |xml: &mut String, name: &str, ty: &str, components: usize, bytes: usize| {
            let _ = writeln!(
                xml,
                "        <DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{components}\" format=\"appended\" offset=\"{offset}\"/>",
                escape(name)
            );
            offset += 8 + bytes;
        };
        let sections: [(&str, &[Array<'_>]); 3] = [
            ("PointData", &g.point_data),
            ("CellData", &g.cell_data),
            ("Points", std::slice::from_ref(&points)),
        ];
        for (section, arrays) in sections {
            let _ = writeln!(xml, "      <{section}>");
            for a in arrays {
                let d = a.data.as_ref();
                tag(
                    &mut xml,
                    &a.name,
                    d.type_name(),
                    d.components(),
                    d.len() * 8,
                );
            }
            let _ = writeln!(xml, "      </{section}>");
        }
        xml.push_str("      <Cells>\n");
        tag(
            &mut xml,
            "connectivity",
            "Int64",
            1,
            connectivity.data.as_ref().len() * 8,
        );
        tag(
            &mut xml,
            "offsets",
            "Int64",
            1,
            offsets.data.as_ref().len() * 8,
        );
        tag(&mut xml, "types", "UInt8", 1, g.types.len());
        xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
        xml.push_str("  <AppendedData encoding=\"raw\">\n   _");
        out.write_all(xml.as_bytes()).map_err(io)?;
        let arrays =
            g.point_data
                .iter()
                .chain(&g.cell_data)
                .chain([&points, &connectivity, &offsets]);
        for a in arrays {
            write_raw(out, a.data.as_ref()).map_err(io)?;
        }
        out.write_all(&(g.types.len() as u64).to_le_bytes())
            .and_then(|()| out.write_all(&g.types))
            .and_then(|()| out.write_all(b"\n  </AppendedData>\n</VTKFile>\n"))
            .map_err(io)
    }

    /// Writes the `.vtu` file at `path` in `format`, streamed (the binary form holds no copy
    /// of the file in memory). Errors if a data array has the wrong length, a line cell names
    /// a point that does not exist, or the file cannot be written.
    pub fn write_file(&self, path: &Path, format: VtuFormat) -> Result<(), Error> {
        let file = path.display().to_string();
        let io =
            |e: std::io::Error| Error::new(&file, Location::None, ErrorKind::Io(e.to_string()));
        match format {
            VtuFormat::Ascii => {
                let xml = self.to_xml(&file)?;
                std::fs::write(path, xml).map_err(io)
            }
            VtuFormat::Binary => {
                let f = std::fs::File::create(path).map_err(io)?;
                let mut w = std::io::BufWriter::with_capacity(1 << 20, f);
                self.write_binary(&file, &mut w)?;
                w.flush().map_err(io)
            }
        }
    }
}

/// How [`VtuWriter::write_file`] writes the arrays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VtuFormat {
    /// Raw little-endian bytes in one appended block: small, and what ParaView reads fastest.
    #[default]
    Binary,
    /// Text, one tuple (one cell) per line: for diffs.
    Ascii,
}

const HEADER: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n";
const FOOTER: &str = "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";

/// The checked arrays of a file ([`VtuWriter::grid`]).
struct Grid<'a> {
    n_points: usize,
    n_cells: usize,
    point_data: Vec<Array<'a>>,
    cell_data: Vec<Array<'a>>,
    points: Vec<f64>,
    connectivity: Vec<i64>,
    offsets: Vec<i64>,
    types: Vec<u8>,
}

/// A named data array, the writer's own or the caller's.
struct Array<'a> {
    name: String,
    data: std::borrow::Cow<'a, DataArray>,
}

impl<'a> Array<'a> {
    fn owned(name: &str, data: DataArray) -> Array<'a> {
        Array {
            name: name.to_owned(),
            data: std::borrow::Cow::Owned(data),
        }
    }

    fn borrowed(name: &str, data: &'a DataArray) -> Array<'a> {
        Array {
            name: name.to_owned(),
            data: std::borrow::Cow::Borrowed(data),
        }
    }
}

/// The byte count (`UInt64`) and the values of `a` as little-endian bytes, a block at a time.
fn write_raw(out: &mut impl Write, a: &DataArray) -> std::io::Result<()> {
    out.write_all(&((a.len() * 8) as u64).to_le_bytes())?;
    let mut buffer = Vec::with_capacity(1 << 16);
    macro_rules! blocks {
        ($values:expr) => {
            for block in $values.chunks(1 << 13) {
                buffer.clear();
                for v in block {
                    buffer.extend_from_slice(&v.to_le_bytes());
                }
                out.write_all(&buffer)?;
            }
        };
    }
    match a {
        DataArray::F64 { values, .. } => blocks!(values),
        DataArray::I64 { values, .. } => blocks!(values),
    }
    Ok(())
}

/// `a` extended to `n` tuples with NaN (`Float64`) or −1 (`Int64`).
fn padded(a: &DataArray, n: usize) -> DataArray {
    let c = a.components();
    match a {
        DataArray::F64 { components, values } => {
            let mut values = values.clone();
            values.resize(n * c, f64::NAN);
            DataArray::F64 {
                components: *components,
                values,
            }
        }
        DataArray::I64 { components, values } => {
            let mut values = values.clone();
            values.resize(n * c, -1);
            DataArray::I64 {
                components: *components,
                values,
            }
        }
    }
}

/// The connectivity, one cell per line.
fn write_cells(out: &mut String, name: &str, conn: &[i64], offsets: &[i64]) {
    let _ = writeln!(
        out,
        "        <DataArray type=\"Int64\" Name=\"{name}\" NumberOfComponents=\"1\" format=\"ascii\">"
    );
    let mut start = 0usize;
    for &end in offsets {
        let end = end as usize;
        out.push_str("          ");
        for (k, x) in conn[start..end].iter().enumerate() {
            if k > 0 {
                out.push(' ');
            }
            let _ = write!(out, "{x}");
        }
        out.push('\n');
        start = end;
    }
    out.push_str("        </DataArray>\n");
}

#[cfg(test)]
mod tests;
