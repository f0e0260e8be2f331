use super::*;

#[test]
fn historical_variables_keep_two_steps_and_plain_ones_one() {
    let mut d = NodalData::default();
    d.resize(3);
    d.add_scalar(ScalarVar::WeightedGap);
    d.add_scalar(ScalarVar::NormalGap);
    assert!(d.scalar(ScalarVar::WeightedGap, 1).is_some());
    assert!(d.scalar(ScalarVar::NormalGap, 1).is_none());
    assert!(
        d.scalar(ScalarVar::NodalArea, 0).is_none(),
        "absent variable"
    );

    d.scalar_mut(ScalarVar::WeightedGap, 0).unwrap()[2] = 4.0;
    d.clone_solution_step();
    assert_eq!(
        d.scalar(ScalarVar::WeightedGap, 1).unwrap(),
        &[0.0, 0.0, 4.0]
    );
    d.scalar_mut(ScalarVar::WeightedGap, 0).unwrap()[2] = 5.0;
    assert_eq!(d.scalar(ScalarVar::WeightedGap, 0).unwrap()[2], 5.0);
    assert_eq!(d.scalar(ScalarVar::WeightedGap, 1).unwrap()[2], 4.0);
}

#[test]
fn columns_grow_with_the_nodes() {
    let mut d = NodalData::default();
    d.add_vector(VectorVar::Velocity);
    d.resize(2);
    assert_eq!(d.vector(VectorVar::Velocity, 0).unwrap().len(), 2);
    assert_eq!(d.vector(VectorVar::Velocity, 1).unwrap().len(), 2);
    assert!(!d.has_vector(VectorVar::Acceleration));
}

#[test]
fn variables_added_without_history_keep_one_step() {
    let mut d = NodalData::default();
    d.resize(2);
    d.add_scalar_current(ScalarVar::NodalH);
    d.add_vector_current(VectorVar::Normal);
    assert_eq!(d.scalar_steps(ScalarVar::NodalH), 1);
    assert_eq!(d.vector_steps(VectorVar::Normal), 1);
    assert!(d.scalar(ScalarVar::NodalH, 1).is_none());
    // A later `add_*` finds the variable present and leaves it as it is.
    d.add_vector(VectorVar::Normal);
    assert_eq!(d.vector_steps(VectorVar::Normal), 1);
    d.clone_solution_step();
    assert_eq!(d.scalar(ScalarVar::NodalH, 0).unwrap(), &[0.0, 0.0]);
    // Variables added with history keep both steps.
    d.add_scalar(ScalarVar::WeightedGap);
    assert_eq!(d.scalar_steps(ScalarVar::WeightedGap), 2);
    assert_eq!(d.scalar_steps(ScalarVar::NodalArea), 0);
}

/// A vector variable's stamp changes with every access that can change its values, and only
/// with those; a clone shares it until one of them changes.
#[test]
fn a_vector_stamp_follows_the_writes() {
    let mut d = NodalData::default();
    d.resize(3);
    assert_eq!(d.vector_stamp(VectorVar::Normal), 0);
    d.add_vector(VectorVar::Normal);
    let added = d.vector_stamp(VectorVar::Normal);
    assert_ne!(added, 0);
    // Reading, adding it again, other variables: the same.
    let _ = d.vector(VectorVar::Normal, 0);
    d.add_vector(VectorVar::Normal);
    d.add_vector_current(VectorVar::AuxiliarCoordinates);
    d.scalar_mut(ScalarVar::NormalGap, 0);
    d.vector_mut(VectorVar::AuxiliarCoordinates, 0);
    assert_eq!(d.vector_stamp(VectorVar::Normal), added);
    let clone = d.clone();
    assert_eq!(clone.vector_stamp(VectorVar::Normal), added);
    // Every write access, the buffer advanced, the nodes resized: a new stamp each time.
    let mut seen = vec![added];
    let writes: [fn(&mut NodalData); 4] = [
        |d| {
            let _ = d.vector_mut(VectorVar::Normal, 0);
        },
        |d| {
            if let Some(v) = d.take_vector(VectorVar::Normal, 0) {
                d.put_vector(VectorVar::Normal, 0, v);
            }
        },
        |d| d.clone_solution_step(),
        |d| d.resize(4),
    ];
    for write in writes {
        write(&mut d);
        let stamp = d.vector_stamp(VectorVar::Normal);
        assert!(!seen.contains(&stamp), "{seen:?} {stamp}");
        seen.push(stamp);
    }
    assert_eq!(clone.vector_stamp(VectorVar::Normal), added);
}

