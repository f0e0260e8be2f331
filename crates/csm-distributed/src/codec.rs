//! The bytes the ranks exchange (little endian): a rank's owned result, a rank's local mesh.

use std::collections::BTreeMap;

use csm_geometry::GeometryKind;
use csm_model::{EntityArrays, MeshArrays, PartArrays};
use csm_search::{IdMap, NodeResult, SearchResult, StepResult};

// A rank's owned result as bytes (little endian): the pair maps, the nodes, the warnings.

pub(crate) fn put_u32(out: &mut Vec<u8>, x: u32) {
    out.extend_from_slice(&x.to_le_bytes());
}

pub(crate) fn put_str(out: &mut Vec<u8>, s: &str) {
    put_u32(out, s.len() as u32);
    out.extend_from_slice(s.as_bytes());
}

fn put_maps(out: &mut Vec<u8>, maps: &BTreeMap<String, IdMap<Vec<u32>>>) {
    put_u32(out, maps.len() as u32);
    for (key, map) in maps {
        put_str(out, key);
        put_u32(out, map.len() as u32);
        for (id, masters) in map {
            put_u32(out, *id);
            put_u32(out, masters.len() as u32);
            for m in masters {
                put_u32(out, *m);
            }
        }
    }
}

pub(crate) fn encode_result(r: &SearchResult) -> Vec<u8> {
    let mut out = Vec::new();
    put_maps(&mut out, &r.pairs);
    put_maps(&mut out, &r.pruned);
    put_u32(&mut out, r.nodes.len() as u32);
    for (id, n) in &r.nodes {
        put_u32(&mut out, *id);
        out.push(u8::from(n.active) | (u8::from(n.normal_gap.is_some()) << 1));
        out.extend_from_slice(&n.normal_gap.unwrap_or(0.0).to_le_bytes());
    }
    put_u32(&mut out, r.warnings.len() as u32);
    for w in &r.warnings {
        put_str(&mut out, w);
    }
    out.push(u8::from(r.master_slave_constraints.is_some()));
    out.extend_from_slice(&(r.paired_conditions as u64).to_le_bytes());
    put_u32(&mut out, r.steps.len() as u32);
    for s in &r.steps {
        put_u32(&mut out, s.step);
        out.extend_from_slice(&s.search_s.to_le_bytes());
        let bytes = encode_result(&s.result);
        put_u32(&mut out, bytes.len() as u32);
        out.extend_from_slice(&bytes);
    }
    out
}

/// Reads what [`encode`] wrote (bytes from this program on another rank).
pub(crate) struct Reader<'a>(pub(crate) &'a [u8]);

impl Reader<'_> {
    pub(crate) fn bytes(&mut self, n: usize) -> &[u8] {
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        head
    }
    pub(crate) fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.bytes(4).try_into().expect("4 bytes"))
    }
    pub(crate) fn string(&mut self) -> String {
        let n = self.u32() as usize;
        String::from_utf8_lossy(self.bytes(n)).into_owned()
    }
    pub(crate) fn maps(&mut self) -> BTreeMap<String, IdMap<Vec<u32>>> {
        (0..self.u32())
            .map(|_| {
                let key = self.string();
                let map = (0..self.u32())
                    .map(|_| {
                        let id = self.u32();
                        let masters = (0..self.u32()).map(|_| self.u32()).collect();
                        (id, masters)
                    })
                    .collect();
                (key, map)
            })
            .collect()
    }
}

