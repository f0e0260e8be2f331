//! MSH 4.1 `$Entities`, `$Nodes` and `$Elements`, ASCII and binary.
//!
//! Binary 4.1 writes `int` for dimensions, entity tags, types and physical tags, `size_t`
//! (8 bytes, the data size) for counts and node/element tags, and `double` for coordinates,
//! everything little-endian, right after the section's header line.

use crate::cursor::Cursor;
use crate::error::{Error, ErrorKind};
use crate::msh::element_type;
use crate::msh::parse_msh::Format;
use crate::msh::raw_mesh::{RawMesh, RawNode};

/// Reads ASCII or binary values with one call.
struct Reader<'c, 'a> {
    cur: &'c mut Cursor<'a>,
    binary: bool,
}

impl Reader<'_, '_> {
    /// An `int` (binary) or an integer word.
    fn int(&mut self, what: &str) -> Result<i64, Error> {
        if self.binary {
            self.cur.bin_i32(what).map(i64::from)
        } else {
            self.cur.i64(what)
        }
    }

    /// A `size_t` count (binary) or an unsigned word.
    fn size(&mut self, what: &str) -> Result<u64, Error> {
        if self.binary {
            self.cur.bin_u64(what)
        } else {
            self.cur.u64(what)
        }
    }

    /// A `size_t` tag as a positive 32-bit id.
    fn tag(&mut self, what: &str) -> Result<u32, Error> {
        self.cur.skip_ws_if_text(self.binary)?;
        let pos = self.cur.pos();
        let v = self.size(what)?;
        u32::try_from(v).ok().filter(|&t| t > 0).ok_or_else(|| {
            self.cur
                .expected_at(pos, &format!("{what} in 1..2^32"), &v.to_string())
        })
    }

    /// A `double`; in text it must be finite.
    fn real(&mut self, what: &str) -> Result<f64, Error> {
        if self.binary {
            self.cur.bin_f64(what)
        } else {
            self.cur.f64(what)
        }
    }
}

impl Cursor<'_> {
    /// Skips whitespace unless reading binary data.
    fn skip_ws_if_text(&mut self, binary: bool) -> Result<(), Error> {
        if binary { Ok(()) } else { self.skip_ws() }
    }
}

fn start<'c, 'a>(
    cur: &'c mut Cursor<'a>,
    f: Format,
    section: &'static str,
) -> Result<Reader<'c, 'a>, Error> {
    if f.binary {
        cur.skip_line_end()?;
        cur.set_binary(Some(section));
    }
    Ok(Reader {
        cur,
        binary: f.binary,
    })
}

fn dim_of(r: &mut Reader<'_, '_>) -> Result<usize, Error> {
    r.cur.skip_ws_if_text(r.binary)?;
    let pos = r.cur.pos();
    let d = r.int("an entity dimension (0-3)")?;
    usize::try_from(d).ok().filter(|&d| d <= 3).ok_or_else(|| {
        r.cur
            .expected_at(pos, "an entity dimension (0-3)", &d.to_string())
    })
}

/// `$Entities`: the physical groups of every point, curve, surface and volume.
pub(crate) fn entities(cur: &mut Cursor<'_>, f: Format, raw: &mut RawMesh) -> Result<(), Error> {
    let mut r = start(cur, f, "$Entities")?;
    let mut counts = [0u64; 4];
    for c in &mut counts {
        *c = r.size("an entity count")?;
    }
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let tag = r.int("an entity tag")?;
            let n_coords = if dim == 0 { 3 } else { 6 };
            for _ in 0..n_coords {
                r.real("a bounding-box coordinate")?;
            }
            let n_phys = r.size("the number of physical tags")?;
            let mut phys = Vec::new();
            for _ in 0..n_phys {
                phys.push(r.int("a physical tag")?);
            }
            if dim > 0 {
                let n_bound = r.size("the number of bounding entities")?;
                for _ in 0..n_bound {
                    r.int("a bounding entity tag")?;
                }
            }
            raw.entities.insert((dim, tag), phys);
        }
    }
    r.cur.set_binary(None);
    Ok(())
}

/// `$Nodes`: blocks of node tags, then their coordinates (plus parametric ones, skipped).
pub(crate) fn nodes(cur: &mut Cursor<'_>, f: Format, raw: &mut RawMesh) -> Result<(), Error> {
    let mut r = start(cur, f, "$Nodes")?;
    let n_blocks = r.size("the number of entity blocks")?;
    for _ in 0..3 {
        r.size("the number of nodes and the min/max node tags")?;
    }
    let mut block: Vec<(u32, usize)> = Vec::new();
    for _ in 0..n_blocks {
        let dim = dim_of(&mut r)?;
        r.int("an entity tag")?;
        r.cur.skip_ws_if_text(r.binary)?;
        let ppos = r.cur.pos();
        let parametric = r.int("the parametric flag (0 or 1)")?;
        let extra = match parametric {
            0 => 0,
            1 => dim,
            p => {
                return Err(r.cur.expected_at(
                    ppos,
                    "the parametric flag (0 or 1)",
                    &p.to_string(),
                ));
            }
        };
        let n = r.size("the number of nodes in the block")?;
        block.clear();
        for _ in 0..n {
            r.cur.skip_ws_if_text(r.binary)?;
            let pos = r.cur.pos();
            block.push((r.tag("a node tag")?, pos));
        }
        for &(tag, _) in &block {
            r.cur.skip_ws_if_text(r.binary)?;
            let pos = r.cur.pos();
            let x = r.real("an x coordinate")?;
            let y = r.real("a y coordinate")?;
            let z = r.real("a z coordinate")?;
            for _ in 0..extra {
                r.real("a parametric coordinate")?;
            }
            raw.nodes.push(RawNode {
                tag,
                xyz: [x, y, z],
                pos,
                binary: r.binary,
            });
        }
    }
    r.cur.set_binary(None);
    Ok(())
}

/// `$Elements`: blocks of cells of one type on one entity.
pub(crate) fn elements(cur: &mut Cursor<'_>, f: Format, raw: &mut RawMesh) -> Result<(), Error> {
    let mut r = start(cur, f, "$Elements")?;
    let n_blocks = r.size("the number of entity blocks")?;
    for _ in 0..3 {
        r.size("the number of elements and the min/max element tags")?;
    }
    for _ in 0..n_blocks {
        let dim = dim_of(&mut r)?;
        let entity = r.int("an entity tag")?;
        r.cur.skip_ws_if_text(r.binary)?;
        let tpos = r.cur.pos();
        let ty = r.int("an element type")?;
        let Some(nn) = element_type::n_nodes(ty) else {
            return Err(r.cur.error_at(tpos, ErrorKind::UnknownElementType(ty)));
        };
        let n = r.size("the number of elements in the block")?;
        let phys: Vec<(usize, i64)> = raw
            .entities
            .get(&(dim, entity))
            .map(|p| p.iter().map(|&t| (element_type::dim(ty), t)).collect())
            .unwrap_or_default();
        for _ in 0..n {
            r.cur.skip_ws_if_text(r.binary)?;
            let pos = r.cur.pos();
            let tag = r.tag("an element tag")?;
            let first = raw.node_tags.len();
            for _ in 0..nn {
                let node = r.tag("a node tag")?;
                raw.node_tags.push(node);
            }
            raw.push_element(r.cur, tag, ty, first, &phys, pos, r.binary)?;
        }
    }
    r.cur.set_binary(None);
    Ok(())
}
