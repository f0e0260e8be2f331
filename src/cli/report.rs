//! `csm report`: error against run time for every search strategy, measured against the
//! exhaustive ground truth ([`csm_eval::GroundTruth`]); the sweep is `csm_eval`'s
//! ([`csm_eval::run_report`]), written here as a Markdown table and an SVG chart with the
//! Pareto front (`docs/report.md` explains the metrics).

use std::fmt::Write as _;

use csm_chart as chart;
use csm_eval::Score;
pub use csm_eval::{Report, ReportOptions, Row, Strategy, TruthSummary, run_report, strategies};
use csm_search::{Compatibility, SearchTreeType};

/// The texts of a [`Report`]: the Markdown table, the one-line summary, the SVG chart.
pub trait ReportText {
    /// The report as Markdown: the scene, the ground truths, the notes, then one table row per
    /// strategy (search times in milliseconds; `*` marks the Pareto front of the row's
    /// activation rule).
    fn to_markdown(&self) -> String;
    /// A short summary: the strategy count and the Pareto front of each activation rule.
    fn summary(&self) -> String;
    /// The SVG chart: search time (log scale) on x, missed true pairs (%) on y, one marker per
    /// strategy, the Pareto front of each activation rule as a polyline, and a legend; equal
    /// reports give equal files.
    fn to_svg(&self) -> String;
}

fn fmt_gap(e: Option<f64>) -> String {
    e.map_or_else(
        || "—".to_owned(),
        |e| {
            if e == 0.0 {
                "0".to_owned()
            } else {
                format!("{e:.2e}")
            }
        },
    )
}

impl ReportText for Report {
    /// The report as Markdown: the scene, the ground truths, the notes, then one table row
    /// per strategy (search times in milliseconds; `*` marks the Pareto front of the row's activation rule).
    fn to_markdown(&self) -> String {
        let mut s = String::new();
        // Writing to a String cannot fail.
        let _ = writeln!(s, "# csm report: {}\n", self.scene);
        let _ = writeln!(
            s,
            "Pair key {}: {} slave faces, {} master faces. Metrics: `docs/report.md`.\n",
            self.key, self.n_slaves, self.n_masters
        );
        match self.sample {
            Some(sample) => {
                let size = self.truths.first().map_or(0, |t| t.truth.pairs.len());
                let _ = writeln!(
                    s,
                    "**Sampled:** more than the limit of faces per side, so the ground truth is \
                     computed for a seeded random sample of {} slave faces (seed {}) against \
                     all masters; every count below is over the sample and its nodes.\n",
                    size, sample.seed
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "The ground truth is exhaustive (every slave face against every master).\n"
                );
            }
        }
        for t in &self.truths {
            let truth = &t.truth;
            let active = truth.nodes.values().filter(|n| n.active).count();
            let _ = writeln!(
                s,
                "- Ground truth, {} activation (DISTANCE_THRESHOLD {:.3e}): {} true pairs over \
                 {} slave faces, {} active of {} nodes; {} segmentations after the prefilter.",
                if truth.simple_search {
                    "Simple"
                } else {
                    "Advanced"
                },
                truth.distance_threshold,
                truth.n_pairs(),
                truth.pairs.len(),
                active,
                truth.nodes.len(),
                truth.overlap_tests
            );
        }
        let _ = writeln!(
            s,
            "- `bounding_box_factor` is swept in `robust` mode only: in `kratos` mode Kratos' \
             Python layer drops `octree_search_parameters`, so the default is in force (set \
             it through `cpp_search_parameters` to reach Kratos' C++ process).\n"
        );
        let _ = writeln!(
            s,
            "| type_search | activation | mode | search_factor | bbf | missed | missed % | \
             spurious cand. | extra pairs | wrong ACTIVE | max gap error | unmapped | search ms \
             | Pareto |"
        );
        let _ = writeln!(
            s,
            "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:-:|"
        );
        for r in &self.rows {
            let st = &r.strategy;
            let bbf = if st.uses_bounding_box_factor() {
                format!("{}", st.bounding_box_factor)
            } else {
                "—".to_owned()
            };
            let head = format!(
                "| {} | {} | {} | {} | {} ",
                st.type_search.name(),
                st.activation(),
                st.compatibility.name(),
                st.search_factor,
                bbf
            );
            match &r.score {
                Ok(sc) => {
                    let _ = writeln!(
                        s,
                        "{head}| {} | {:.2} | {} | {} | {} | {} | {} | {:.1} | {} |",
                        sc.missed,
                        sc.missed_percent(),
                        sc.spurious_candidates,
                        sc.extra_pairs,
                        sc.wrong_active,
                        fmt_gap(sc.max_gap_error),
                        sc.unmapped,
                        r.search_s * 1e3,
                        if r.pareto { "*" } else { "" }
                    );
                }
                Err(e) => {
                    let e = e.replace('|', "/");
                    let _ = writeln!(s, "{head}| failed: {e} | | | | | | | | |");
                }
            }
        }
        s
    }

