//! The octree path (`type_search = OctreeWithOBB`, reference §8). Not implemented yet.

use csm_model::{ConditionIdx, ModelPart, PartIdx};

use crate::error::{Error, ErrorKind};
use crate::setup::{Compatibility, SearchParameters};

/// What the octree search of one pair needs besides the model.
#[derive(Debug)]
pub(crate) struct OctreeContext<'a> {
    pub params: &'a SearchParameters,
    /// `Contact.ContactSub<key>`.
    pub sub: PartIdx,
    pub dim: usize,
    pub slave_nodes: usize,
    pub compatibility: Compatibility,
    pub domain_size: u32,
}

/// SearchUsingOcTree: fills the slaves' INDEX_MAPs (MappingCheck) or pushes the created
/// (slave, master) pairs (No/DirectCheck).
pub(crate) fn search_octree(
    _model: &mut ModelPart,
    _cx: &OctreeContext<'_>,
    _created: &mut Vec<(ConditionIdx, ConditionIdx)>,
) -> Result<(), Error> {
    Err(ErrorKind::NotImplemented("type_search octree_with_obb".to_owned()).into())
}
