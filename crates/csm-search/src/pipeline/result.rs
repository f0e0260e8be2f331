//! The result of a search step, in the form of RESULT.json (DESIGN.md §3).

use std::collections::BTreeMap;

use serde_json::{Map, Value, json};

/// NORMAL_GAP and ACTIVE of one slave-side node after the search step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeResult {
    /// The gap; `None` where NORMAL_GAP was never written (No/DirectCheck) or holds the
    /// "not mapped" sentinel.
    pub normal_gap: Option<f64>,
    /// The ACTIVE flag (undefined counts as false).
    pub active: bool,
}

/// The pairs, nodes and counters of one search step, ids external and sorted.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SearchResult {
    /// For every pair key, every slave-side condition id with its INDEX_MAP keys (ascending).
    pub pairs: BTreeMap<String, BTreeMap<u32, Vec<u32>>>,
    /// For every pair key, the INDEX_MAP entries (slave condition id → master ids, ascending)
    /// the MappingCheck mortar pruning removed in the step: the search's candidates before the
    /// pruning are `pairs` ∪ `pruned`. Empty without MappingCheck. Not part of RESULT.json
    /// (DESIGN.md §3); the error-vs-run-time report counts spurious candidates with it.
    pub pruned: BTreeMap<String, BTreeMap<u32, Vec<u32>>>,
    /// Every slave-side node of the pairs.
    pub nodes: BTreeMap<u32, NodeResult>,
    /// Paired conditions created (Kratos' ComputingContact count).
    pub paired_conditions: usize,
    /// Warnings of the setup and of the run.
    pub warnings: Vec<String>,
    /// The steps of a multi-step run (SETUP.json `steps`), in order; empty for a single step.
    /// The other fields are then those of the last step.
    pub steps: Vec<StepResult>,
}

/// The result of one step of a multi-step run (RESULT.json `steps` entry).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepResult {
    /// The step number, from 1.
    pub step: u32,
    /// Pairs, nodes and paired conditions after that step's search (its `steps` and
    /// `warnings` are not written).
    pub result: SearchResult,
    /// Wall time of the step's search (`timings_s.search`), 0 when not measured.
    pub search_s: f64,
}

impl SearchResult {
    /// RESULT.json (`csm-result/1`): keys in the contract's order, ids in numeric order.
    /// `timings` become `timings_s`. A multi-step result adds `steps`: per step `step`,
    /// `pairs`, `nodes`, `paired_conditions` and `timings_s` (`search`).
    pub fn to_json(&self, timings: &[(&str, f64)]) -> Value {
        let pairs: Map<String, Value> = self
            .pairs
            .iter()
            .map(|(key, slaves)| {
                let m: Map<String, Value> = slaves
                    .iter()
                    .map(|(s, masters)| (s.to_string(), json!(masters)))
                    .collect();
                (key.clone(), Value::Object(m))
            })
            .collect();
        let nodes: Map<String, Value> = self
            .nodes
            .iter()
            .map(|(id, n)| {
                let gap = n.normal_gap.filter(|g| g.is_finite());
                (
                    id.to_string(),
                    json!({"normal_gap": gap, "active": n.active}),
                )
            })
            .collect();
        let timings: Map<String, Value> = timings
            .iter()
            .map(|(k, v)| ((*k).to_owned(), json!(v)))
            .collect();
        let mut out = Map::new();
        out.insert("format".into(), json!("csm-result/1"));
        out.insert("pairs".into(), Value::Object(pairs));
        out.insert("nodes".into(), Value::Object(nodes));
        out.insert("paired_conditions".into(), json!(self.paired_conditions));
        out.insert("warnings".into(), json!(self.warnings));
        out.insert("timings_s".into(), Value::Object(timings));
        if !self.steps.is_empty() {
            let steps: Vec<Value> = self
                .steps
                .iter()
                .map(|s| {
                    let mut v = s.result.to_json(&[("search", s.search_s)]);
                    let mut step = Map::new();
                    step.insert("step".into(), json!(s.step));
                    if let Value::Object(m) = &mut v {
                        for key in ["pairs", "nodes", "paired_conditions", "timings_s"] {
                            if let Some(x) = m.remove(key) {
                                step.insert(key.into(), x);
                            }
                        }
                    }
                    Value::Object(step)
                })
                .collect();
            out.insert("steps".into(), Value::Array(steps));
        }
        Value::Object(out)
    }

    /// Total number of (slave, master) entries over every pair key.
    pub fn n_pairs(&self) -> usize {
        self.pairs
            .values()
            .flat_map(|m| m.values())
            .map(Vec::len)
            .sum()
    }
}
