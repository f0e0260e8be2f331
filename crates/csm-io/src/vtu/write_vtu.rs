//! The VTU writer: a model part as a VTK XML UnstructuredGrid, binary (raw appended data, what
//! ParaView reads fastest) or ASCII (diff-friendly).
//!
//! Points are the nodes in dense order (current coordinates), then the extra points (e.g.
//! condition centres) in the order given. Cells are the elements, then the conditions, then
//! the line cells, each in dense order. Built-in arrays: point data `node_id` (−1 on extra
//! points); cell data `entity_id` (the file id; the index of the line for line cells) and
//! `entity_kind` (0 element, 1 condition, 2 line cell; `Int8`); `connectivity` and `offsets`
//! are `Int32` while the point and connectivity counts fit, else `Int64`. A point data array
//! holds one tuple per point, or one per node only: then it is padded on the extra points with
//! NaN (`Float64`) or −1 (the integer types). In the ASCII form floats are written in Rust's
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
    /// `Int32` values.
    I32 {
        /// Components per tuple.
        components: usize,
        /// The values, tuple after tuple.
        values: Vec<i32>,
    },
    /// `Int8` values (flags, small codes).
    I8 {
        /// Components per tuple.
        components: usize,
        /// The values, tuple after tuple.
        values: Vec<i8>,
    },
}

/// A value type of the file: its VTK name, its padding (NaN, −1), its text and its bytes.
trait Value: Copy {
    const TYPE: &'static str;
    const PAD: Self;
    const SIZE: usize;
    fn text(self, out: &mut String);
    fn bytes(self, out: &mut [u8]);
}

macro_rules! integer_value {
    ($t:ty, $name:literal, $pad:expr) => {
        impl Value for $t {
            const TYPE: &'static str = $name;
            const PAD: Self = $pad;
            const SIZE: usize = std::mem::size_of::<$t>();
            fn text(self, out: &mut String) {
                let _ = write!(out, "{self}");
            }
            fn bytes(self, out: &mut [u8]) {
                out.copy_from_slice(&self.to_le_bytes());
            }
        }
    };
}
integer_value!(i64, "Int64", -1);
integer_value!(i32, "Int32", -1);
integer_value!(i8, "Int8", -1);
// Cell types are never padded.
integer_value!(u8, "UInt8", 0);

impl Value for f64 {
    const TYPE: &'static str = "Float64";
    const PAD: Self = f64::NAN;
    const SIZE: usize = 8;
    fn text(self, out: &mut String) {
        push_f64(out, self);
    }
    fn bytes(self, out: &mut [u8]) {
        out.copy_from_slice(&self.to_le_bytes());
    }
}

/// `$body` with `$values` bound to the array's values (a slice of its type).
macro_rules! with_values {
    ($array:expr, $values:ident => $body:expr) => {
        match $array {
            DataArray::F64 {
                values: $values, ..
            } => $body,
            DataArray::I64 {
                values: $values, ..
            } => $body,
            DataArray::I32 {
                values: $values, ..
            } => $body,
            DataArray::I8 {
                values: $values, ..
            } => $body,
        }
    };
}

