use csm_geometry::math::{Point, Vector};

use crate::{ModelPart, NodeId, VectorVar};

fn two_nodes() -> ModelPart {
    let mut m = ModelPart::new("Structure");
    m.add_node(NodeId(1), Point::new(0.0, 0.0, 0.0)).unwrap();
    m.add_node(NodeId(2), Point::new(1.0, 0.0, 0.0)).unwrap();
    m
}

#[test]
fn advance_time_step_shifts_the_buffer_and_the_clock() {
    let mut m = two_nodes();
    m.nodal_data_mut().add_vector(VectorVar::Velocity);
    m.nodal_data_mut()
        .vector_mut(VectorVar::Velocity, 0)
        .unwrap()[1] = Vector::new(2.0, 0.0, 0.0);
    m.process_info_mut().set_number("STEP", 1.0);
    m.process_info_mut().set_number("TIME", 1.0);
    m.advance_time_step(0.25);
    let pi = m.process_info();
    assert_eq!(
        (
            pi.number("STEP"),
            pi.number("TIME"),
            pi.number("DELTA_TIME")
        ),
        (Some(2.0), Some(1.25), Some(0.25))
    );
    let data = m.nodal_data();
    for step in 0..2 {
        assert_eq!(
            data.vector(VectorVar::Velocity, step).unwrap()[1],
            Vector::new(2.0, 0.0, 0.0),
            "buffer {step}"
        );
    }
}

/// Two steps of a node moving +1, then +3 in x with dt = 0.5: DISPLACEMENT accumulates,
/// VELOCITY is the increment over dt, ACCELERATION the velocity change over dt; the node that
/// does not move keeps zero velocity.
#[test]
fn prescribed_motion_follows_the_buffer_semantics() {
    let mut m = two_nodes();
    let dt = 0.5;
    m.prescribe_motion(&[Point::new(1.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0)], dt);
    m.advance_time_step(dt);
    m.prescribe_motion(&[Point::new(4.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0)], dt);
    assert_eq!(m.nodes().coordinates()[0], Point::new(4.0, 0.0, 0.0));
    let data = m.nodal_data();
    let x = |var, step| data.vector(var, step).unwrap()[0].x;
    assert_eq!(x(VectorVar::Displacement, 0), 4.0);
    assert_eq!(x(VectorVar::Displacement, 1), 1.0);
    assert_eq!(x(VectorVar::Velocity, 0), 6.0);
    assert_eq!(x(VectorVar::Velocity, 1), 2.0);
    assert_eq!(x(VectorVar::Acceleration, 0), 8.0);
    assert_eq!(x(VectorVar::Acceleration, 1), 4.0);
    let still = data.vector(VectorVar::Velocity, 0).unwrap()[1];
    assert_eq!(still, Vector::zeros());
}
