//! Unit tests of the report's helpers.

use super::*;

#[test]
fn nice_ceilings() {
    assert_eq!(nice_ceiling(0.0), 1.0);
    assert_eq!(nice_ceiling(0.3), 0.5);
    assert_eq!(nice_ceiling(1.0), 1.0);
    assert_eq!(nice_ceiling(3.2), 5.0);
    assert_eq!(nice_ceiling(57.0), 100.0);
}

fn row(ms: f64, missed: usize) -> Row {
    Row {
        strategy: Strategy {
            type_search: SearchTreeType::KdtreeInRadius,
            simple_search: true,
            search_factor: 1.0,
            bounding_box_factor: 0.1,
            compatibility: Compatibility::Kratos,
        },
        score: Ok(Score {
            true_pairs: 100,
            missed,
            ..Score::default()
        }),
        search_s: ms / 1e3,
        pareto: false,
    }
}

/// The front against a brute-force dominance check.
#[test]
fn the_pareto_front_is_the_set_of_non_dominated_rows() {
    let data = [
        (5.0, 10),
        (3.0, 20),
        (8.0, 0),
        (9.0, 0),
        (4.0, 20),
        (2.0, 50),
        (6.0, 5),
        (7.0, 5),
    ];
    let mut rows: Vec<Row> = data.iter().map(|&(t, m)| row(t, m)).collect();
    mark_pareto(&mut rows);
    for (i, &(ti, mi)) in data.iter().enumerate() {
        let dominated = data
            .iter()
            .any(|&(t, m)| (t <= ti && m <= mi) && (t < ti || m < mi));
        assert_eq!(rows[i].pareto, !dominated, "{ti} {mi}");
    }
}

#[test]
fn the_sweep_covers_every_mode_and_sweeps_bbf_in_robust_mode_only() {
    let options = ReportOptions::default();
    let all = strategies(&options, 3.5, 0.1);
    // 6 types × 2 rules × 3 factors × 2 modes, plus 2 more bbf values for the 4 OBB-like types
    // in robust mode at the default factor.
    assert_eq!(all.len(), 6 * 2 * 3 * 2 + 4 * 2 * 2);
    assert!(
        all.iter()
            .filter(|s| s.compatibility == Compatibility::Kratos)
            .all(|s| s.bounding_box_factor == 0.1)
    );
}
