//! The section loop of a Gmsh file: `$MeshFormat` (version, ASCII/binary, endianness),
//! `$PhysicalNames`, and skipping of sections csm does not read (Gmsh's rule: an unknown
//! `$Section` is skipped up to `$EndSection`).

use crate::cursor::{Cursor, quote};
use crate::error::{Error, ErrorKind};
use crate::msh::raw_mesh::RawMesh;
use crate::msh::{sections_v2, sections_v4};

/// The format of the file, from `$MeshFormat`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Format {
    /// 2 (MSH 2.x) or 4 (MSH 4.1).
    pub(crate) major: u32,
    pub(crate) binary: bool,
}

/// Reads every section of the file.
pub(crate) fn parse_msh(cur: &mut Cursor<'_>) -> Result<RawMesh, Error> {
    if cur.at_end()? {
        return Err(cur.error_at(0, ErrorKind::Empty));
    }
    let mut raw = RawMesh::default();
    let mut format: Option<Format> = None;
    while let Some(t) = cur.token()? {
        let Some(name) = t.text.strip_prefix('$') else {
            return Err(cur.expected_at(t.pos, "a section `$Name`", &quote(t.text)));
        };
        if name.starts_with("End") {
            return Err(cur.expected_at(t.pos, "a section `$Name`", &quote(t.text)));
        }
        if name != "MeshFormat" && format.is_none() {
            return Err(cur.expected_at(t.pos, "`$MeshFormat` first", &quote(t.text)));
        }
        match (name, format) {
            ("MeshFormat", None) => {
                let f = mesh_format(cur)?;
                raw.merge_copies = f.major == 2;
                format = Some(f);
                continue;
            }
            ("MeshFormat", Some(_)) => {
                return Err(cur.expected_at(t.pos, "one `$MeshFormat`", "a second one"));
            }
            ("PhysicalNames", _) => physical_names(cur, &mut raw)?,
            ("Entities", Some(f)) if f.major == 4 => sections_v4::entities(cur, f, &mut raw)?,
            ("Nodes", Some(f)) if f.major == 4 => sections_v4::nodes(cur, f, &mut raw)?,
            ("Elements", Some(f)) if f.major == 4 => sections_v4::elements(cur, f, &mut raw)?,
            ("Nodes", Some(f)) => sections_v2::nodes(cur, f, &mut raw)?,
            ("Elements", Some(f)) => sections_v2::elements(cur, f, &mut raw)?,
            _ => {
                let end = format!("\n$End{name}");
                if cur.skip_past(end.as_bytes()).is_none() {
                    return Err(cur.error_at(t.pos, ErrorKind::Unterminated(format!("${name}"))));
                }
                continue;
            }
        }
        cur.expect_word(&format!("$End{name}"))?;
    }
    if format.is_none() {
        return Err(cur.eof("`$MeshFormat`"));
    }
    Ok(raw)
}

/// `$MeshFormat`: `version file-type data-size`, then (binary) the int 1 in the file's byte
/// order; csm reads little-endian files only.
fn mesh_format(cur: &mut Cursor<'_>) -> Result<Format, Error> {
    let v = cur.expect_token("the MSH version (2.2 or 4.1)")?;
    let major = match v.text {
        "4.1" => 4,
        t if t.starts_with("2.") || t == "2" => 2,
        t => return Err(cur.error_at(v.pos, ErrorKind::UnsupportedVersion(t.to_owned()))),
    };
    let ft = cur.expect_token("the file type (0 ASCII, 1 binary)")?;
    let binary = match ft.text {
        "0" => false,
        "1" => true,
        t => {
            return Err(cur.expected_at(
                ft.pos,
                "the file type 0 (ASCII) or 1 (binary)",
                &quote(t),
            ));
        }
    };
    let ds = cur.expect_token("the data size 8")?;
    if ds.text != "8" {
        return Err(cur.expected_at(ds.pos, "the data size 8", &quote(ds.text)));
    }
    if binary {
        cur.skip_line_end()?;
        let pos = cur.pos();
        cur.set_binary(Some("$MeshFormat"));
        let one = cur.bin_i32("the endianness marker (the int 1)")?;
        cur.set_binary(None);
        if one != 1 {
            let found = if one == 0x0100_0000 {
                "1 in big-endian byte order (csm reads little-endian files)".to_owned()
            } else {
                format!("{one}")
            };
            return Err(Error::new(
                cur.file(),
                crate::error::Location::Byte {
                    offset: pos,
                    section: "$MeshFormat".to_owned(),
                },
                ErrorKind::Expected {
                    expected: "the endianness marker 1 (little-endian)".to_owned(),
                    found,
                },
            ));
        }
    }
    cur.expect_word("$EndMeshFormat")?;
    Ok(Format { major, binary })
}

/// `$PhysicalNames` (always ASCII): `dim tag "name"` per line.
fn physical_names(cur: &mut Cursor<'_>, raw: &mut RawMesh) -> Result<(), Error> {
    let n = cur.u64("the number of physical names")?;
    for _ in 0..n {
        let dim = cur.u64("a physical group dimension (0-3)")?;
        if dim > 3 {
            return Err(cur.expected_at(
                cur.pos(),
                "a physical group dimension (0-3)",
                &dim.to_string(),
            ));
        }
        let tag = cur.i64("a physical tag")?;
        let (line, pos) = cur.rest_of_line()?;
        let name = line
            .strip_prefix('"')
            .and_then(|s| s.strip_suffix('"'))
            .ok_or_else(|| cur.expected_at(pos, "a quoted physical name", &quote(line)))?;
        raw.physical_names
            .insert((dim as usize, tag), name.to_owned());
    }
    Ok(())
}
