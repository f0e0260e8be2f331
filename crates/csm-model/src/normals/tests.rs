use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Vector};

use super::node_sums::{NODE_BLOCK_BITS, SERIAL_CONTRIBUTIONS, sums_by_node_blocks};
use super::*;
use crate::GeometryStamp;
use crate::{ConditionId, NodeId, PropertiesId};

fn model(points: &[[f64; 3]], conditions: &[(GeometryKind, &[u32])]) -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    for (i, p) in points.iter().enumerate() {
        mp.add_node(NodeId(i as u32 + 1), Point::new(p[0], p[1], p[2]))
            .unwrap();
    }
    for (i, (kind, nodes)) in conditions.iter().enumerate() {
        let ids: Vec<NodeId> = nodes.iter().map(|&n| NodeId(n)).collect();
        mp.add_condition(ConditionId(i as u32 + 1), *kind, "", &ids, PropertiesId(0))
            .unwrap();
    }
    mp
}

fn nodal(mp: &ModelPart) -> &[Vector] {
    mp.nodal_data().vector(VectorVar::Normal, 0).unwrap()
}

#[track_caller]
fn assert_close(a: &Vector, b: [f64; 3]) {
    assert!(
        (a - Vector::new(b[0], b[1], b[2])).norm() < 1e-14,
        "{a:?} != {b:?}"
    );
}

#[test]
fn flat_quad_patch_has_the_face_normal_everywhere() {
    let pts = [
        [0., 0., 0.],
        [1., 0., 0.],
        [2., 0., 0.],
        [0., 1., 0.],
        [1., 1., 0.],
        [2., 1., 0.],
    ];
    let q = GeometryKind::Quadrilateral3D4;
    let mut mp = model(&pts, &[(q, &[1, 2, 5, 4]), (q, &[2, 3, 6, 5])]);
    for mode in [NormalsMode::Kratos, NormalsMode::Once] {
        compute_unit_normals(&mut mp, None, mode).unwrap();
        for n in mp.condition_normals() {
            assert_close(n, [0., 0., 1.]);
        }
        for n in nodal(&mp) {
            assert_close(n, [0., 0., 1.]);
        }
    }
}

#[test]
fn a_kink_gets_the_normalised_sum_of_the_face_normals() {
    // Two triangles folded at 90° along the edge 1–2: normals +z and +x.
    let pts = [[0., 0., 0.], [0., 1., 0.], [-1., 0., 0.], [0., 0., 1.]];
    let t = GeometryKind::Triangle3D3;
    let mut mp = model(&pts, &[(t, &[1, 2, 3]), (t, &[1, 2, 4])]);
    compute_unit_normals(&mut mp, None, NormalsMode::Once).unwrap();
    assert_close(&mp.condition_normals()[0], [0., 0., 1.]);
    assert_close(&mp.condition_normals()[1], [1., 0., 0.]);
    let s = 0.5f64.sqrt();
    assert_close(&nodal(&mp)[0], [s, 0., s]);
    assert_close(&nodal(&mp)[1], [s, 0., s]);
    assert_close(&nodal(&mp)[2], [0., 0., 1.]);
    assert_close(&nodal(&mp)[3], [1., 0., 0.]);
}

#[test]
fn lines_in_2d_point_to_the_right_of_their_direction() {
    let pts = [[0., 0., 0.], [1., 0., 0.]];
    let mut mp = model(&pts, &[(GeometryKind::Line2D2, &[1, 2])]);
    compute_unit_normals(&mut mp, None, NormalsMode::Kratos).unwrap();
    assert_close(&mp.condition_normals()[0], [0., -1., 0.]);
    assert_close(&nodal(&mp)[1], [0., -1., 0.]);
}

#[test]
fn degenerate_faces_are_errors_not_nan() {
    let pts = [[0., 0., 0.], [1., 0., 0.], [2., 0., 0.]];
    let mut mp = model(&pts, &[(GeometryKind::Triangle3D3, &[1, 2, 3])]);
    let e = compute_unit_normals(&mut mp, None, NormalsMode::Kratos).unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::Geometry {
            entity: EntityKind::Condition,
            id: 1,
            ..
        }
    ));
}

