//! Typed ids: external (file) ids and dense internal indices, kept apart.

use std::fmt;

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
        pub struct $name(pub u32);

        impl $name {
            /// The raw value.
            pub fn get(self) -> u32 {
                self.0
            }
            /// The raw value as an index into dense storage.
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

id_type!(
    /// External id of a node, as in the mesh file (Kratos ids are 1-based).
    NodeId
);
id_type!(
    /// Dense internal index of a node in its [`crate::ModelPart`].
    NodeIdx
);
id_type!(
    /// External id of an element, as in the mesh file.
    ElementId
);
id_type!(
    /// Dense internal index of an element.
    ElementIdx
);
id_type!(
    /// External id of a condition, as in the mesh file.
    ConditionId
);
id_type!(
    /// Dense internal index of a condition.
    ConditionIdx
);
id_type!(
    /// Id of a properties block (Kratos `Properties`), as in the mesh file.
    PropertiesId
);
id_type!(
    /// Dense index of a sub model part in the part tree of a [`crate::ModelPart`].
    PartIdx
);
