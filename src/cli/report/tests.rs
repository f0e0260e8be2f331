//! Unit tests of the report's helpers.

use csm_eval::{GroundTruth, mark_pareto};

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
    // An Advanced row beating every Simple one does not remove them from the Simple front.
    let mut fast = row(0.5, 0);
    fast.strategy.simple_search = false;
    rows.push(fast);
    mark_pareto(&mut rows);
    assert!(rows[data.len()].pareto);
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

fn synthetic_report() -> Report {
    let truth = |simple: bool| TruthSummary {
        truth: GroundTruth {
            key: 0,
            simple_search: simple,
            distance_threshold: if simple { 1e24 } else { 0.1 },
            n_slaves: 4,
            sampled: false,
            pairs: [(1, vec![10, 11]), (2, vec![11])].into_iter().collect(),
            nodes: Default::default(),
            overlap_tests: 6,
        },
        seconds: 0.01,
    };
    let mut rows = Vec::new();
    for (i, (t, missed)) in [(2.0, 2), (5.0, 1), (40.0, 0), (3.0, 3)]
        .into_iter()
        .enumerate()
    {
        let mut r = row(t, missed);
        r.strategy.simple_search = i % 2 == 0;
        r.strategy.type_search = SearchTreeType::Kdop;
        if i == 3 {
            r.strategy.compatibility = Compatibility::Robust;
            r.score = Err("a | failure".to_owned());
        }
        rows.push(r);
    }
    mark_pareto(&mut rows);
    Report {
        scene: "synthetic <scene>".to_owned(),
        key: 0,
        n_slaves: 4,
        n_masters: 3,
        sample: None,
        truths: vec![truth(true), truth(false)],
        rows,
    }
}

/// The chart and the table are deterministic text (fixed precision), pinned by snapshots.
#[test]
fn the_chart_and_the_table_of_a_synthetic_report() {
    let report = synthetic_report();
    let svg = report.to_svg();
    assert_eq!(svg, synthetic_report().to_svg());
    assert!(svg.contains("synthetic &lt;scene&gt;"));
    insta::assert_snapshot!("synthetic_svg", svg);
    insta::assert_snapshot!("synthetic_markdown", report.to_markdown());
    insta::assert_snapshot!("synthetic_summary", report.summary());
}