#[test]
fn opposite_faces_cancel_into_an_error() {
    let pts = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]];
    let t = GeometryKind::Triangle3D3;
    let mut mp = model(&pts, &[(t, &[1, 2, 3]), (t, &[1, 3, 2])]);
    let e = compute_unit_normals(&mut mp, None, NormalsMode::Once).unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::Geometry {
            entity: EntityKind::Node,
            ..
        }
    ));
}

/// Two triangles, the first (in the z = 0 plane) alone in the part "first".
fn two_triangles_first_in_part() -> (ModelPart, PartIdx) {
    let pts = [
        [0., 0., 0.],
        [1., 0., 0.],
        [0., 1., 0.],
        [5., 0., 0.],
        [6., 0., 0.],
        [5., 0., 1.],
    ];
    let t = GeometryKind::Triangle3D3;
    let mut mp = model(&pts, &[(t, &[1, 2, 3]), (t, &[4, 5, 6])]);
    let part = mp.create_part("first").unwrap();
    mp.add_conditions_to_part(part, &[ConditionIdx(0)]);
    (mp, part)
}

#[test]
fn only_the_given_part_is_computed() {
    let (mut mp, part) = two_triangles_first_in_part();
    compute_unit_normals(&mut mp, Some(part), NormalsMode::Kratos).unwrap();
    assert_close(&mp.condition_normals()[0], [0., 0., 1.]);
    assert_close(&mp.condition_normals()[1], [0., 0., 0.]);
    assert_close(&nodal(&mp)[4], [0., 0., 0.]);
}

/// A bumpy `n`×`n`-node grid of triangles and quadrilaterals, node ids scrambled so that a
/// face's nodes fall into different blocks of the blocked sums.
fn bumpy_grid(n: usize) -> ModelPart {
    let id = |i: usize, j: usize| ((i * n + j) * 37 % (n * n)) as u32 + 1;
    let mut pts = vec![[0.0; 3]; n * n];
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f64 * 0.1, j as f64 * 0.1);
            pts[id(i, j) as usize - 1] = [x, y, (3.0 * x).sin() * (2.0 * y).cos() * 0.05];
        }
    }
    let mut faces: Vec<(GeometryKind, Vec<u32>)> = Vec::new();
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 3 == 0 {
                faces.push((GeometryKind::Quadrilateral3D4, vec![a, b, c, d]));
            } else {
                faces.push((GeometryKind::Triangle3D3, vec![a, b, c]));
                faces.push((GeometryKind::Triangle3D3, vec![a, c, d]));
            }
        }
    }
    let refs: Vec<(GeometryKind, &[u32])> = faces.iter().map(|(k, v)| (*k, &v[..])).collect();
    model(&pts, &refs)
}

fn all_conditions(mp: &ModelPart) -> Vec<ConditionIdx> {
    (0..mp.conditions().len() as u32)
        .map(ConditionIdx)
        .collect()
}

#[test]
fn nodal_sums_are_the_serial_sums_for_any_thread_count() {
    // More nodes than one block of the blocked sums.
    let n = 101;
    let mp = bumpy_grid(n);
    let table = face_unit_normals(&mp, &all_conditions(&mp)).unwrap();
    let mut serial = (vec![Vector::zeros(); n * n], vec![0u32; n * n]);
    for face in table.iter() {
        for (k, node) in mp
            .conditions()
            .nodes(face.condition.index())
            .iter()
            .enumerate()
        {
            serial.0[node.index()] += face.node(k);
            serial.1[node.index()] += 1;
        }
    }
    assert_eq!(table.nodal_sums_serial(&mp), serial);
    // Enough contributions for the blocks' parallel pass (the wanted sums below take the
    // serial one).
    assert!(serial.1.iter().sum::<u32>() as usize >= SERIAL_CONTRIBUTIONS);
    for threads in [1, 2, 3, 7] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let sums = pool.install(|| table.nodal_sums(&mp));
        assert_eq!(sums, serial, "{threads} threads");
        // Many chunks of faces, of sizes that do not divide the face count.
        for faces in [1, 7, 1000] {
            let mut sums = (vec![Vector::zeros(); n * n], vec![0u32; n * n]);
            pool.install(|| table.nodal_sums_in_chunks(&mp, faces, (&mut sums.0, &mut sums.1)));
            assert_eq!(sums, serial, "{threads} threads, chunks of {faces} faces");
        }
    }
}

