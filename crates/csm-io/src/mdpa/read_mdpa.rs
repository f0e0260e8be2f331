//! The Kratos `.mdpa` reader (behaviour of Kratos' `ModelPartIO::ReadModelPart`).
//!
//! The file is read word by word (any whitespace, CRLF, tabs; `//` and `/* */` comments).
//! Blocks: `ModelPartData` (values into the process info), `Properties N`, `Nodes`,
//! `Elements <Name>`, `Conditions <Name>` (geometry from the name, see
//! `geometry_from_name`), `NodalData VAR` (NODAL_H, WEIGHTED_GAP, DISPLACEMENT, VELOCITY,
//! ACCELERATION, NORMAL and their `_X/_Y/_Z` components are stored in the current step of the
//! model's nodal data; other variables are skipped), `ElementalData`, `ConditionalData`,
//! `Table`, `Geometries`, `Mesh` and `Constraints` (skipped), and nested `SubModelPart name`
//! blocks (`SubModelPartNodes/Elements/Conditions` fill the part at its full path `A.B`;
//! `SubModelPartData/Tables/Properties` are skipped). Any other `Begin X` is an error.
//! `DOMAIN_SIZE` is 2 when every element and condition is a 2D geometry (`…2D…N` names),
//! else 3, unless `ModelPartData` sets it.

use csm_model::{
    ConditionId, ElementId, ModelPart, NodeId, NodeIdx, PartIdx, Properties, PropertiesId,
    PropertyValue, ScalarVar, VectorVar,
};

use crate::cursor::{Cursor, Token, parse_f64, quote};
use crate::error::{Error, ErrorKind};
use crate::mdpa::geometry_from_name::geometry_from_name;
use crate::mdpa::number_block::{self, Parsed, Record};

/// Reads a Kratos `.mdpa` text into a model part named `Structure`. `file_name` is used in
/// error messages only.
///
/// The `Nodes`, `Elements`, `Conditions` and sub-model-part id blocks are parsed in parallel
/// (rayon's pool) when they hold plain numbers only; the model and every error are those of
/// the word-by-word reading.
pub fn read_mdpa(text: &str, file_name: &str) -> Result<ModelPart, Error> {
    read_mdpa_with(text.as_bytes(), file_name, Some(Parallel::default()))
}

/// [`read_mdpa`] of a file's bytes, as `read_mdpa(&String::from_utf8_lossy(bytes))`: UTF-8
/// text (every ASCII file) is read in place, anything else after the lossy conversion (each
/// invalid byte sequence becomes U+FFFD, so a Latin-1 comment or name still reads).
pub(crate) fn read_mdpa_bytes(bytes: &[u8], file_name: &str) -> Result<ModelPart, Error> {
    if is_utf8(bytes) {
        read_mdpa_with(bytes, file_name, Some(Parallel::default()))
    } else {
        read_mdpa(&String::from_utf8_lossy(bytes), file_name)
    }
}

/// Whether `bytes` are UTF-8 (as `std::str::from_utf8(bytes).is_ok()`), checked in pieces in
/// parallel on a large text: a piece starts at an ASCII byte, which no multi-byte sequence
/// contains, so the pieces are UTF-8 exactly when the whole is.
pub(super) fn is_utf8(bytes: &[u8]) -> bool {
    use rayon::prelude::*;
    /// The bytes of a piece (at least).
    const PIECE: usize = 1 << 20;
    if bytes.len() < 2 * PIECE || rayon::current_num_threads() < 2 {
        return std::str::from_utf8(bytes).is_ok();
    }
    let mut cuts = vec![0];
    let mut at = PIECE;
    while at < bytes.len() {
        match bytes[at..].iter().position(u8::is_ascii) {
            Some(k) => {
                cuts.push(at + k);
                at += k + PIECE;
            }
            None => break,
        }
    }
    cuts.push(bytes.len());
    cuts.par_windows(2)
        .all(|w| std::str::from_utf8(&bytes[w[0]..w[1]]).is_ok())
}

/// The sizes of the parallel block parsing.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Parallel {
    /// The smallest chunk one worker parses (bytes).
    pub(crate) min_chunk: usize,
    /// The bytes of a window (see [`number_block::WINDOW_BYTES`]).
    pub(crate) window: usize,
}

