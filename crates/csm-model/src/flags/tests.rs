use super::*;

#[test]
fn tri_state_semantics_follow_kratos() {
    let mut f = Flags::new();
    assert!(!f.is_defined(Flag::ACTIVE));
    assert!(!f.is(Flag::ACTIVE));
    assert!(f.is_not(Flag::ACTIVE), "IsNot is true for undefined flags");
    assert_eq!(f.get(Flag::ACTIVE), None);

    f.set(Flag::ACTIVE, false);
    assert!(f.is_defined(Flag::ACTIVE));
    assert!(!f.is(Flag::ACTIVE));
    assert_eq!(f.get(Flag::ACTIVE), Some(false));

    f.flip(Flag::ACTIVE);
    assert!(f.is(Flag::ACTIVE));
    f.reset(Flag::ACTIVE);
    assert_eq!(f.get(Flag::ACTIVE), None);

    f.flip(Flag::SLAVE);
    assert!(
        f.is(Flag::SLAVE),
        "flipping an undefined flag makes it true"
    );
    assert!(!f.is_defined(Flag::MASTER));
}

#[test]
fn combined_flags_require_all() {
    let mut f = Flags::new();
    f.set(Flag::INTERFACE, true);
    assert!(!f.is(Flag::INTERFACE | Flag::SLAVE));
    f.set(Flag::SLAVE, true);
    assert!(f.is(Flag::INTERFACE | Flag::SLAVE));
}
