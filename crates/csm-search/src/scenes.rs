//! Scenes built in code, for the tests of this crate and of the layers that use it (the
//! evaluation layer's): two non-matching plates of prisms and the setup that pairs them.

use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ConditionId, ElementId, ModelPart, NodeId, NodeIdx, PropertiesId};

use crate::{SearchSetup, parse_setup};

/// The cell size of [`plates`].
pub const PLATES_H: f64 = 0.25;
const H: f64 = PLATES_H;

/// Two square plates of `n × n` cells split into triangles, each the contact face of one layer
/// of prisms `H` thick (so every node is in an element, as Kratos' Python path needs): `Slave`
/// at height `gap` facing down (its prisms above), `Master` at height 0 facing up (its prisms
/// below) — or facing down too with `master_down` (its prisms above). The slave grid is shifted
/// by a third of a cell so the meshes do not match.
pub fn plates(n: usize, gap: f64, master_down: bool) -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    let mut next_node = 1u32;
    let mut next_cond = 1u32;
    let mut next_elem = 1u32;
    for (name, z, shift, down) in [
        ("Slave", gap, H / 3.0, true),
        ("Master", 0.0, 0.0, master_down),
    ] {
        let first = next_node;
        // Layer 0 is the contact face, layer 1 the far side of the prisms.
        let far = if down { z + H } else { z - H };
        for layer_z in [z, far] {
            for j in 0..=n {
                for i in 0..=n {
                    let (x, y) = (i as f64 * H + shift, j as f64 * H + shift);
                    mp.add_node(NodeId(next_node), Point::new(x, y, layer_z))
                        .unwrap();
                    next_node += 1;
                }
            }
        }
        let layer = (n + 1) * (n + 1);
        let id =
            |i: usize, j: usize, l: usize| NodeId(first + (l * layer + j * (n + 1) + i) as u32);
        let part = mp.create_part(name).unwrap();
        let mut conds = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                // Counter-clockwise seen from above.
                for [a, b, c] in [[0, 1, 2], [0, 2, 3]] {
                    let (pa, pb, pc) = (corners[a], corners[b], corners[c]);
                    let face = |l: usize| [id(pa.0, pa.1, l), id(pb.0, pb.1, l), id(pc.0, pc.1, l)];
                    let (contact, opposite) = (face(0), face(1));
                    let t = if down {
                        [contact[0], contact[2], contact[1]]
                    } else {
                        contact
                    };
                    let idx = mp
                        .add_condition(
                            ConditionId(next_cond),
                            GeometryKind::Triangle3D3,
                            "",
                            &t,
                            PropertiesId(0),
                        )
                        .unwrap();
                    conds.push(idx);
                    next_cond += 1;
                    // Prism: lower triangle counter-clockwise from above, then the upper one.
                    let (lower, upper) = if z < far {
                        (contact, opposite)
                    } else {
                        (opposite, contact)
                    };
                    let nodes = [lower[0], lower[1], lower[2], upper[0], upper[1], upper[2]];
                    mp.add_element(
                        ElementId(next_elem),
                        GeometryKind::Prism3D6,
                        "",
                        &nodes,
                        PropertiesId(0),
                    )
                    .unwrap();
                    next_elem += 1;
                }
            }
        }
        let nodes: Vec<NodeIdx> = (first..first + layer as u32)
            .map(|i| mp.nodes().index_of(i).unwrap())
            .collect();
        mp.add_nodes_to_part(part, &nodes);
        mp.add_conditions_to_part(part, &conds);
    }
    mp.process_info_mut().set_number("DOMAIN_SIZE", 3.0);
    mp
}

/// The setup of [`plates`]: pair 0 of `Slave` (assumed slave) and `Master`, with
/// `search_parameters` (a JSON object) and `extra` top-level keys (`, "key": value, …`).
/// Panics if they do not make a valid setup (a test's own mistake).
pub fn plates_setup(search_parameters: &str, extra: &str) -> SearchSetup {
    let text = format!(
        r#"{{"contact_model_part": {{"0": ["Slave", "Master"]}},
            "assume_master_slave": {{"0": ["Slave"]}},
            "search_parameters": {search_parameters} {extra}}}"#
    );
    // The text is a valid setup for any valid `search_parameters` object and extra keys.
    parse_setup(&text, "plates setup").expect("a valid plates setup")
}