#[test]
fn wanted_nodal_sums_are_the_serial_sums_in_any_chunks() {
    // Two node blocks, many chunks of faces; the wanted nodes' sums are the serial ones (in
    // face order), every other node keeps its value.
    let n = 101;
    let mp = bumpy_grid(n);
    let table = face_unit_normals(&mp, &all_conditions(&mp)).unwrap();
    let faces: Vec<FaceNormalsRef<'_>> = table.iter().collect();
    // Each face's nodal normals, flat: face f's k-th at `first[f] + k`.
    let mut first = Vec::new();
    let mut normals = Vec::new();
    for face in &faces {
        first.push(normals.len());
        let n_nodes = mp.conditions().nodes(face.condition.index()).len();
        normals.extend((0..n_nodes).map(|k| face.node(k)));
    }
    let n_nodes = n * n;
    assert!(n_nodes > 1 << NODE_BLOCK_BITS);
    let wanted: Vec<bool> = (0..n_nodes).map(|i| i % 3 == 1 || i % 1000 == 0).collect();
    let mut serial = (
        vec![Vector::new(7.0, -1.0, 0.5); n_nodes],
        vec![0u32; n_nodes],
    );
    for (f, face) in faces.iter().enumerate() {
        let nodes = mp.conditions().nodes(face.condition.index());
        for (k, node) in nodes.iter().enumerate() {
            let i = node.index();
            if wanted[i] {
                if serial.1[i] == 0 {
                    serial.0[i] = Vector::zeros();
                }
                serial.0[i] += normals[first[f] + k];
                serial.1[i] += 1;
            }
        }
    }
    assert!(serial.1.iter().filter(|&&c| c > 0).count() > n_nodes / 3);
    assert!((serial.1.iter().sum::<u32>() as usize) < SERIAL_CONTRIBUTIONS);
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for per_chunk in [1, 7, 1000, faces.len()] {
            let mut sums = (
                vec![Vector::new(7.0, -1.0, 0.5); n_nodes],
                vec![0u32; n_nodes],
            );
            pool.install(|| {
                sums_by_node_blocks(
                    (&mut sums.0, &mut sums.1),
                    (faces.len(), Some(&wanted)),
                    |f| mp.conditions().nodes(faces[f].condition.index()),
                    (|f, k| (first[f] + k) as u32, |r| normals[r as usize]),
                    per_chunk,
                )
            });
            assert_eq!(
                sums, serial,
                "{threads} threads, chunks of {per_chunk} faces"
            );
        }
    }
}

