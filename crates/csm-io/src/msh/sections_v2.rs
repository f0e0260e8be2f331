//! MSH 2.2 `$Nodes` and `$Elements`, ASCII and binary.
//!
//! ASCII: `n`, then `tag x y z` per node; `n`, then `tag type n_tags tags… nodes…` per
//! element, where the first tag is the physical group (0: none). Binary: the counts are text
//! lines, the rest is little-endian `int`/`double`; elements come in blocks headed by
//! `type n_follow n_tags`.

use crate::cursor::Cursor;
use crate::error::{Error, ErrorKind};
use crate::msh::element_type;
use crate::msh::parse_msh::Format;
use crate::msh::raw_mesh::{RawMesh, RawNode};

/// A tag as a positive 32-bit id.
fn tag_of(cur: &Cursor<'_>, v: i64, pos: usize, what: &str) -> Result<u32, Error> {
    u32::try_from(v)
        .ok()
        .filter(|&t| t > 0)
        .ok_or_else(|| cur.expected_at(pos, what, &v.to_string()))
}

/// `$Nodes` of MSH 2.2.
pub(crate) fn nodes(cur: &mut Cursor<'_>, f: Format, raw: &mut RawMesh) -> Result<(), Error> {
    let n = cur.u64("the number of nodes")?;
    if !f.binary {
        for _ in 0..n {
            cur.skip_ws()?;
            let pos = cur.pos();
            let tag = cur.id("a node tag")?;
            let x = cur.f64("a finite x coordinate")?;
            let y = cur.f64("a finite y coordinate")?;
            let z = cur.f64("a finite z coordinate")?;
            raw.nodes.push(RawNode {
                tag,
                xyz: [x, y, z],
                pos,
                binary: false,
            });
        }
        return Ok(());
    }
    cur.skip_line_end()?;
    cur.set_binary(Some("$Nodes"));
    for _ in 0..n {
        let pos = cur.pos();
        let t = cur.bin_i32("a node tag")?;
        let tag = tag_of(cur, t.into(), pos, "a positive node tag")?;
        let x = cur.bin_f64("an x coordinate")?;
        let y = cur.bin_f64("a y coordinate")?;
        let z = cur.bin_f64("a z coordinate")?;
        raw.nodes.push(RawNode {
            tag,
            xyz: [x, y, z],
            pos,
            binary: true,
        });
    }
    cur.set_binary(None);
    Ok(())
}

/// `$Elements` of MSH 2.2.
pub(crate) fn elements(cur: &mut Cursor<'_>, f: Format, raw: &mut RawMesh) -> Result<(), Error> {
    let n = cur.u64("the number of elements")?;
    if !f.binary {
        for _ in 0..n {
            cur.skip_ws()?;
            let pos = cur.pos();
            let tag = cur.id("an element tag")?;
            let tpos = cur.pos();
            let ty = cur.i64("an element type")?;
            let Some(nn) = element_type::n_nodes(ty) else {
                return Err(cur.error_at(tpos + 1, ErrorKind::UnknownElementType(ty)));
            };
            let n_tags = cur.u64("the number of tags")?;
            let mut physical = 0;
            for k in 0..n_tags {
                let v = cur.i64("a tag")?;
                if k == 0 {
                    physical = v;
                }
            }
            let first = raw.node_tags.len();
            for _ in 0..nn {
                let node = cur.id("a node tag")?;
                raw.node_tags.push(node);
            }
            let phys: &[(usize, i64)] = if physical != 0 {
                &[(element_type::dim(ty), physical)]
            } else {
                &[]
            };
            raw.push_element(cur, tag, ty, first, phys, pos, false)?;
        }
        return Ok(());
    }
    cur.skip_line_end()?;
    cur.set_binary(Some("$Elements"));
    let mut left = n;
    while left > 0 {
        let hpos = cur.pos();
        let ty = i64::from(cur.bin_i32("an element type")?);
        let Some(nn) = element_type::n_nodes(ty) else {
            return Err(cur.error_at(hpos, ErrorKind::UnknownElementType(ty)));
        };
        let fpos = cur.pos();
        let n_follow = cur.bin_i32("the number of elements that follow")?;
        let n_follow = u64::try_from(n_follow)
            .ok()
            .filter(|&k| k > 0 && k <= left)
            .ok_or_else(|| {
                cur.expected_at(
                    fpos,
                    &format!("between 1 and {left} elements that follow"),
                    &n_follow.to_string(),
                )
            })?;
        let tpos = cur.pos();
        let n_tags = cur.bin_i32("the number of tags")?;
        let n_tags = u64::try_from(n_tags)
            .map_err(|_| cur.expected_at(tpos, "a number of tags ≥ 0", &n_tags.to_string()))?;
        for _ in 0..n_follow {
            let pos = cur.pos();
            let t = cur.bin_i32("an element tag")?;
            let tag = tag_of(cur, t.into(), pos, "a positive element tag")?;
            let mut physical = 0;
            for k in 0..n_tags {
                let v = cur.bin_i32("a tag")?;
                if k == 0 {
                    physical = i64::from(v);
                }
            }
            let first = raw.node_tags.len();
            for _ in 0..nn {
                let npos = cur.pos();
                let v = cur.bin_i32("a node tag")?;
                raw.node_tags
                    .push(tag_of(cur, v.into(), npos, "a positive node tag")?);
            }
            let phys: &[(usize, i64)] = if physical != 0 {
                &[(element_type::dim(ty), physical)]
            } else {
                &[]
            };
            raw.push_element(cur, tag, ty, first, phys, pos, true)?;
        }
        left -= n_follow;
    }
    cur.set_binary(None);
    Ok(())
}