    /// A short summary: the strategy count and the Pareto front of each activation rule.
    fn summary(&self) -> String {
        let mut s = String::new();
        let failed = self.rows.iter().filter(|r| r.score.is_err()).count();
        let _ = writeln!(
            s,
            "{} strategies ({} failed); Pareto fronts (missed true pairs vs search time):",
            self.rows.len(),
            failed
        );
        for simple in [false, true] {
            let front: Vec<String> = self
                .front(simple)
                .iter()
                .map(|r| {
                    let st = &r.strategy;
                    format!(
                        "{} {} sf {}{} ({:.2}% missed, {:.1} ms)",
                        st.type_search.name(),
                        st.compatibility.name(),
                        st.search_factor,
                        if st.uses_bounding_box_factor() {
                            format!(" bbf {}", st.bounding_box_factor)
                        } else {
                            String::new()
                        },
                        r.score.as_ref().map_or(0.0, Score::missed_percent),
                        r.search_s * 1e3
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "  {}: {}",
                if simple { "simple" } else { "advanced" },
                front.join("; ")
            );
        }
        s
    }

    /// The SVG chart: search time (log scale) on x, missed true pairs (%) on y, one marker per
    /// strategy (colour: `type_search`; filled: `robust`, hollow: `kratos`; square: Advanced
    /// activation, circle: Simple), the Pareto front of each rule as a polyline (Advanced solid,
    /// Simple dashed), and a legend. Coordinates
    /// have one decimal, so equal reports give equal files.
    fn to_svg(&self) -> String {
        const W: f64 = 760.0;
        const H: f64 = 460.0;
        const LEFT: f64 = 70.0;
        const RIGHT: f64 = 200.0;
        const TOP: f64 = 40.0;
        const BOTTOM: f64 = 60.0;
        let ok: Vec<(&Row, f64)> = self
            .rows
            .iter()
            .filter_map(|r| r.score.as_ref().ok().map(|s| (r, s.missed_percent())))
            .collect();
        let ms = |r: &Row| (r.search_s * 1e3).max(1e-3);
        let (mut lo, mut hi) = ok.iter().fold((f64::INFINITY, 0.0_f64), |(l, h), (r, _)| {
            (l.min(ms(r)), h.max(ms(r)))
        });
        if !lo.is_finite() {
            (lo, hi) = (1.0, 10.0);
        }
        // A log axis a little wider than the data, ticks at 1, 2, 3, 5 × 10^k.
        let (x0, mut x1) = (lo.log10() - 0.05, hi.log10() + 0.05);
        if x1 - x0 < 0.3 {
            x1 = x0 + 0.3;
        }
        let ymax_data = ok.iter().map(|(_, m)| *m).fold(0.0, f64::max);
        let ymax = nice_ceiling(ymax_data);
        let px = |t: f64| LEFT + (t.log10() - x0) / (x1 - x0) * (W - LEFT - RIGHT);
        let py = |m: f64| H - BOTTOM - m / ymax * (H - TOP - BOTTOM);
        let mut s = String::new();
        s.push_str(&chart::open(W, H));
        let _ = writeln!(
            s,
            "{}",
            chart::title(
                W / 2.0,
                22.0,
                &format!("{}: missed true pairs vs search time", self.scene)
            )
        );
        // Axes and ticks.
        let (bx, by) = (H - BOTTOM, W - RIGHT);
        let _ = writeln!(
            s,
            r#"<path d="M{LEFT:.1} {TOP:.1} V{bx:.1} H{by:.1}" fill="none" stroke="black"/>"#
        );
        for e in (x0.floor() as i32)..=(x1.ceil() as i32) {
            for m in [1.0, 2.0, 3.0, 5.0] {
                let v = m * 10f64.powi(e);
                let lv = v.log10();
                if lv < x0 || lv > x1 {
                    continue;
                }
                let x = px(v);
                let _ = writeln!(
                    s,
                    "{}{}",
                    chart::line(x, bx, x, bx + 5.0, "black", ""),
                    chart::text(x, bx + 18.0, MIDDLE, &fmt_ms(v))
                );
            }
        }
        for k in 0..=4 {
            let m = ymax * f64::from(k) / 4.0;
            let y = py(m);
            let _ = writeln!(
                s,
                "{}{}",
                chart::line(LEFT - 5.0, y, LEFT, y, "black", ""),
                chart::text(LEFT - 8.0, y + 4.0, r#" text-anchor="end""#, &trim_float(m))
            );
        }
        let _ = writeln!(
            s,
            "{}",
            chart::text(
                (LEFT + W - RIGHT) / 2.0,
                H - 15.0,
                MIDDLE,
                "search step time (ms, log scale)"
            )
        );
        let _ = writeln!(
            s,
            r#"<text x="18" y="{:.1}" text-anchor="middle" transform="rotate(-90 18 {:.1})">missed true pairs (%)</text>"#,
            (TOP + H - BOTTOM) / 2.0,
            (TOP + H - BOTTOM) / 2.0
        );
        // The Pareto fronts: Advanced solid, Simple dashed.
        for simple in [false, true] {
            let front: Vec<(f64, f64)> = self
                .front(simple)
                .iter()
                .map(|r| {
                    let m = r.score.as_ref().map_or(0.0, Score::missed_percent);
                    (px(ms(r)), py(m))
                })
                .collect();
            if !front.is_empty() {
                let dash = if simple {
                    r#" stroke-dasharray="4 3""#
                } else {
                    ""
                };
                let _ = writeln!(s, "{}", chart::polyline(&front, "black", dash));
            }
        }
        // The markers.
        for (r, m) in &ok {
            let colour = colour_of(r.strategy.type_search);
            let fill = if r.strategy.compatibility == Compatibility::Robust {
                colour
            } else {
                "none"
            };
            let (x, y) = (px(ms(r)), py(*m));
            let title = format!(
                "{} {} {} sf {} bbf {}",
                r.strategy.type_search.name(),
                r.strategy.activation(),
                r.strategy.compatibility.name(),
                r.strategy.search_factor,
                r.strategy.bounding_box_factor
            );
            if r.strategy.simple_search {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{x:.1}" cy="{y:.1}" r="4.5" fill="{fill}" stroke="{colour}" stroke-width="1.5"><title>{title}</title></circle>"#
                );
            } else {
                let _ = writeln!(
                    s,
                    r#"<rect x="{:.1}" y="{:.1}" width="8" height="8" fill="{fill}" stroke="{colour}" stroke-width="1.5"><title>{title}</title></rect>"#,
                    x - 4.0,
                    y - 4.0
                );
            }
        }
        // The legend.
        let lx = W - RIGHT + 20.0;
        let mut ly = TOP + 5.0;
        let mut types: Vec<SearchTreeType> = Vec::new();
        for r in &self.rows {
            if !types.contains(&r.strategy.type_search) {
                types.push(r.strategy.type_search);
            }
        }
        for t in types {
            let _ = writeln!(
                s,
                r#"<circle cx="{lx:.1}" cy="{ly:.1}" r="4.5" fill="{c}" stroke="{c}"/>{}"#,
                chart::text(lx + 12.0, ly + 4.0, "", t.name()),
                c = colour_of(t)
            );
            ly += 18.0;
        }
        ly += 8.0;
        for (shape, label) in [
            (
                format!(r#"<circle cx="{lx:.1}" cy="{ly:.1}" r="4.5" fill="gray" stroke="gray"/>"#),
                "robust (filled)",
            ),
            (
                format!(
                    r#"<circle cx="{lx:.1}" cy="{:.1}" r="4.5" fill="none" stroke="gray" stroke-width="1.5"/>"#,
                    ly + 18.0
                ),
                "kratos (hollow)",
            ),
            (
                format!(
                    r#"<circle cx="{lx:.1}" cy="{:.1}" r="4.5" fill="none" stroke="black"/>"#,
                    ly + 36.0
                ),
                "Simple activation",
            ),
            (
                format!(
                    r#"<rect x="{:.1}" y="{:.1}" width="8" height="8" fill="none" stroke="black"/>"#,
                    lx - 4.0,
                    ly + 50.0
                ),
                "Advanced activation",
            ),
        ] {
            let _ = writeln!(s, "{shape}{}", chart::text(lx + 12.0, ly + 4.0, "", label));
            ly += 18.0;
        }
        for (dash, label) in [
            ("", "Pareto front, Advanced"),
            (r#" stroke-dasharray="4 3""#, "Pareto front, Simple"),
        ] {
            let _ = writeln!(
                s,
                "{}{}",
                chart::line(lx - 6.0, ly, lx + 6.0, ly, "black", dash),
                chart::text(lx + 12.0, ly + 4.0, "", label)
            );
            ly += 18.0;
        }
        s.push_str(chart::close());
        s
    }
}

/// The attribute of centred text.
const MIDDLE: &str = r#" text-anchor="middle""#;

fn colour_of(t: SearchTreeType) -> &'static str {
    match t {
        SearchTreeType::KdtreeInRadius => "#1f77b4",
        SearchTreeType::KdtreeInBox => "#ff7f0e",
        SearchTreeType::KdtreeInRadiusWithObb => "#2ca02c",
        SearchTreeType::KdtreeInBoxWithObb => "#d62728",
        SearchTreeType::OctreeWithObb => "#9467bd",
        SearchTreeType::Kdop => "#8c564b",
    }
}

/// 1, 2, 5 × 10^k at or above `v` (1 for 0).
fn nice_ceiling(v: f64) -> f64 {
    if v <= 0.0 || !v.is_finite() {
        return 1.0;
    }
    let e = v.log10().floor();
    let base = 10f64.powf(e);
    for m in [1.0, 2.0, 5.0, 10.0] {
        if m * base >= v * (1.0 - 1e-12) {
            return m * base;
        }
    }
    10.0 * base
}

fn fmt_ms(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.0}")
    } else {
        trim_float(v)
    }
}

fn trim_float(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_owned()
}

#[cfg(test)]
mod tests;