#[test]
fn a_subset_of_the_table_is_the_table_of_the_subset() {
    let mut mp = bumpy_grid(12);
    // A 2D solid (not a face) among the conditions: skipped by both.
    mp.add_condition(
        ConditionId(10_000),
        GeometryKind::Triangle2D3,
        "",
        &[NodeId(1), NodeId(2), NodeId(3)],
        PropertiesId(0),
    )
    .unwrap();
    let all = all_conditions(&mp);
    let table = face_unit_normals(&mp, &all).unwrap();
    // compute_unit_normals returns the table of its part's conditions (and writes their
    // centre normals as the condition normals, where the kept table reads them).
    let computed = compute_unit_normals(&mut mp, None, NormalsMode::Kratos).unwrap();
    assert_eq!(computed, table);
    let kept = computed.keep();
    assert_eq!(kept.subset(&mp, &all), Some(table.clone()));
    // Every third condition, backwards (quadrilaterals, with their nodal normals, and
    // triangles), and the solid.
    let some: Vec<ConditionIdx> = all.iter().rev().step_by(3).copied().collect();
    assert!(some.contains(all.last().unwrap()));
    let fresh = face_unit_normals(&mp, &some).unwrap();
    assert!(fresh.len() > 10 && fresh.len() < table.len());
    assert_eq!(kept.subset(&mp, &some), Some(fresh.clone()));
    assert_eq!(
        kept.positions(&mp)
            .and_then(|p| Some([p.subset(&mp, &all)?, p.subset(&mp, &some)?])),
        Some([table.clone(), fresh.clone()])
    );
    assert_eq!(kept.subset(&mp, &[]), Some(FaceNormals::default()));
    // The nodal sums of a list, from the positions, are those of its table; nodes of no
    // face keep what they had.
    let positions = kept.positions(&mp).unwrap();
    let n_nodes = mp.nodes().len();
    for list in [&all, &some] {
        let expected = face_unit_normals(&mp, list).unwrap().nodal_sums(&mp);
        let mut sums = vec![Vector::new(7.0, -1.0, 0.5); n_nodes];
        let mut count = vec![0u32; n_nodes];
        assert!(positions.nodal_sums_into(&mp, (list, None), (&mut sums, &mut count)));
        assert_eq!(count, expected.1);
        for i in 0..n_nodes {
            let want = if count[i] > 0 {
                expected.0[i]
            } else {
                Vector::new(7.0, -1.0, 0.5)
            };
            assert_eq!(sums[i], want, "node {i}");
        }
        assert_eq!(count.contains(&0), list.len() < all.len());
    }
    // Only the wanted nodes: theirs as from the whole list, every other untouched.
    let wanted: Vec<bool> = (0..n_nodes).map(|i| i % 3 == 1).collect();
    let expected = face_unit_normals(&mp, &some).unwrap().nodal_sums(&mp);
    let mut sums = vec![Vector::new(7.0, -1.0, 0.5); n_nodes];
    let mut count = vec![0u32; n_nodes];
    assert!(positions.nodal_sums_into(&mp, (&some, Some(&wanted)), (&mut sums, &mut count)));
    for i in 0..n_nodes {
        let k = if wanted[i] { expected.1[i] } else { 0 };
        assert_eq!(count[i], k, "node {i}");
        let want = if k > 0 {
            expected.0[i]
        } else {
            Vector::new(7.0, -1.0, 0.5)
        };
        assert_eq!(sums[i], want, "node {i}");
    }
    assert!((0..n_nodes).any(|i| wanted[i] && count[i] > 0));
    // A face the kept table does not have.
    let part = face_unit_normals(&mp, &some).unwrap().keep();
    assert_eq!(part.subset(&mp, &all), None);
    assert_eq!(part.subset(&mp, &some), Some(fresh));
    let mut untouched = (vec![Vector::zeros(); n_nodes], vec![0u32; n_nodes]);
    let part_positions = part.positions(&mp).unwrap();
    assert!(!part_positions.nodal_sums_into(
        &mp,
        (&all, None),
        (&mut untouched.0, &mut untouched.1)
    ));
    assert!(untouched.1.iter().all(|&k| k == 0));
    // Condition normals that are no longer the kept centre normals (one last bit) or that
    // the model no longer has.
    let c = some[1];
    let n = mp.condition_normals()[c.index()];
    mp.condition_normals_mut()[c.index()].x = f64::from_bits(n.x.to_bits() ^ 1);
    assert_eq!(kept.subset(&mp, &all), None);
    mp.condition_normals_mut()[c.index()] = n;
    assert_eq!(kept.subset(&mp, &all), Some(table.clone()));
    // Two faces turned over (signs that cancel in a weak hash).
    let before = mp.condition_normals().to_vec();
    for c in [some[1], some[2]] {
        mp.condition_normals_mut()[c.index()] *= -1.0;
    }
    assert_eq!(kept.subset(&mp, &all), None);
    mp.condition_normals_mut().copy_from_slice(&before);
    assert_eq!(kept.subset(&mp, &all), Some(table));
    assert_eq!(kept.subset(&model(&[], &[]), &[]), None);
}

