//! Kratos' tri-state flags: every flag is undefined, true or false.
//!
//! Kratos stores two bit sets per entity, which flags are *defined* and their *values*, and
//! the search depends on the difference (`IsDefined(ACTIVE)`, reference Q7).

bitflags::bitflags! {
    /// The flags the contact pipeline uses, named as in Kratos.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
    pub struct Flag: u32 {
        /// Node or condition on a contact interface.
        const INTERFACE = 1 << 0;
        /// Master side.
        const MASTER = 1 << 1;
        /// Slave side.
        const SLAVE = 1 << 2;
        /// Active in contact.
        const ACTIVE = 1 << 3;
        /// General-purpose marker.
        const MARKER = 1 << 4;
        /// Selected (octree search).
        const SELECTED = 1 << 5;
        /// Visited.
        const VISITED = 1 << 6;
        /// Slip (frictional contact).
        const SLIP = 1 << 7;
        /// Isolated (active node without a paired condition).
        const ISOLATED = 1 << 8;
        /// To be erased.
        const TO_ERASE = 1 << 9;
        /// Modified (remeshing).
        const MODIFIED = 1 << 10;
        /// Inverted search.
        const INVERTED_SEARCH = 1 << 11;
    }
}

/// The tri-state flags of one entity: which flags are defined, and the values of those.
///
/// Semantics follow Kratos: [`Flags::is`] is true only for defined-and-true;
/// [`Flags::is_not`] is `!is` (so also true for undefined); [`Flags::is_defined`] tells
/// undefined apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Flags {
    defined: Flag,
    values: Flag,
}

impl Flags {
    /// No flag defined.
    pub const fn new() -> Flags {
        Flags {
            defined: Flag::empty(),
            values: Flag::empty(),
        }
    }

    /// Defines `flag` and sets it to `value` (Kratos `Set(flag, value)`).
    pub fn set(&mut self, flag: Flag, value: bool) {
        self.defined |= flag;
        self.values.set(flag, value);
    }

    /// True iff every flag in `flag` is defined and true (Kratos `Is`).
    pub fn is(&self, flag: Flag) -> bool {
        self.defined.contains(flag) && self.values.contains(flag)
    }

    /// Kratos `IsNot`: the negation of [`Flags::is`], true for undefined flags too.
    pub fn is_not(&self, flag: Flag) -> bool {
        !self.is(flag)
    }

    /// True iff every flag in `flag` is defined (Kratos `IsDefined`).
    pub fn is_defined(&self, flag: Flag) -> bool {
        self.defined.contains(flag)
    }

    /// Makes `flag` undefined again (Kratos `Reset`).
    pub fn reset(&mut self, flag: Flag) {
        self.defined.remove(flag);
        self.values.remove(flag);
    }

    /// Toggles `flag` and marks it defined (Kratos `Flip`): undefined becomes true.
    pub fn flip(&mut self, flag: Flag) {
        self.defined |= flag;
        self.values.toggle(flag);
    }

    /// The value of `flag`: `None` when undefined.
    pub fn get(&self, flag: Flag) -> Option<bool> {
        self.is_defined(flag).then(|| self.values.contains(flag))
    }

    /// The set of defined flags.
    pub fn defined(&self) -> Flag {
        self.defined
    }
}

#[cfg(test)]
mod tests;
