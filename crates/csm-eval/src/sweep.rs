//! The sweep of `csm report`: every strategy (`type_search` × Simple/Advanced ×
//! `search_factor` × `bounding_box_factor` × kratos/robust) run on one scene and scored against
//! its exhaustive ground truth, and the Pareto front of error against run time. Rendering (the
//! Markdown table, the SVG chart) belongs to the CLI.

use std::time::Instant;

use csm_model::{Flag, ModelPart};
use csm_search::{Compatibility, ContactSearch, SearchSetup, SearchTreeType};

use crate::{GroundTruth, Sample, Score};

/// The sweep and the sampling of a report.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportOptions {
    /// The `type_search` values compared.
    pub type_searches: Vec<SearchTreeType>,
    /// The `search_factor` values (every strategy, both modes).
    pub search_factors: Vec<f64>,
    /// The `bounding_box_factor` values of the OBB and 18-DOP variants, swept in `robust` mode
    /// at the setup's `search_factor` (Kratos' Python layer drops the key in `kratos` mode).
    pub bounding_box_factors: Vec<f64>,
    /// Above this many faces on either side the ground truth is computed for a sample.
    pub sample_limit: usize,
    /// The size and seed of that sample.
    pub sample: Sample,
}

impl Default for ReportOptions {
    /// Every `type_search`; `search_factor` 1, 2, 3.5 (the default); `bounding_box_factor`
    /// 0.02, 0.1 (the default), 0.5; a sample of 2,000 slave faces (seed 1) above 20,000
    /// faces per side.
    fn default() -> ReportOptions {
        ReportOptions {
            type_searches: vec![
                SearchTreeType::KdtreeInRadius,
                SearchTreeType::KdtreeInBox,
                SearchTreeType::KdtreeInRadiusWithObb,
                SearchTreeType::KdtreeInBoxWithObb,
                SearchTreeType::OctreeWithObb,
                SearchTreeType::Kdop,
            ],
            search_factors: vec![1.0, 2.0, 3.5],
            bounding_box_factors: vec![0.02, 0.1, 0.5],
            sample_limit: 20_000,
            sample: Sample {
                size: 2_000,
                seed: 1,
            },
        }
    }
}

/// One strategy of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategy {
    /// `type_search`.
    pub type_search: SearchTreeType,
    /// `simple_search` (Simple activation) or Advanced.
    pub simple_search: bool,
    /// `search_factor`.
    pub search_factor: f64,
    /// `octree_search_parameters.bounding_box_factor` in force.
    pub bounding_box_factor: f64,
    /// `compatibility`.
    pub compatibility: Compatibility,
}

impl Strategy {
    /// Whether `bounding_box_factor` matters to it (the OBB and 18-DOP variants).
    pub fn uses_bounding_box_factor(&self) -> bool {
        matches!(
            self.type_search,
            SearchTreeType::KdtreeInRadiusWithObb
                | SearchTreeType::KdtreeInBoxWithObb
                | SearchTreeType::OctreeWithObb
                | SearchTreeType::Kdop
        )
    }

    /// `"simple"` or `"advanced"`.
    pub fn activation(&self) -> &'static str {
        if self.simple_search {
            "simple"
        } else {
            "advanced"
        }
    }
}

/// A strategy's measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The strategy.
    pub strategy: Strategy,
    /// Its result against the ground truth, or why it could not run.
    pub score: Result<Score, String>,
    /// Wall time of its search step (`timings_s.search`), seconds.
    pub search_s: f64,
    /// On the Pareto front of missed pairs against search time among the strategies with the
    /// same activation rule (they share a ground truth).
    pub pareto: bool,
}

/// The ground truth of one activation rule.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthSummary {
    /// The ground truth.
    pub truth: GroundTruth,
    /// Wall time to compute it, seconds.
    pub seconds: f64,
}