/// The geometry stamp changes with every change of the coordinates or of the conditions'
/// nodes (and only with those), differs between models, and is shared by a clone until one
/// of them changes.
#[test]
fn the_geometry_stamp_follows_coordinates_and_condition_nodes() {
    let mut mp = bumpy_grid(5);
    let s0 = mp.geometry_stamp();
    assert_ne!(s0, GeometryStamp::default());
    assert_ne!(s0, bumpy_grid(5).geometry_stamp());
    // What does not touch the geometry.
    mp.nodes_mut().flags_mut()[0].set(Flag::SLAVE, true);
    mp.conditions_mut().flags_mut()[0].set(Flag::SLAVE, true);
    mp.nodal_data_mut().add_vector(VectorVar::Normal);
    mp.condition_normals_mut()[0] = Vector::x();
    let part = mp.create_part("Part").unwrap();
    mp.add_conditions_to_part(part, &[ConditionIdx(0)]);
    assert_eq!(mp.geometry_stamp(), s0);
    let clone = mp.clone();
    assert_eq!(clone.geometry_stamp(), s0);
    // What does (even without changing a value).
    let changes: [fn(&mut ModelPart); 5] = [
        |m| {
            let _ = m.nodes_mut().coordinates_mut();
        },
        |m| m.conditions_mut().reverse_nodes(0),
        |m| assert!(m.conditions_mut().permute_nodes(0, &[1, 2, 3, 0])),
        |m| {
            m.add_node(NodeId(9_999), Point::new(9.0, 9.0, 9.0))
                .unwrap();
        },
        |m| {
            let nodes = [NodeId(1), NodeId(2), NodeId(3)];
            m.add_condition(
                ConditionId(9_999),
                GeometryKind::Triangle3D3,
                "",
                &nodes,
                PropertiesId(0),
            )
            .unwrap();
        },
    ];
    let mut seen = vec![s0];
    for change in changes {
        change(&mut mp);
        let s = mp.geometry_stamp();
        assert!(!seen.contains(&s), "{s:?}");
        seen.push(s);
    }
    assert_eq!(clone.geometry_stamp(), s0);
}