impl Default for Parallel {
    fn default() -> Parallel {
        Parallel {
            min_chunk: 64 << 10,
            window: number_block::WINDOW_BYTES,
        }
    }
}

/// [`read_mdpa`]; `parallel`: the sizes of the parallel block parsing, or `None` for the
/// word-by-word reading only (the oracle of the tests).
pub(crate) fn read_mdpa_with(
    bytes: &[u8],
    file_name: &str,
    parallel: Option<Parallel>,
) -> Result<ModelPart, Error> {
    let mut cur = Cursor::new(bytes, file_name, true);
    if cur.at_end()? {
        return Err(cur.error_at(0, ErrorKind::Empty));
    }
    let mut r = Reader {
        cur,
        mp: ModelPart::new("Structure"),
        ids: Vec::new(),
        parallel,
    };
    let mut domain_size_given = false;
    while let Some(t) = r.cur.token()? {
        if t.text != "Begin" {
            return Err(r.cur.expected_at(t.pos, "`Begin`", &quote(t.text)));
        }
        let b = r.cur.expect_token("a block name")?;
        match b.text {
            "ModelPartData" => {
                domain_size_given |= r.values("ModelPartData", None)?;
            }
            "Properties" => {
                let id = r.cur.id("a properties id")?;
                r.values("Properties", Some(PropertiesId(id)))?;
            }
            "Nodes" => r.nodes()?,
            "Elements" | "Conditions" => r.entities(b.text == "Elements")?,
            "NodalData" => r.nodal_data()?,
            "SubModelPart" => r.sub_model_part(None)?,
            "ElementalData"
            | "ConditionalData"
            | "Table"
            | "Geometries"
            | "Mesh"
            | "Constraints"
            | "MasterSlaveConstraints" => r.skip_block(b)?,
            other => {
                return Err(r
                    .cur
                    .error_at(b.pos, ErrorKind::UnknownBlock(other.to_owned())));
            }
        }
    }
    let mut mp = r.mp;
    if !domain_size_given {
        let kinds = mp.elements().kinds().iter().chain(mp.conditions().kinds());
        let mut any = false;
        let mut all_2d = true;
        for k in kinds {
            any = true;
            all_2d &= k.working_dim() == 2;
        }
        mp.process_info_mut()
            .set_number("DOMAIN_SIZE", if any && all_2d { 2.0 } else { 3.0 });
    }
    Ok(mp)
}

/// Adds element (`is_element`) or condition `id` of `kind` named `name` to `mp`.
fn add_entity(
    mp: &mut ModelPart,
    is_element: bool,
    (id, kind, name): (u32, csm_geometry::GeometryKind, &str),
    conn: &[NodeId],
    prop: PropertiesId,
) -> Result<(), csm_model::Error> {
    mp.ensure_properties(prop);
    if is_element {
        mp.add_element(ElementId(id), kind, name, conn, prop)
            .map(|_| ())
    } else {
        mp.add_condition(ConditionId(id), kind, name, conn, prop)
            .map(|_| ())
    }
}

struct Reader<'a> {
    cur: Cursor<'a>,
    mp: ModelPart,
    ids: Vec<NodeIdx>,
    /// The sizes of the parallel block parsing; `None`: word by word only.
    parallel: Option<Parallel>,
}

/// A value of a properties or process info line: a number, `[n] (a, b, …)` or text.
fn parse_value(text: &str) -> PropertyValue {
    if let Some(x) = parse_f64(text) {
        return PropertyValue::Number(x);
    }
    if text.starts_with('[')
        && let (Some(open), Some(close)) = (text.find('('), text.rfind(')'))
        && open < close
    {
        let inner = text[open + 1..close].replace(['(', ')'], " ");
        let v: Option<Vec<f64>> = inner
            .split([',', ' '])
            .filter(|s| !s.trim().is_empty())
            .map(|s| parse_f64(s.trim()))
            .collect();
        if let Some(v) = v {
            return PropertyValue::Vector(v);
        }
    }
    PropertyValue::Text(text.trim_matches('"').to_owned())
}

fn scalar_var(name: &str) -> Option<ScalarVar> {
    Some(match name {
        "NODAL_H" => ScalarVar::NodalH,
        "WEIGHTED_GAP" => ScalarVar::WeightedGap,
        "LAGRANGE_MULTIPLIER_CONTACT_PRESSURE" => ScalarVar::LagrangeMultiplierContactPressure,
        "NORMAL_GAP" => ScalarVar::NormalGap,
        "NODAL_AREA" => ScalarVar::NodalArea,
        _ => return None,
    })
}

