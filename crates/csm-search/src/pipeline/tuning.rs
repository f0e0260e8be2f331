//! How a search organises its work: the knobs that change the order of work or what is kept in
//! memory, never a result (tests run every setting against the default and compare the bits).
//! Production uses [`SearchTuning::default`]; tests set it through
//! [`crate::ContactSearch::set_tuning`].

pub use csm_activation::MappingTuning;

/// Which slave queries of a kd-tree search run first, in slave order as their nodes are read,
/// and which run along a Morton curve of the slave centres (neighbouring queries visit the
/// same tree nodes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum QueryOrder {
    /// The slaves the estimate puts far from every master first, the others along the curve.
    #[default]
    Estimate,
    /// Every query first, in slave order.
    AllFirst,
    /// Every query along the curve.
    AllAlongCurve,
}

/// The work-organisation knobs of a [`crate::ContactSearch`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SearchTuning {
    /// The mortar mapping's ([`MappingTuning`]: streaming threshold and batch, operators kept).
    pub mapping: MappingTuning,
    /// The order of the kd-tree's slave queries.
    pub query_order: QueryOrder,
}
