//! `csm info`: the parts of a mesh with their entity counts and geometry types.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use csm_geometry::GeometryKind;
use csm_model::{ModelPart, PartIdx};

/// Counts and geometry kinds of one part (or of the whole model).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PartInfo {
    /// Number of nodes.
    pub nodes: usize,
    /// Number of elements.
    pub elements: usize,
    /// Number of conditions.
    pub conditions: usize,
    /// Element geometry kinds with their counts, by kind.
    pub element_kinds: BTreeMap<GeometryKind, usize>,
    /// Condition geometry kinds with their counts, by kind.
    pub condition_kinds: BTreeMap<GeometryKind, usize>,
}

/// What `csm info` reports about a model.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MeshInfo {
    /// The whole model.
    pub total: PartInfo,
    /// `DOMAIN_SIZE` of the model (2 or 3), if known.
    pub domain_size: Option<u32>,
    /// Every sub model part by full path (`.`-separated), in path order.
    pub parts: BTreeMap<String, PartInfo>,
}

fn count_kinds(kinds: impl Iterator<Item = GeometryKind>) -> BTreeMap<GeometryKind, usize> {
    let mut m = BTreeMap::new();
    for k in kinds {
        *m.entry(k).or_insert(0) += 1;
    }
    m
}

fn part_info(model: &ModelPart, part: PartIdx) -> PartInfo {
    let p = model.part(part);
    PartInfo {
        nodes: p.nodes().len(),
        elements: p.elements().len(),
        conditions: p.conditions().len(),
        element_kinds: count_kinds(
            p.elements()
                .iter()
                .map(|e| model.elements().kind(e.index())),
        ),
        condition_kinds: count_kinds(
            p.conditions()
                .iter()
                .map(|c| model.conditions().kind(c.index())),
        ),
    }
}

/// Summarises `model`: totals and every sub model part.
pub fn mesh_info(model: &ModelPart) -> MeshInfo {
    let total = PartInfo {
        nodes: model.nodes().len(),
        elements: model.elements().len(),
        conditions: model.conditions().len(),
        element_kinds: count_kinds(model.elements().kinds().iter().copied()),
        condition_kinds: count_kinds(model.conditions().kinds().iter().copied()),
    };
    let parts = (0..model.parts().len())
        .map(|i| {
            let idx = PartIdx(i as u32);
            (model.part(idx).path().to_owned(), part_info(model, idx))
        })
        .collect();
    let domain_size = model.process_info().number("DOMAIN_SIZE").map(|d| d as u32);
    MeshInfo {
        total,
        domain_size,
        parts,
    }
}

fn kinds_text(kinds: &BTreeMap<GeometryKind, usize>) -> String {
    let v: Vec<String> = kinds
        .iter()
        .map(|(k, n)| format!("{} ×{n}", k.name()))
        .collect();
    if v.is_empty() {
        "-".to_owned()
    } else {
        v.join(", ")
    }
}

impl MeshInfo {
    /// Keeps only the part at `path` (and nothing else); `None` if there is no such part.
    pub fn only_part(&self, path: &str) -> Option<MeshInfo> {
        let key = path.trim().replace('/', ".");
        let part = self.parts.get(&key)?;
        Some(MeshInfo {
            total: self.total.clone(),
            domain_size: self.domain_size,
            parts: BTreeMap::from([(key, part.clone())]),
        })
    }

    /// The JSON contract of `csm info --json`:
    /// `{"nodes": N, "elements": N, "conditions": N, "parts": {"<path>": {"nodes": N,
    /// "elements": N, "conditions": N}}}`, keys in path order.
    pub fn to_json(&self) -> serde_json::Value {
        let parts: serde_json::Map<String, serde_json::Value> = self
            .parts
            .iter()
            .map(|(path, p)| {
                (
                    path.clone(),
                    serde_json::json!({
                        "nodes": p.nodes, "elements": p.elements, "conditions": p.conditions
                    }),
                )
            })
            .collect();
        serde_json::json!({
            "nodes": self.total.nodes,
            "elements": self.total.elements,
            "conditions": self.total.conditions,
            "parts": parts,
        })
    }

    /// The human-readable report of `csm info`.
    pub fn to_text(&self, mesh_name: &str) -> String {
        let mut s = String::new();
        let dim = self
            .domain_size
            .map(|d| format!("{d}D"))
            .unwrap_or_else(|| "?D".to_owned());
        // Writing to a String cannot fail.
        let _ = writeln!(
            s,
            "{mesh_name}: {dim}, {} nodes, {} elements, {} conditions",
            self.total.nodes, self.total.elements, self.total.conditions
        );
        let _ = writeln!(s, "  elements:   {}", kinds_text(&self.total.element_kinds));
        let _ = writeln!(
            s,
            "  conditions: {}",
            kinds_text(&self.total.condition_kinds)
        );
        if self.parts.is_empty() {
            let _ = writeln!(s, "no sub model parts");
            return s;
        }
        let width = self.parts.keys().map(|k| k.len()).max().unwrap_or(0).max(4);
        let _ = writeln!(
            s,
            "{:<width$}  {:>8}  {:>8}  {:>10}  geometry",
            "part", "nodes", "elements", "conditions"
        );
        for (path, p) in &self.parts {
            let mut kinds = p.element_kinds.clone();
            for (k, n) in &p.condition_kinds {
                *kinds.entry(*k).or_insert(0) += n;
            }
            let _ = writeln!(
                s,
                "{path:<width$}  {:>8}  {:>8}  {:>10}  {}",
                p.nodes,
                p.elements,
                p.conditions,
                kinds_text(&kinds)
            );
        }
        s
    }
}