pub(crate) fn decode_result(bytes: &[u8]) -> SearchResult {
    let mut r = Reader(bytes);
    let pairs = r.maps();
    let pruned = r.maps();
    let nodes = (0..r.u32())
        .map(|_| {
            let id = r.u32();
            let flags = r.bytes(1)[0];
            let gap = f64::from_le_bytes(r.bytes(8).try_into().expect("8 bytes"));
            let result = NodeResult {
                normal_gap: (flags & 2 != 0).then_some(gap),
                active: flags & 1 != 0,
            };
            (id, result)
        })
        .collect();
    let warnings = (0..r.u32()).map(|_| r.string()).collect();
    let constraints = r.bytes(1)[0] != 0;
    let paired = u64::from_le_bytes(r.bytes(8).try_into().expect("8 bytes"));
    let steps = (0..r.u32())
        .map(|_| {
            let step = r.u32();
            let search_s = f64::from_le_bytes(r.bytes(8).try_into().expect("8 bytes"));
            let n = r.u32() as usize;
            StepResult {
                step,
                result: decode_result(r.bytes(n)),
                search_s,
            }
        })
        .collect();
    SearchResult {
        paired_conditions: paired as usize,
        pairs,
        pruned,
        nodes,
        warnings,
        master_slave_constraints: constraints.then_some(0),
        steps,
        ..SearchResult::default()
    }
}

// A rank's local mesh: nodes (id, x, y, z), elements and conditions by kind name (ids,
// connectivity, properties), parts (name, nodes, elements, conditions), the domain size.

fn put_list(out: &mut Vec<u8>, list: &[u32]) {
    put_u32(out, list.len() as u32);
    for x in list {
        put_u32(out, *x);
    }
}

fn put_entities(out: &mut Vec<u8>, by_kind: &BTreeMap<GeometryKind, EntityArrays>) {
    put_u32(out, by_kind.len() as u32);
    for (kind, a) in by_kind {
        put_str(out, kind.name());
        put_list(out, &a.ids);
        put_list(out, &a.connectivity);
        put_list(out, &a.properties);
    }
}

pub(crate) fn encode_mesh(m: &MeshArrays) -> Vec<u8> {
    let mut out = Vec::new();
    put_list(&mut out, &m.node_ids);
    for p in &m.points {
        for x in p {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    put_entities(&mut out, &m.elements);
    put_entities(&mut out, &m.conditions);
    put_u32(&mut out, m.parts.len() as u32);
    for (name, p) in &m.parts {
        put_str(&mut out, name);
        put_list(&mut out, &p.nodes);
        put_list(&mut out, &p.elements);
        put_list(&mut out, &p.conditions);
    }
    put_u32(&mut out, m.domain_size.map_or(0, |d| d + 1));
    out
}

impl Reader<'_> {
    fn list(&mut self) -> Vec<u32> {
        (0..self.u32()).map(|_| self.u32()).collect()
    }

    fn f64(&mut self) -> f64 {
        f64::from_le_bytes(self.bytes(8).try_into().expect("8 bytes"))
    }

    fn entities(&mut self) -> Result<BTreeMap<GeometryKind, EntityArrays>, String> {
        (0..self.u32())
            .map(|_| {
                let name = self.string();
                let kind = GeometryKind::from_name(&name)
                    .ok_or_else(|| format!("unknown geometry `{name}`"))?;
                let ids = self.list();
                let connectivity = self.list();
                let properties = self.list();
                Ok((
                    kind,
                    EntityArrays {
                        ids,
                        connectivity,
                        properties,
                    },
                ))
            })
            .collect()
    }
}

pub(crate) fn decode_mesh(bytes: &[u8]) -> Result<MeshArrays, String> {
    let mut r = Reader(bytes);
    let node_ids = r.list();
    let points = node_ids
        .iter()
        .map(|_| [r.f64(), r.f64(), r.f64()])
        .collect();
    let elements = r.entities()?;
    let conditions = r.entities()?;
    let parts = (0..r.u32())
        .map(|_| {
            let name = r.string();
            let part = PartArrays {
                nodes: r.list(),
                elements: r.list(),
                conditions: r.list(),
            };
            (name, part)
        })
        .collect();
    let domain_size = r.u32().checked_sub(1);
    Ok(MeshArrays {
        node_ids,
        points,
        elements,
        conditions,
        parts,
        domain_size,
    })
}