/// A report: the scene, the ground truths and one row per strategy.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// What was measured (the mesh file name, or "demo scene").
    pub scene: String,
    /// The pair key reported (the setup's first).
    pub key: u32,
    /// Slave-side and master-side faces of the pair.
    pub n_slaves: usize,
    /// Master-side faces of the pair.
    pub n_masters: usize,
    /// The sample used, if the scene was above the limit.
    pub sample: Option<Sample>,
    /// The ground truth for Simple (`simple_search: true`) and Advanced.
    pub truths: Vec<TruthSummary>,
    /// The strategies, in sweep order.
    pub rows: Vec<Row>,
}

/// The strategies of `options` for a setup whose `search_factor` and `bounding_box_factor`
/// (as parsed in `kratos` mode) are `sf0` and `bbf0`.
pub fn strategies(options: &ReportOptions, sf0: f64, bbf0: f64) -> Vec<Strategy> {
    let mut out = Vec::new();
    for compatibility in [Compatibility::Kratos, Compatibility::Robust] {
        for simple_search in [true, false] {
            for &type_search in &options.type_searches {
                for &search_factor in &options.search_factors {
                    let base = Strategy {
                        type_search,
                        simple_search,
                        search_factor,
                        bounding_box_factor: bbf0,
                        compatibility,
                    };
                    let sweep = compatibility == Compatibility::Robust
                        && base.uses_bounding_box_factor()
                        && search_factor == sf0;
                    if sweep {
                        for &b in &options.bounding_box_factors {
                            out.push(Strategy {
                                bounding_box_factor: b,
                                ..base
                            });
                        }
                    } else {
                        out.push(base);
                    }
                }
            }
        }
    }
    out
}

fn side_counts(model: &ModelPart, key: u32) -> (usize, usize) {
    let Some(sub) = model.find_part(&format!("Contact.ContactSub{key}")) else {
        return (0, 0);
    };
    let flags = model.conditions().flags();
    let conditions = model.part(sub).conditions();
    let slaves = conditions
        .iter()
        .filter(|c| flags[c.index()].is(Flag::SLAVE))
        .count();
    let masters = conditions
        .iter()
        .filter(|c| flags[c.index()].is(Flag::MASTER))
        .count();
    (slaves, masters)
}

/// Runs the report of `setup`'s first pair key on `model` (as read): the ground truth for
/// Simple and Advanced activation, then every strategy of `options` — each initialized once
/// per mode and activation rule, then one timed search step per strategy.
///
/// Errors: a setup without pairs, a scene the ground truth cannot handle (quadratic faces,
/// a setup `initialize` refuses). A strategy that fails is reported in its row.
pub fn run_report(
    model: &ModelPart,
    setup: &SearchSetup,
    scene: &str,
    options: &ReportOptions,
) -> Result<Report, String> {
    let Some((&key, pair)) = setup.pairs.iter().next() else {
        return Err("the setup has no contact pair".to_owned());
    };
    let (sf0, bbf0) = (
        pair.search.search_factor,
        pair.search.octree.bounding_box_factor,
    );
    // The sides' sizes, from an initialized copy.
    let (n_slaves, n_masters) = {
        let mut m = model.clone();
        ContactSearch::initialize(&mut m, setup).map_err(|e| e.to_string())?;
        side_counts(&m, key)
    };
    let sample = (n_slaves.max(n_masters) > options.sample_limit).then_some(options.sample);
    let mut truths = Vec::new();
    for simple in [true, false] {
        let mut s = setup.clone();
        if let Some(p) = s.pairs.get_mut(&key) {
            p.search.simple_search = simple;
        }
        let start = Instant::now();
        let truth = GroundTruth::compute(model, &s, key, sample).map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        tracing::info!(target: "csm",
            "ground truth ({}): {} true pairs over {} slave faces, {} segmentations, {seconds:.3} s",
            if simple { "simple" } else { "advanced" },
            truth.n_pairs(),
            truth.pairs.len(),
            truth.overlap_tests
        );
        truths.push(TruthSummary { truth, seconds });
    }
    let all = strategies(options, sf0, bbf0);
    let mut rows = Vec::with_capacity(all.len());
    for compatibility in [Compatibility::Kratos, Compatibility::Robust] {
        for (t, simple) in [true, false].into_iter().enumerate() {
            let mut s = setup.clone();
            s.compatibility = compatibility;
            if let Some(p) = s.pairs.get_mut(&key) {
                p.search.simple_search = simple;
            }
            let mut base_model = model.clone();
            let base = ContactSearch::initialize(&mut base_model, &s);
            for strategy in all
                .iter()
                .filter(|x| x.compatibility == compatibility && x.simple_search == simple)
            {
                let row = match &base {
                    Ok(base) => run_strategy(&base_model, base, &s, key, strategy, &truths[t]),
                    Err(e) => Row {
                        strategy: *strategy,
                        score: Err(e.to_string()),
                        search_s: 0.0,
                        pareto: false,
                    },
                };
                rows.push(row);
            }
        }
    }
    mark_pareto(&mut rows);
    Ok(Report {
        scene: scene.to_owned(),
        key,
        n_slaves,
        n_masters,
        sample,
        truths,
        rows,
    })
}