impl DataArray {
    fn type_name(&self) -> &'static str {
        match self {
            DataArray::F64 { .. } => f64::TYPE,
            DataArray::I64 { .. } => i64::TYPE,
            DataArray::I32 { .. } => i32::TYPE,
            DataArray::I8 { .. } => i8::TYPE,
        }
    }

    fn components(&self) -> usize {
        match self {
            DataArray::F64 { components, .. }
            | DataArray::I64 { components, .. }
            | DataArray::I32 { components, .. }
            | DataArray::I8 { components, .. } => (*components).max(1),
        }
    }

    fn len(&self) -> usize {
        with_values!(self, values => values.len())
    }

    fn value_size(&self) -> usize {
        match self {
            DataArray::F64 { .. } | DataArray::I64 { .. } => 8,
            DataArray::I32 { .. } => 4,
            DataArray::I8 { .. } => 1,
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

/// An ASCII data array: `values` then padding up to `len` values, `per_line` a line.
fn write_ascii<T: Value>(
    out: &mut String,
    name: &str,
    components: usize,
    (values, len): (&[T], usize),
) {
    let _ = writeln!(
        out,
        "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{components}\" format=\"ascii\">",
        T::TYPE,
        escape(name)
    );
    let padding = std::iter::repeat_n(T::PAD, len.saturating_sub(values.len()));
    let all: Vec<T> = values.iter().copied().chain(padding).collect();
    for chunk in all.chunks(components.max(1)) {
        out.push_str("          ");
        for (k, &x) in chunk.iter().enumerate() {
            if k > 0 {
                out.push(' ');
            }
            x.text(out);
        }
        out.push('\n');
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
    /// the extra points with NaN (`Float64`) or −1 (the integer types).
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

    /// Errors if a data array has the wrong length or a line cell names a point that does not
    /// exist.
    fn check(&self, file_name: &str) -> Result<(), Error> {
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
        Ok(())
    }

    /// The arrays of the file, checked: errors if a data array has the wrong length or a
    /// line cell names a point that does not exist.
    fn grid(&self, file_name: &str) -> Result<Grid<'_>, Error> {
        self.check(file_name)?;
        let (n_points, n_cells) = (self.n_points(), self.n_cells());
        let node_ids = ids(self
            .model
            .nodes()
            .ids()
            .iter()
            .map(|&i| i64::from(i))
            .collect());
        let mut point_data = vec![Array::owned("node_id", node_ids, n_points)];
        point_data.extend(
            self.point_data
                .iter()
                .map(|(name, a)| Array::borrowed(name, a, n_points)),
        );
        let (mut ids, mut kinds) = (Vec::with_capacity(n_cells), Vec::with_capacity(n_cells));
        for (k, ents) in [self.model.elements(), self.model.conditions()]
            .into_iter()
            .enumerate()
        {
            ids.extend(ents.ids().iter().map(|&i| i64::from(i)));
            kinds.extend(std::iter::repeat_n(k as i8, ents.len()));
        }
        ids.extend((0..self.lines.len()).map(|i| i as i64));
        kinds.extend(std::iter::repeat_n(2, self.lines.len()));
        let mut cell_data = vec![
            Array::owned("entity_id", self::ids(ids), n_cells),
            Array::owned(
                "entity_kind",
                DataArray::I8 {
                    components: 1,
                    values: kinds,
                },
                n_cells,
            ),
        ];
        cell_data.extend(
            self.cell_data
                .iter()
                .map(|(name, a)| Array::borrowed(name, a, n_cells)),
        );
        let xyz: Vec<f64> = self
            .model
            .nodes()
            .coordinates()
            .iter()
            .chain(&self.extra_points)
            .flat_map(|p| [p.x, p.y, p.z])
            .collect();
        let mut conn: Vec<usize> = Vec::new();
        let mut offsets: Vec<usize> = Vec::with_capacity(n_cells);
        let mut types: Vec<u8> = Vec::with_capacity(n_cells);
        for ents in [self.model.elements(), self.model.conditions()] {
            for i in 0..ents.len() {
                let nodes = ents.nodes(i);
                let kind = ents.kind(i);
                match vtk_permutation(kind) {
                    Some(p) if p.len() == nodes.len() => {
                        conn.extend(p.iter().map(|&k| nodes[k].index()));
                    }
                    _ => conn.extend(nodes.iter().map(|n| n.index())),
                }
                offsets.push(conn.len());
                types.push(vtk_cell_type(kind));
            }
        }
        for l in &self.lines {
            conn.extend(l);
            offsets.push(conn.len());
            types.push(3);
        }
        Ok(Grid {
            n_points,
            n_cells,
            point_data,
            cell_data,
            points: xyz,
            connectivity: self::ids(conn.into_iter().map(|v| v as i64).collect()),
            offsets: self::ids(offsets.into_iter().map(|v| v as i64).collect()),
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
        for (section, arrays) in [("PointData", &g.point_data), ("CellData", &g.cell_data)] {
            let _ = writeln!(out, "      <{section}>");
            for a in arrays {
                let c = a.data.components();
                with_values!(&*a.data, values => write_ascii(&mut out, &a.name, c, (values, a.tuples * c)));
            }
            let _ = writeln!(out, "      </{section}>");
        }
        out.push_str("      <Points>\n");
        write_ascii(&mut out, "Points", 3, (&g.points, g.points.len()));
        out.push_str("      </Points>\n");
        out.push_str("      <Cells>\n");
        write_cells(&mut out, &g.connectivity, &g.offsets);
        with_values!(&g.offsets, values => write_ascii(&mut out, "offsets", 1, (values, values.len())));
        write_ascii(&mut out, "types", 1, (&g.types, g.types.len()));
        out.push_str("      </Cells>\n");
        out.push_str(FOOTER);
        Ok(out)
    }

    /// Writes the `.vtu` file in the binary form to `out`: every array as raw little-endian
    /// bytes in one appended block (`<AppendedData encoding="raw">`, each array preceded by
    /// its byte count as a `UInt64`), what ParaView reads fastest. The arrays are those of
    /// the ASCII form, with the same types, streamed from the model: nothing of the size of
    /// the mesh is built. The values are encoded by rayon's pool in tasks of a few thousand
    /// while this thread writes the ones before; the bytes are the same on any pool. Errors as [`write_file`](Self::write_file); `file_name` names the
    /// file in them.
    pub fn write_binary(&self, file_name: &str, out: &mut impl Write) -> Result<(), Error> {
        self.check(file_name)?;
        let io =
            |e: std::io::Error| Error::new(file_name, Location::None, ErrorKind::Io(e.to_string()));
        let (n_points, n_cells) = (self.n_points(), self.n_cells());
        let nodes = self.model.nodes();
        let entities = [self.model.elements(), self.model.conditions()];
        let n_conn: usize = entities
            .iter()
            .map(|e| (0..e.len()).map(|i| e.nodes(i).len()).sum::<usize>())
            .sum::<usize>()
            + 2 * self.lines.len();
        // The built-in arrays' types, as `grid` decides them (`ids`).
        let narrow = |v: i64| i32::try_from(v).is_ok();
        let node_ids_narrow = nodes.ids().iter().all(|&i| narrow(i64::from(i)));
        let entity_ids_narrow = entities
            .iter()
            .flat_map(|e| e.ids())
            .all(|&i| narrow(i64::from(i)))
            && narrow(self.lines.len() as i64);
        let indices_narrow = narrow(n_points.saturating_sub(1).max(n_conn) as i64);
        let int = |is_narrow: bool| if is_narrow { i32::TYPE } else { i64::TYPE };
        let size = |is_narrow: bool| if is_narrow { 4 } else { 8 };

        // The XML first, each array with its offset into the appended block.
        let mut xml = String::from(HEADER);
        let _ = writeln!(
            xml,
            "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
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
        let user = |xml: &mut String,
                    tag: &mut dyn FnMut(&mut String, &str, &str, usize, usize),
                    arrays: &[(String, DataArray)],
                    tuples: usize| {
            for (name, a) in arrays {
                let c = a.components();
                tag(xml, name, a.type_name(), c, tuples * c * a.value_size());
            }
        };
        xml.push_str("      <PointData>\n");
        tag(
            &mut xml,
            "node_id",
            int(node_ids_narrow),
            1,
            n_points * size(node_ids_narrow),
        );
        user(&mut xml, &mut tag, &self.point_data, n_points);
        xml.push_str("      </PointData>\n      <CellData>\n");
        tag(
            &mut xml,
            "entity_id",
            int(entity_ids_narrow),
            1,
            n_cells * size(entity_ids_narrow),
        );
        tag(&mut xml, "entity_kind", i8::TYPE, 1, n_cells);
        user(&mut xml, &mut tag, &self.cell_data, n_cells);
        xml.push_str("      </CellData>\n      <Points>\n");
        tag(&mut xml, "Points", f64::TYPE, 3, n_points * 24);
        xml.push_str("      </Points>\n      <Cells>\n");
        tag(
            &mut xml,
            "connectivity",
            int(indices_narrow),
            1,
            n_conn * size(indices_narrow),
        );
        tag(
            &mut xml,
            "offsets",
            int(indices_narrow),
            1,
            n_cells * size(indices_narrow),
        );
        tag(&mut xml, "types", u8::TYPE, 1, n_cells);
        xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
        xml.push_str("  <AppendedData encoding=\"raw\">\n   _");
        out.write_all(xml.as_bytes()).map_err(io)?;

        // Then the values, in the same order.
        let narrow = appended::Narrow {
            node_ids: node_ids_narrow,
            entity_ids: entity_ids_narrow,
            indices: indices_narrow,
        };
        let arrays = self.appended_arrays(&narrow, n_conn);
        debug_assert_eq!(
            arrays.iter().map(|a| 8 + a.bytes).sum::<usize>(),
            offset,
            "the XML's offsets"
        );
        appended::write_arrays(out, &arrays)
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

/// Ids or point indices: `Int32` while they fit, else `Int64`.
fn ids(values: Vec<i64>) -> DataArray {
    if values.iter().all(|&v| i32::try_from(v).is_ok()) {
        DataArray::I32 {
            components: 1,
            values: values.into_iter().map(|v| v as i32).collect(),
        }
    } else {
        DataArray::I64 {
            components: 1,
            values,
        }
    }
}

/// The checked arrays of a file ([`VtuWriter::grid`]).
struct Grid<'a> {
    n_points: usize,
    n_cells: usize,
    point_data: Vec<Array<'a>>,
    cell_data: Vec<Array<'a>>,
    points: Vec<f64>,
    connectivity: DataArray,
    offsets: DataArray,
    types: Vec<u8>,
}

/// A named data array, the writer's own or the caller's, of `tuples` tuples: those it lacks
/// are padding.
struct Array<'a> {
    name: String,
    data: std::borrow::Cow<'a, DataArray>,
    tuples: usize,
}

impl<'a> Array<'a> {
    fn owned(name: &str, data: DataArray, tuples: usize) -> Array<'a> {
        Array {
            name: name.to_owned(),
            data: std::borrow::Cow::Owned(data),
            tuples,
        }
    }

    fn borrowed(name: &str, data: &'a DataArray, tuples: usize) -> Array<'a> {
        Array {
            name: name.to_owned(),
            data: std::borrow::Cow::Borrowed(data),
            tuples,
        }
    }
}

/// The connectivity, one cell per line.
fn write_cells(out: &mut String, conn: &DataArray, offsets: &DataArray) {
    let _ = writeln!(
        out,
        "        <DataArray type=\"{}\" Name=\"connectivity\" NumberOfComponents=\"1\" format=\"ascii\">",
        conn.type_name()
    );
    let ends: Vec<usize> =
        with_values!(offsets, values => values.iter().map(|&v| v as usize).collect());
    let mut start = 0usize;
    with_values!(conn, values => {
        for &end in &ends {
            out.push_str("          ");
            for (k, &x) in values[start..end].iter().enumerate() {
                if k > 0 {
                    out.push(' ');
                }
                x.text(out);
            }
            out.push('\n');
            start = end;
        }
    });
    out.push_str("        </DataArray>\n");
}

mod appended;

#[cfg(test)]
mod tests;