fn vector_var(name: &str) -> Option<VectorVar> {
    Some(match name {
        "DISPLACEMENT" => VectorVar::Displacement,
        "VELOCITY" => VectorVar::Velocity,
        "ACCELERATION" => VectorVar::Acceleration,
        "NORMAL" => VectorVar::Normal,
        _ => return None,
    })
}

impl<'a> Reader<'a> {
    fn model_err(&self, pos: usize, e: csm_model::Error) -> Error {
        self.cur.error_at(pos, ErrorKind::Model(e))
    }

    /// The next word, which must not be `End` … of another block: true at `End <block>`.
    fn at_end_of(&mut self, t: &Token<'_>, block: &str) -> Result<bool, Error> {
        if t.text == "End" {
            self.cur.expect_word(block)?;
            return Ok(true);
        }
        Ok(false)
    }

    fn next(&mut self, block: &str) -> Result<Token<'a>, Error> {
        self.cur.expect_token_with(|| format!("`End {block}`"))
    }

    /// `NAME value` lines up to `End <block>`; into properties `props`, or the process info.
    /// Nested `Begin Table … End Table` are skipped. True if DOMAIN_SIZE was set.
    fn values(&mut self, block: &str, props: Option<PropertiesId>) -> Result<bool, Error> {
        let mut properties = props.map(Properties::new);
        let mut domain_size = false;
        loop {
            let t = self.next(block)?;
            let (text, pos) = (t.text, t.pos);
            if text == "End" {
                self.cur.expect_word(block)?;
                break;
            }
            if text == "Begin" {
                let b = self.cur.expect_token("a block name")?;
                if b.text != "Table" {
                    return Err(self
                        .cur
                        .error_at(b.pos, ErrorKind::UnknownBlock(b.text.to_owned())));
                }
                self.skip_block(b)?;
                continue;
            }
            let name = text.to_owned();
            let (value, _) = self.cur.rest_of_line()?;
            let value = parse_value(value);
            match &mut properties {
                Some(p) => {
                    p.values.insert(name, value);
                }
                None => {
                    domain_size |= name == "DOMAIN_SIZE";
                    self.mp.process_info_mut().set(&name, value);
                }
            }
            let _ = pos;
        }
        if let Some(p) = properties {
            let id = p.id;
            if self.mp.properties().contains_key(&id) {
                // Kratos merges repeated blocks; keep the values of both.
                if let Some(old) = self.mp.properties_mut().get_mut(&id) {
                    old.values.extend(p.values);
                }
            } else {
                self.mp.properties_mut().insert(id, p);
            }
        }
        Ok(domain_size)
    }

    /// Skips up to `End <name>` of the block `b` (nested blocks of the same name included).
    fn skip_block(&mut self, b: Token<'_>) -> Result<(), Error> {
        let name = b.text.to_owned();
        let mut depth = 1usize;
        let mut prev_begin = false;
        let mut prev_end = false;
        while let Some(t) = self.cur.token()? {
            if t.text == name && prev_begin {
                depth += 1;
            } else if t.text == name && prev_end {
                depth -= 1;
                if depth == 0 {
                    return Ok(());
                }
            }
            prev_begin = t.text == "Begin";
            prev_end = t.text == "End";
        }
        Err(self
            .cur
            .error_at(b.pos, ErrorKind::Unterminated(format!("`Begin {name}`"))))
    }

    /// The end of the plain body of the block the cursor is in (see
    /// [`number_block::plain_body_end`]), when the parallel parsing is on.
    fn plain_body_end(&self) -> Option<usize> {
        self.parallel?;
        number_block::plain_body_end(self.cur.data(), self.cur.pos())
    }

    /// The plain body of the current block (see [`number_block::plain_body_end`]) as
    /// `record`s, window by window: each window is parsed in parallel while the previous one
    /// is used by `insert` (the model, the window's records, how many records the whole body
    /// likely holds — for reserving room — on the first window, else 0). `insert` returns the
    /// word index (from the window's start) and the error of a record it refuses. The cursor
    /// is left after the last window used: at the block's `End`, or at the start of a window
    /// it must read word by word.
    fn parallel_records(
        &mut self,
        record: Record,
        mut insert: impl FnMut(&mut ModelPart, &Parsed, usize) -> Result<(), (usize, csm_model::Error)>
        + Send,
    ) -> Result<(), Error> {
        let (Some(sizes), Some(end)) = (self.parallel, self.plain_body_end()) else {
            return Ok(());
        };
        let data = self.cur.data();
        let body_start = self.cur.pos();
        let parse = |at: usize| -> Option<(Parsed, usize)> {
            if at >= end {
                return None;
            }
            let to = number_block::window_end(data, at, end, sizes.window);
            number_block::parse_window(data, (at, to), record, sizes.min_chunk).map(|p| (p, to))
        };
        let mut at = body_start;
        let mut current = parse(at);
        while let Some((parsed, to)) = current {
            let estimate = if at == body_start {
                let records = match record {
                    Record::Node => parsed.ids.len(),
                    Record::Ids(n) => parsed.ids.len() / n.max(1),
                };
                number_block::estimate_records(records, to - at, end - body_start)
            } else {
                0
            };
            let mp = &mut self.mp;
            let (next, inserted) = rayon::join(|| parse(to), || insert(mp, &parsed, estimate));
            if let Err((word, e)) = inserted {
                return Err(self.model_err(self.word_pos(at, word), e));
            }
            self.cur.set_pos(to);
            at = to;
            current = next;
        }
        Ok(())
    }

    /// The byte offset of word `k` (from 0) after `start`.
    fn word_pos(&self, start: usize, k: usize) -> usize {
        let mut c = self.cur.at(start);
        for _ in 0..k {
            if let Ok(None) | Err(_) = c.token() {
                break;
            }
        }
        match c.token() {
            Ok(Some(t)) => t.pos,
            _ => c.pos(),
        }
    }

    fn nodes(&mut self) -> Result<(), Error> {
        self.parallel_records(Record::Node, |mp, parsed, estimate| {
            mp.reserve_nodes(estimate);
            mp.add_nodes(&parsed.ids, &parsed.coordinates)
                .map_err(|(k, e)| (4 * k, e))
        })?;
        loop {
            let t = self.next("Nodes")?;
            let (text, pos) = (t.text, t.pos);
            if self.at_end_of(&Token { text, pos }, "Nodes")? {
                return Ok(());
            }
            let id = crate::cursor::parse_u64(text)
                .and_then(|v| u32::try_from(v).ok())
                .ok_or_else(|| {
                    self.cur
                        .expected_at(pos, "a node id or `End Nodes`", &quote(text))
                })?;
            let x = self.cur.f64("a finite x coordinate")?;
            let y = self.cur.f64("a finite y coordinate")?;
            let z = self.cur.f64("a finite z coordinate")?;
            self.mp
                .add_node(NodeId(id), [x, y, z].into())
                .map_err(|e| self.model_err(pos, e))?;
        }
    }

    fn entities(&mut self, is_element: bool) -> Result<(), Error> {
        let block = if is_element { "Elements" } else { "Conditions" };
        let name_tok = self.cur.expect_token("an element or condition name")?;
        let name = name_tok.text.to_owned();
        let kind = geometry_from_name(&name, is_element).ok_or_else(|| {
            self.cur
                .error_at(name_tok.pos, ErrorKind::UnknownGeometryName(name.clone()))
        })?;
        let mut conn: Vec<NodeId> = Vec::with_capacity(kind.n_nodes());
        let width = kind.n_nodes() + 2;
        let nodes_each = kind.n_nodes();
        self.parallel_records(Record::Ids(width), |mp, parsed, estimate| {
            mp.reserve_entities(!is_element, estimate, nodes_each);
            mp.add_entity_records(!is_element, kind, &name, &parsed.ids)
                .map_err(|(k, e)| (width * k, e))
        })?;
        loop {
            let t = self.next(block)?;
            let (text, pos) = (t.text, t.pos);
            if self.at_end_of(&Token { text, pos }, block)? {
                return Ok(());
            }
            let id = crate::cursor::parse_u64(text)
                .and_then(|v| u32::try_from(v).ok())
                .ok_or_else(|| {
                    self.cur
                        .expected_at(pos, &format!("an id or `End {block}`"), &quote(text))
                })?;
            let prop = PropertiesId(self.cur.id("a properties id")?);
            conn.clear();
            for _ in 0..kind.n_nodes() {
                conn.push(NodeId(self.cur.id("a node id")?));
            }
            add_entity(&mut self.mp, is_element, (id, kind, &name), &conn, prop)
                .map_err(|e| self.model_err(pos, e))?;
        }
    }

    fn node_idx(&self, id: u32, pos: usize) -> Result<NodeIdx, Error> {
        self.mp.nodes().index_of(id).ok_or_else(|| {
            self.model_err(
                pos,
                csm_model::Error::new(csm_model::ErrorKind::MissingEntity {
                    entity: csm_model::EntityKind::Node,
                    id,
                }),
            )
        })
    }

    /// `Begin NodalData VAR`: `id fixed value` (scalars, components) or
    /// `id fixed [3] (x, y, z)` (vectors) per line.
    fn nodal_data(&mut self) -> Result<(), Error> {
        let var_tok = self.cur.expect_token("a variable name")?;
        let var = var_tok.text.to_owned();
        let (base, component) = match var.rsplit_once('_') {
            Some((b, "X")) if vector_var(b).is_some() => (b.to_owned(), Some(0)),
            Some((b, "Y")) if vector_var(b).is_some() => (b.to_owned(), Some(1)),
            Some((b, "Z")) if vector_var(b).is_some() => (b.to_owned(), Some(2)),
            _ => (var.clone(), None),
        };
        let scalar = if component.is_none() {
            scalar_var(&base)
        } else {
            None
        };
        let vector = vector_var(&base);
        if scalar.is_none() && vector.is_none() {
            return self.skip_block(Token {
                text: "NodalData",
                pos: var_tok.pos,
            });
        }
        if let Some(s) = scalar {
            self.mp.nodal_data_mut().add_scalar(s);
        }
        if let Some(v) = vector {
            self.mp.nodal_data_mut().add_vector(v);
        }
        loop {
            let t = self.next("NodalData")?;
            let (text, pos) = (t.text, t.pos);
            if self.at_end_of(&Token { text, pos }, "NodalData")? {
                return Ok(());
            }
            let id = crate::cursor::parse_u64(text)
                .and_then(|v| u32::try_from(v).ok())
                .ok_or_else(|| {
                    self.cur
                        .expected_at(pos, "a node id or `End NodalData`", &quote(text))
                })?;
            let idx = self.node_idx(id, pos)?;
            let (line, lpos) = self.cur.rest_of_line()?;
            let words: Vec<&str> = line.split_whitespace().collect();
            if let (Some(v), None) = (vector, component) {
                // Optional fixity word, then `[3] (x, y, z)`.
                let start = line.find('[').ok_or_else(|| {
                    self.cur
                        .expected_at(lpos, "a vector `[3] (x, y, z)`", &quote(line))
                })?;
                let values = match parse_value(&line[start..]) {
                    PropertyValue::Vector(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => {
                        v
                    }
                    _ => {
                        return Err(self.cur.expected_at(
                            lpos,
                            "a vector `[3] (x, y, z)`",
                            &quote(line),
                        ));
                    }
                };
                if let Some(col) = self.mp.nodal_data_mut().vector_mut(v, 0) {
                    col[idx.index()] = [values[0], values[1], values[2]].into();
                }
                continue;
            }
            let value = words
                .last()
                .and_then(|w| parse_f64(w))
                .filter(|x| x.is_finite() && (1..=2).contains(&words.len()))
                .ok_or_else(|| self.cur.expected_at(lpos, "`fixed value`", &quote(line)))?;
            match (scalar, vector, component) {
                (Some(s), _, _) => {
                    if let Some(col) = self.mp.nodal_data_mut().scalar_mut(s, 0) {
                        col[idx.index()] = value;
                    }
                }
                (_, Some(v), Some(c)) => {
                    if let Some(col) = self.mp.nodal_data_mut().vector_mut(v, 0) {
                        col[idx.index()][c] = value;
                    }
                }
                _ => {}
            }
        }
    }

    /// Ids up to `End <block>`, and the offset their words start from (the position of id
    /// `k` is [`word_pos`](Self::word_pos)`(start, k)`).
    fn id_list(&mut self, block: &str) -> Result<(Vec<u32>, usize), Error> {
        let start = self.cur.pos();
        let mut out = Vec::new();
        self.parallel_records(Record::Ids(1), |_, parsed, estimate| {
            out.reserve(estimate);
            out.extend_from_slice(&parsed.ids);
            Ok(())
        })?;
        loop {
            let t = self.next(block)?;
            let (text, pos) = (t.text, t.pos);
            if self.at_end_of(&Token { text, pos }, block)? {
                return Ok((out, start));
            }
            let id = crate::cursor::parse_u64(text)
                .and_then(|v| u32::try_from(v).ok())
                .ok_or_else(|| {
                    self.cur
                        .expected_at(pos, &format!("an id or `End {block}`"), &quote(text))
                })?;
            out.push(id);
        }
    }

    fn sub_model_part(&mut self, parent: Option<&str>) -> Result<(), Error> {
        let name_tok = self.cur.expect_token("a sub model part name")?;
        let path = match parent {
            Some(p) => format!("{p}.{}", name_tok.text),
            None => name_tok.text.to_owned(),
        };
        let npos = name_tok.pos;
        let part: PartIdx = self
            .mp
            .create_part(&path)
            .map_err(|e| self.model_err(npos, e))?;
        loop {
            let t = self.next("SubModelPart")?;
            let (text, pos) = (t.text, t.pos);
            if self.at_end_of(&Token { text, pos }, "SubModelPart")? {
                return Ok(());
            }
            if text != "Begin" {
                return Err(self.cur.expected_at(
                    pos,
                    "`Begin` or `End SubModelPart`",
                    &quote(text),
                ));
            }
            let b = self.cur.expect_token("a block name")?;
            let (btext, bpos) = (b.text, b.pos);
            match btext {
                "SubModelPartNodes" => {
                    let (ids, start) = self.id_list(btext)?;
                    self.ids.clear();
                    for (k, id) in ids.into_iter().enumerate() {
                        let idx = self.mp.nodes().index_of(id).ok_or_else(|| {
                            self.missing(csm_model::EntityKind::Node, id, self.word_pos(start, k))
                        })?;
                        self.ids.push(idx);
                    }
                    self.ids.sort_unstable();
                    let ids = std::mem::take(&mut self.ids);
                    self.mp.add_nodes_to_part(part, &ids);
                    self.ids = ids;
                }
                "SubModelPartElements" => {
                    let v = self.entity_list(btext, csm_model::EntityKind::Element)?;
                    let v: Vec<_> = v.into_iter().map(csm_model::ElementIdx).collect();
                    self.mp.add_elements_to_part(part, &v);
                }
                "SubModelPartConditions" => {
                    let v = self.entity_list(btext, csm_model::EntityKind::Condition)?;
                    let v: Vec<_> = v.into_iter().map(csm_model::ConditionIdx).collect();
                    self.mp.add_conditions_to_part(part, &v);
                }
                "SubModelPartData"
                | "SubModelPartTables"
                | "SubModelPartProperties"
                | "SubModelPartGeometries"
                | "SubModelPartConstraints" => {
                    self.skip_block(Token {
                        text: btext,
                        pos: bpos,
                    })?;
                }
                "SubModelPart" => {
                    let p = path.clone();
                    self.sub_model_part(Some(&p))?;
                }
                other => {
                    return Err(self
                        .cur
                        .error_at(bpos, ErrorKind::UnknownBlock(other.to_owned())));
                }
            }
        }
    }

    /// The sorted dense indices of the element or condition (`entity`) ids of `block`.
    fn entity_list(
        &mut self,
        block: &str,
        entity: csm_model::EntityKind,
    ) -> Result<Vec<u32>, Error> {
        let (ids, start) = self.id_list(block)?;
        let entities = match entity {
            csm_model::EntityKind::Element => self.mp.elements(),
            _ => self.mp.conditions(),
        };
        let mut v = Vec::with_capacity(ids.len());
        for (k, id) in ids.into_iter().enumerate() {
            let i = entities
                .index_of(id)
                .ok_or_else(|| self.missing(entity, id, self.word_pos(start, k)))?;
            v.push(u32::try_from(i).expect("entity index fits u32"));
        }
        v.sort_unstable();
        Ok(v)
    }

    fn missing(&self, entity: csm_model::EntityKind, id: u32, pos: usize) -> Error {
        self.model_err(
            pos,
            csm_model::Error::new(csm_model::ErrorKind::MissingEntity { entity, id }),
        )
    }
}
