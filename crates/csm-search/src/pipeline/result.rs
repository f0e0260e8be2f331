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
    /// The contact conditions whose id Kratos changes (file id → Kratos id): its contact
    /// process numbers every condition of the model 1..N in id order before the search, so
    /// Kratos' INDEX_MAPs show the new ids. `pairs` keeps the file ids. Written to RESULT.json
    /// (`kratos_condition_ids`) only when not empty.
    pub kratos_condition_ids: BTreeMap<u32, u32>,
    /// `MPCContactProcess`: the `ContactMasterSlaveConstraint`s created, one per paired
    /// condition (RESULT.json `master_slave_constraints`); `None` for the processes that make
    /// paired conditions only.
    pub master_slave_constraints: Option<usize>,
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
        if let Some(n) = self.master_slave_constraints {
            out.insert("master_slave_constraints".into(), json!(n));
        }
        if !self.kratos_condition_ids.is_empty() {
            let ids: Map<String, Value> = self
                .kratos_condition_ids
                .iter()
                .map(|(file, kratos)| (file.to_string(), json!(kratos)))
                .collect();
            out.insert("kratos_condition_ids".into(), Value::Object(ids));
        }
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

    /// Writes RESULT.json to `writer`, pretty-printed and followed by a newline: the same
    /// text as `serde_json::to_string_pretty(&self.to_json(timings))`, streamed (no JSON
    /// tree of the whole result in memory).
    ///
    /// Errors: those of the writer.
    pub fn write_json(
        &self,
        timings: &[(&str, f64)],
        mut writer: impl std::io::Write,
    ) -> std::io::Result<()> {
        serde_json::to_writer_pretty(
            &mut writer,
            &ResultJson {
                result: self,
                timings,
                step: None,
            },
        )
        .map_err(std::io::Error::from)?;
        writer.write_all(b"\n")
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

/// RESULT.json of a result (`step: None`) or one `steps` entry, serialised as
/// [`SearchResult::to_json`] builds it (same keys, same order).
struct ResultJson<'a> {
    result: &'a SearchResult,
    timings: &'a [(&'a str, f64)],
    step: Option<u32>,
}

impl serde::Serialize for ResultJson<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        struct Pairs<'a>(&'a BTreeMap<String, BTreeMap<u32, Vec<u32>>>);
        impl serde::Serialize for Pairs<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                struct Slaves<'a>(&'a BTreeMap<u32, Vec<u32>>);
                impl serde::Serialize for Slaves<'_> {
                    fn serialize<S: serde::Serializer>(
                        &self,
                        serializer: S,
                    ) -> Result<S::Ok, S::Error> {
                        serializer.collect_map(self.0)
                    }
                }
                serializer.collect_map(self.0.iter().map(|(k, v)| (k, Slaves(v))))
            }
        }
        struct Nodes<'a>(&'a BTreeMap<u32, NodeResult>);
        impl serde::Serialize for Nodes<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                struct Node(NodeResult);
                impl serde::Serialize for Node {
                    fn serialize<S: serde::Serializer>(
                        &self,
                        serializer: S,
                    ) -> Result<S::Ok, S::Error> {
                        let mut m = serializer.serialize_map(Some(2))?;
                        m.serialize_entry(
                            "normal_gap",
                            &self.0.normal_gap.filter(|g| g.is_finite()),
                        )?;
                        m.serialize_entry("active", &self.0.active)?;
                        m.end()
                    }
                }
                serializer.collect_map(self.0.iter().map(|(id, n)| (id, Node(*n))))
            }
        }
        struct Timings<'a>(&'a [(&'a str, f64)]);
        impl serde::Serialize for Timings<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                // `json!(f64)`: a non-finite value is null.
                serializer.collect_map(
                    self.0
                        .iter()
                        .map(|(k, v)| (*k, Some(*v).filter(|v| v.is_finite()))),
                )
            }
        }
        struct Steps<'a>(&'a [StepResult]);
        impl serde::Serialize for Steps<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_seq(self.0.iter().map(StepJson))
            }
        }
        struct StepJson<'a>(&'a StepResult);
        impl serde::Serialize for StepJson<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                let timings = [("search", self.0.search_s)];
                ResultJson {
                    result: &self.0.result,
                    timings: &timings,
                    step: Some(self.0.step),
                }
                .serialize(serializer)
            }
        }
        let r = self.result;
        let mut m = serializer.serialize_map(None)?;
        match self.step {
            None => {
                m.serialize_entry("format", "csm-result/1")?;
                m.serialize_entry("pairs", &Pairs(&r.pairs))?;
                m.serialize_entry("nodes", &Nodes(&r.nodes))?;
                m.serialize_entry("paired_conditions", &r.paired_conditions)?;
                if let Some(n) = r.master_slave_constraints {
                    m.serialize_entry("master_slave_constraints", &n)?;
                }
                if !r.kratos_condition_ids.is_empty() {
                    m.serialize_entry("kratos_condition_ids", &r.kratos_condition_ids)?;
                }
                m.serialize_entry("warnings", &r.warnings)?;
                m.serialize_entry("timings_s", &Timings(self.timings))?;
                if !r.steps.is_empty() {
                    m.serialize_entry("steps", &Steps(&r.steps))?;
                }
            }
            Some(step) => {
                m.serialize_entry("step", &step)?;
                m.serialize_entry("pairs", &Pairs(&r.pairs))?;
                m.serialize_entry("nodes", &Nodes(&r.nodes))?;
                m.serialize_entry("paired_conditions", &r.paired_conditions)?;
                m.serialize_entry("timings_s", &Timings(self.timings))?;
            }
        }
        m.end()
    }
}

#[cfg(test)]
mod json_tests {
    use super::*;

    fn sample(steps: bool) -> SearchResult {
        let mut r = SearchResult::default();
        let mut slaves = BTreeMap::new();
        slaves.insert(12, vec![3, 40]);
        slaves.insert(7, vec![]);
        r.pairs.insert("0".into(), slaves);
        r.pairs.insert("1".into(), BTreeMap::new());
        r.nodes.insert(
            5,
            NodeResult {
                normal_gap: Some(-0.125),
                active: true,
            },
        );
        r.nodes.insert(
            2,
            NodeResult {
                normal_gap: None,
                active: false,
            },
        );
        r.nodes.insert(
            9,
            NodeResult {
                normal_gap: Some(f64::NAN),
                active: false,
            },
        );
        r.paired_conditions = 2;
        r.kratos_condition_ids.insert(40, 3);
        r.master_slave_constraints = Some(2);
        r.warnings = vec!["a \"quoted\" warning".into()];
        if steps {
            r.steps = vec![
                StepResult {
                    step: 1,
                    result: sample(false),
                    search_s: 0.5,
                },
                StepResult {
                    step: 2,
                    result: SearchResult::default(),
                    search_s: f64::NAN,
                },
            ];
        }
        r
    }

    /// The streamed RESULT.json is the text of the JSON tree, byte for byte.
    #[test]
    fn write_json_equals_the_pretty_tree() {
        for steps in [false, true] {
            let r = sample(steps);
            let timings = [("read", 1.25), ("search", 3.0), ("total", f64::INFINITY)];
            let tree = serde_json::to_string_pretty(&r.to_json(&timings)).unwrap() + "\n";
            let mut streamed = Vec::new();
            r.write_json(&timings, &mut streamed).unwrap();
            assert_eq!(String::from_utf8(streamed).unwrap(), tree, "steps: {steps}");
        }
    }
}