fn run_strategy(
    base_model: &ModelPart,
    base: &ContactSearch,
    setup: &SearchSetup,
    key: u32,
    strategy: &Strategy,
    truth: &TruthSummary,
) -> Row {
    let mut row = Row {
        strategy: *strategy,
        score: Err(String::new()),
        search_s: 0.0,
        pareto: false,
    };
    let mut params = setup.pairs[&key].search.clone();
    params.type_search = strategy.type_search;
    params.search_factor = strategy.search_factor;
    params.octree.bounding_box_factor = strategy.bounding_box_factor;
    let mut model = base_model.clone();
    let mut search = base.clone();
    if let Err(e) = search.set_search_parameters(&model, key, &params) {
        row.score = Err(e.to_string());
        return row;
    }
    let start = Instant::now();
    let result = search.step(&mut model);
    row.search_s = start.elapsed().as_secs_f64();
    row.score = result
        .map(|r| truth.truth.score(&r))
        .map_err(|e| e.to_string());
    tracing::debug!(target: "csm",
        "{} {} {} sf {} bbf {}: {:.3} s",
        strategy.type_search.name(),
        strategy.activation(),
        strategy.compatibility.name(),
        strategy.search_factor,
        strategy.bounding_box_factor,
        row.search_s
    );
    row
}

/// Marks the rows no other row beats in both search time and missed pairs (ties in time: the
/// lower error; rows that failed are never on the front), separately for Simple and Advanced
/// activation.
pub fn mark_pareto(rows: &mut [Row]) {
    for simple in [true, false] {
        mark_pareto_of(rows, simple);
    }
}

fn mark_pareto_of(rows: &mut [Row], simple: bool) {
    let mut order: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].score.is_ok() && rows[i].strategy.simple_search == simple)
        .collect();
    let missed = |r: &Row| {
        r.score
            .as_ref()
            .map_or(f64::INFINITY, Score::missed_percent)
    };
    order.sort_by(|&a, &b| {
        rows[a]
            .search_s
            .total_cmp(&rows[b].search_s)
            .then(missed(&rows[a]).total_cmp(&missed(&rows[b])))
    });
    let mut best = f64::INFINITY;
    for i in order {
        let m = missed(&rows[i]);
        if m < best {
            rows[i].pareto = true;
            best = m;
        }
    }
}

impl Report {
    /// The rows on the Pareto front of one activation rule, in time order.
    pub fn front(&self, simple_search: bool) -> Vec<&Row> {
        let mut v: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| r.pareto && r.strategy.simple_search == simple_search)
            .collect();
        v.sort_by(|a, b| a.search_s.total_cmp(&b.search_s));
        v
    }
}
