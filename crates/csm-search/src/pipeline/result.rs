//! The result of a search step, in the form of RESULT.json (DESIGN.md §3).

use std::collections::BTreeMap;

use serde_json::Value;

use super::IdMap;

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
    pub pairs: BTreeMap<String, IdMap<Vec<u32>>>,
    /// For every pair key, the INDEX_MAP entries (slave condition id → master ids, ascending)
    /// the MappingCheck mortar pruning removed in the step: the search's candidates before the
    /// pruning are `pairs` ∪ `pruned`. Empty without MappingCheck. Not part of RESULT.json
    /// (DESIGN.md §3); the error-vs-run-time report counts spurious candidates with it.
    pub pruned: BTreeMap<String, IdMap<Vec<u32>>>,
    /// Every slave-side node of the pairs.
    pub nodes: IdMap<NodeResult>,
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
        // The one serde view of RESULT.json ([`ResultJson`]); `write_json` writes the same
        // text with its big maps formatted in parallel (`result_text.rs`, tested against it).
        // It cannot fail: every map key is a string or an integer and every number is finite
        // or written as null.
        serde_json::to_value(ResultJson {
            result: self,
            timings,
            step: None,
        })
        .expect("RESULT.json serialises")
    }

    /// Writes RESULT.json to `writer`, pretty-printed and followed by a newline: the same
    /// text as `serde_json::to_string_pretty(&self.to_json(timings))`, streamed (no JSON
    /// tree of the whole result in memory), the entries of `pairs` and `nodes` formatted in
    /// parallel (rayon's pool).
    ///
    /// Errors: those of the writer.
    pub fn write_json(
        &self,
        timings: &[(&str, f64)],
        writer: impl std::io::Write,
    ) -> std::io::Result<()> {
        super::result_text::write_result_json(self, timings, writer)
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
        struct Pairs<'a>(&'a BTreeMap<String, IdMap<Vec<u32>>>);
        impl serde::Serialize for Pairs<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                struct Slaves<'a>(&'a IdMap<Vec<u32>>);
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
        struct Nodes<'a>(&'a IdMap<NodeResult>);
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
        r.pairs.insert("0".into(), slaves.into());
        r.pairs.insert("1".into(), IdMap::new());
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

    /// RESULT.json's text: the contract's key order (optional keys after
    /// `paired_conditions`), ids in numeric order, NaN and infinity as null, steps with their
    /// own five keys; streamed or as a tree, the same text.
    #[test]
    fn result_json_has_the_contract_text() {
        let r = sample(true);
        let timings = [("read", 1.25), ("total", f64::INFINITY)];
        let mut streamed = Vec::new();
        r.write_json(&timings, &mut streamed).unwrap();
        let text = String::from_utf8(streamed).unwrap();
        let tree = serde_json::to_string_pretty(&r.to_json(&timings)).unwrap() + "\n";
        assert_eq!(text, tree);
        let compact: String = text.split_whitespace().collect();
        let node = |gap: &str, active: bool| format!(r#"{{"normal_gap":{gap},"active":{active}}}"#);
        let nodes = format!(
            r#"{{"2":{},"5":{},"9":{}}}"#,
            node("null", false),
            node("-0.125", true),
            node("null", false)
        );
        let pairs = r#"{"0":{"7":[],"12":[3,40]},"1":{}}"#;
        let expected = format!(
            r#"{{"format":"csm-result/1","pairs":{pairs},"nodes":{nodes},"paired_conditions":2,"master_slave_constraints":2,"kratos_condition_ids":{{"40":3}},"warnings":["a\"quoted\"warning"],"timings_s":{{"read":1.25,"total":null}},"steps":[{{"step":1,"pairs":{pairs},"nodes":{nodes},"paired_conditions":2,"timings_s":{{"search":0.5}}}},{{"step":2,"pairs":{{}},"nodes":{{}},"paired_conditions":0,"timings_s":{{"search":null}}}}]}}"#
        );
        assert_eq!(compact, expected);
    }
}