/// `set_vector` moves one value per node in as step 0, adding an absent variable with its
/// other buffer steps zero, renews the stamp, and hands a list of the wrong length back.
#[test]
fn set_vector_moves_the_values_in() {
    let mut d = NodalData::default();
    d.resize(2);
    let v = |x: f64| Vector::new(x, 0.0, 0.0);
    assert_eq!(
        d.set_vector(VectorVar::Normal, vec![v(1.0)]),
        Err(vec![v(1.0)])
    );
    assert!(d.vector(VectorVar::Normal, 0).is_none(), "nothing added");
    d.set_vector(VectorVar::Normal, vec![v(1.0), v(2.0)])
        .unwrap();
    assert_eq!(d.vector(VectorVar::Normal, 0).unwrap(), &[v(1.0), v(2.0)]);
    assert_eq!(d.vector(VectorVar::Normal, 1).unwrap(), &[v(0.0), v(0.0)]);
    d.set_vector(VectorVar::AuxiliarCoordinates, vec![v(3.0), v(4.0)])
        .unwrap();
    assert!(d.vector(VectorVar::AuxiliarCoordinates, 1).is_none());
    let stamp = d.vector_stamp(VectorVar::AuxiliarCoordinates);
    d.set_vector(VectorVar::AuxiliarCoordinates, vec![v(5.0), v(6.0)])
        .unwrap();
    assert_ne!(d.vector_stamp(VectorVar::AuxiliarCoordinates), stamp);
    assert_eq!(
        d.vector(VectorVar::AuxiliarCoordinates, 0).unwrap(),
        &[v(5.0), v(6.0)]
    );
}

/// `set_scalar` as `set_vector`: the values moved in as step 0, an absent variable added with
/// its other steps zero, a list of the wrong length handed back.
#[test]
fn set_scalar_moves_the_values_in() {
    let mut d = NodalData::default();
    d.resize(2);
    assert_eq!(d.set_scalar(ScalarVar::NodalH, vec![1.0]), Err(vec![1.0]));
    assert!(d.scalar(ScalarVar::NodalH, 0).is_none(), "nothing added");
    d.set_scalar(ScalarVar::NodalH, vec![1.0, 2.0]).unwrap();
    assert_eq!(d.scalar(ScalarVar::NodalH, 0).unwrap(), &[1.0, 2.0]);
    assert_eq!(d.scalar(ScalarVar::NodalH, 1).unwrap(), &[0.0, 0.0]);
    d.set_scalar(ScalarVar::NodalH, vec![3.0, 4.0]).unwrap();
    assert_eq!(d.scalar(ScalarVar::NodalH, 0).unwrap(), &[3.0, 4.0]);
    assert_eq!(d.scalar(ScalarVar::NodalH, 1).unwrap(), &[0.0, 0.0]);
}

/// Columns long enough to be zeroed in parallel are zero, every step of them, on any pool.
#[test]
fn long_columns_are_added_as_zeros() {
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut d = NodalData::default();
        d.resize(100_003);
        pool.install(|| {
            d.add_scalar(ScalarVar::WeightedGap);
            d.add_scalar_current(ScalarVar::NodalH);
        });
        for (var, step) in [
            (ScalarVar::WeightedGap, 0),
            (ScalarVar::WeightedGap, 1),
            (ScalarVar::NodalH, 0),
        ] {
            let column = d.scalar(var, step).unwrap();
            assert_eq!(column.len(), 100_003);
            assert!(column.iter().all(|v| v.to_bits() == 0), "{var:?} {step}");
        }
    }
}

/// One scalar column written from a vector column: both the columns `scalar_mut` and
/// `vector` give, at the step asked; `None` for an absent variable or step.
#[test]
fn a_scalar_column_is_written_beside_a_vector_column() {
    let mut d = NodalData::default();
    d.resize(2);
    d.add_scalar(ScalarVar::NormalGap);
    d.add_vector(VectorVar::Normal);
    d.vector_mut(VectorVar::Normal, 0).unwrap()[1] = Vector::new(0.0, 0.0, 3.0);
    let (gap, normal) = d.scalar_mut_and_vector((ScalarVar::NormalGap, VectorVar::Normal), 0);
    let (gap, normal) = (gap.unwrap(), normal.unwrap());
    gap[1] = normal[1].z;
    assert_eq!(d.scalar(ScalarVar::NormalGap, 0).unwrap(), &[0.0, 3.0]);
    // NORMAL is historical, NORMAL_GAP is not: no step 1 of the scalar.
    let (gap, normal) = d.scalar_mut_and_vector((ScalarVar::NormalGap, VectorVar::Normal), 1);
    assert!(gap.is_none() && normal.is_some());
    let (gap, normal) = d.scalar_mut_and_vector((ScalarVar::NodalArea, VectorVar::Velocity), 0);
    assert!(gap.is_none() && normal.is_none());
}
