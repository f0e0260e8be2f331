//! What a Gmsh file holds, before it becomes a model: physical names, entities' physical
//! groups, nodes and cells, with the byte offset of each for error messages.

use std::collections::HashMap;
use std::ops::Range;

use crate::cursor::Cursor;
use crate::error::Error;

/// A node as read.
#[derive(Debug, Clone)]
pub(crate) struct RawNode {
    pub(crate) tag: u32,
    pub(crate) xyz: [f64; 3],
    pub(crate) pos: usize,
    pub(crate) binary: bool,
}

/// A cell as read (any dimension).
#[derive(Debug, Clone)]
pub(crate) struct RawElement {
    pub(crate) tag: u32,
    pub(crate) gmsh_type: i64,
    pub(crate) nodes: Range<usize>,
    /// Physical groups as (dimension, physical tag).
    pub(crate) physicals: Vec<(usize, i64)>,
    pub(crate) pos: usize,
    pub(crate) binary: bool,
}

/// The content of a Gmsh file.
#[derive(Debug, Default)]
pub(crate) struct RawMesh {
    pub(crate) physical_names: HashMap<(usize, i64), String>,
    /// MSH 4.1: the physical tags of each entity (dimension, entity tag).
    pub(crate) entities: HashMap<(usize, i64), Vec<i64>>,
    pub(crate) nodes: Vec<RawNode>,
    pub(crate) elements: Vec<RawElement>,
    pub(crate) node_tags: Vec<u32>,
    element_by_tag: HashMap<u32, usize>,
    /// MSH 2.2: cells by (type, sorted nodes), to merge the copies Gmsh writes once per
    /// physical group (Gmsh 4 gives each copy a new tag).
    pub(crate) merge_copies: bool,
    element_by_nodes: HashMap<(i64, Vec<u32>), usize>,
}

impl RawMesh {
    /// The node tags of `e`.
    pub(crate) fn element_nodes(&self, e: &RawElement) -> &[u32] {
        &self.node_tags[e.nodes.clone()]
    }

    /// Adds a cell whose node tags were pushed onto `node_tags` from `first_node` on. The same
    /// tag with the same type and nodes again only adds its physical groups; with other data
    /// it is an error. In MSH 2.2 a cell is listed once per physical group, and Gmsh 4 gives
    /// each copy a new tag: a cell with the type and nodes of an earlier one is merged into
    /// it (the first tag is kept).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn push_element(
        &mut self,
        cur: &Cursor<'_>,
        tag: u32,
        gmsh_type: i64,
        first_node: usize,
        physicals: &[(usize, i64)],
        pos: usize,
        binary: bool,
    ) -> Result<(), Error> {
        let nodes = first_node..self.node_tags.len();
        let mut existing = self.element_by_tag.get(&tag).copied();
        let mut key = None;
        if existing.is_none() && self.merge_copies {
            let mut sorted = self.node_tags[nodes.clone()].to_vec();
            sorted.sort_unstable();
            let k = (gmsh_type, sorted);
            existing = self.element_by_nodes.get(&k).copied();
            key = Some(k);
        }
        if let Some(i) = existing {
            let old = &self.elements[i];
            let same = old.gmsh_type == gmsh_type
                && self.node_tags[old.nodes.clone()] == self.node_tags[nodes.clone()];
            if !same {
                return Err(cur.expected_at(
                    pos,
                    "a new element tag (or a repeat of the same cell)",
                    &format!("tag {tag} again, with another type or other nodes"),
                ));
            }
            self.node_tags.truncate(first_node);
            let old = &mut self.elements[i];
            for p in physicals {
                if !old.physicals.contains(p) {
                    old.physicals.push(*p);
                }
            }
            return Ok(());
        }
        self.element_by_tag.insert(tag, self.elements.len());
        if let Some(k) = key {
            self.element_by_nodes.insert(k, self.elements.len());
        }
        self.elements.push(RawElement {
            tag,
            gmsh_type,
            nodes,
            physicals: physicals.to_vec(),
            pos,
            binary,
        });
        Ok(())
    }
}