/// A kept table serves a later computation of these faces (or some of them) while the
/// geometry and the condition normals are the ones it was computed on: the same table,
/// condition normals and nodal NORMALs as a computation from scratch; after a change of the
/// coordinates, of a condition's nodes or of the condition normals it is not used.
#[test]
fn a_current_kept_table_gives_what_computing_gives() {
    let mut mp = bumpy_grid(12);
    let part = mp.create_part("Part").unwrap();
    let some: Vec<ConditionIdx> = all_conditions(&mp).into_iter().step_by(2).collect();
    mp.add_conditions_to_part(part, &some);
    let kept = compute_unit_normals(&mut mp, None, NormalsMode::Kratos)
        .unwrap()
        .keep();
    let fresh_of = |mp: &ModelPart| {
        let mut again = mp.clone();
        let table = compute_unit_normals(&mut again, Some(part), NormalsMode::Kratos).unwrap();
        (table, again)
    };
    let same = |a: &ModelPart, b: &ModelPart| {
        let bits = |v: &[Vector]| -> Vec<[u64; 3]> {
            v.iter()
                .map(|n| [n.x.to_bits(), n.y.to_bits(), n.z.to_bits()])
                .collect()
        };
        bits(nodal(a)) == bits(nodal(b))
            && bits(a.condition_normals()) == bits(b.condition_normals())
    };
    // Flags and nodal data changed, a condition added: the geometry of these faces is not.
    mp.nodes_mut().flags_mut()[3].set(Flag::SLAVE, true);
    let (expected, expected_model) = fresh_of(&mp);
    assert!(kept.current_subset(&mp, &some).is_some());
    let mut reused = mp.clone();
    let table =
        compute_unit_normals_reusing(&mut reused, Some(part), NormalsMode::Kratos, Some(&kept))
            .unwrap();
    assert_eq!(table, expected);
    assert!(same(&reused, &expected_model));
    // Without building the table (`from_kept`), for a part or all of its own faces: the
    // model is the computed one (and the kept table stays current).
    let from_kept = |mp: &ModelPart, part: PartIdx| {
        let mut m = mp.clone();
        let used = compute_unit_normals_from_kept(&mut m, Some(part), NormalsMode::Kratos, &kept);
        (used.unwrap(), m)
    };
    let (used, m) = from_kept(&mp, part);
    assert!(used && same(&m, &expected_model));
    assert!(kept.current_subset(&m, &some).is_some());
    let everything = mp.create_part("Everything").unwrap();
    mp.add_conditions_to_part(everything, &all_conditions(&mp));
    let fresh_of_all = |mp: &ModelPart| {
        let mut again = mp.clone();
        compute_unit_normals(&mut again, Some(everything), NormalsMode::Kratos).unwrap();
        again
    };
    let (used, m) = from_kept(&mp, everything);
    assert!(used && same(&m, &fresh_of_all(&mp)));
    // NORMAL written since the table's own computation: computed again, not taken as it is.
    let mut touched = mp.clone();
    let normal = touched.nodal_data_mut().vector_mut(VectorVar::Normal, 0);
    normal.unwrap()[0] = Vector::new(0.0, 0.0, 7.0);
    let (used, m) = from_kept(&touched, everything);
    assert!(used && same(&m, &fresh_of_all(&touched)));
    // A table without some of the part's faces is not used.
    let half = compute_unit_normals(&mut mp.clone(), Some(part), NormalsMode::Kratos)
        .unwrap()
        .keep();
    let mut m = mp.clone();
    let used = compute_unit_normals_from_kept(&mut m, Some(everything), NormalsMode::Kratos, &half);
    assert!(!used.unwrap() && same(&m, &mp));
    // After a change of the coordinates (a node moved, the table's values would be wrong),
    // of a condition's nodes, or of the condition normals (one flipped, two exchanged), it
    // is not used, and the results are those of a computation.
    let moves: [fn(&mut ModelPart); 4] = [
        |m| m.nodes_mut().coordinates_mut()[5].z += 0.01,
        |m| m.conditions_mut().reverse_nodes(2),
        |m| m.condition_normals_mut()[4] *= -1.0,
        |m| m.condition_normals_mut().swap(0, 2),
    ];
    for change in moves {
        let mut moved = mp.clone();
        change(&mut moved);
        assert!(kept.current_subset(&moved, &some).is_none());
        let (expected, expected_model) = fresh_of(&moved);
        let table =
            compute_unit_normals_reusing(&mut moved, Some(part), NormalsMode::Kratos, Some(&kept))
                .unwrap();
        assert_eq!(table, expected);
        assert!(same(&moved, &expected_model));
        // Nor without building the table: the model is left as it was.
        let mut changed = mp.clone();
        change(&mut changed);
        let (used, m) = from_kept(&changed, everything);
        assert!(!used && same(&m, &changed));
    }
}

/// `restore_all` puts the whole kept column back: what `restore` writes where `NORMAL`
/// changed only on nodes of the part's conditions since the snapshot (and the stamp moves).
#[test]
fn restoring_the_whole_snapshot_is_restoring_the_part() {
    let (mut mp, part) = two_triangles_first_in_part();
    compute_unit_normals(&mut mp, None, NormalsMode::Kratos).unwrap();
    let snapshot = UnitNormalsSnapshot::take(&mp, Some(part)).unwrap();
    // Changed on nodes of the part's condition only (nodes 0 and 2).
    let col = mp
        .nodal_data_mut()
        .vector_mut(VectorVar::Normal, 0)
        .unwrap();
    col[0] = Vector::new(0.3, 0.4, 0.5);
    col[2] = Vector::zeros();
    let (mut by_part, mut whole) = (mp.clone(), mp);
    snapshot.clone().restore(&mut by_part);
    let stamp = whole.nodal_data().vector_stamp(VectorVar::Normal);
    snapshot.restore_all(&mut whole);
    assert_eq!(nodal(&whole), nodal(&by_part));
    assert_close(&nodal(&whole)[0], [0., 0., 1.]);
    assert_ne!(whole.nodal_data().vector_stamp(VectorVar::Normal), stamp);
}
