//! Multi-step runs: the rigid increments of SETUP.json `steps` and the initial `nodal_values`,
//! resolved against the model's parts (DESIGN.md §3, `docs/steps.md`).

use csm_geometry::math::Point;
use csm_model::{ModelPart, NodeIdx};

use crate::error::{Error, ErrorKind};
use crate::setup::{NodalValueSetup, StepSetup};

fn unknown_part(key: String, part: &str, model: &ModelPart) -> Error {
    ErrorKind::InvalidValue {
        key,
        expected: format!(
            "a sub model part of the mesh ({})",
            model.part_paths().join(", ")
        ),
        found: format!("\"{part}\""),
    }
    .into()
}

/// Every part named in `steps` exists, and the parts moved in one step share no node (a node
/// gets one increment per step). Errors name the offending entry (`steps[i].move.<part>`).
pub(crate) fn check_step_parts(model: &ModelPart, steps: &[StepSetup]) -> Result<(), Error> {
    for (i, step) in steps.iter().enumerate() {
        let mut owner: Vec<Option<usize>> = vec![None; model.nodes().len()];
        for (j, m) in step.moves.iter().enumerate() {
            let key = format!("steps[{i}].move.{}", m.part);
            let part = model
                .find_part(&m.part)
                .ok_or_else(|| unknown_part(key.clone(), &m.part, model))?;
            for n in model.part(part).nodes() {
                if let Some(first) = owner[n.index()] {
                    return Err(ErrorKind::InvalidValue {
                        key,
                        expected: "parts without common nodes in one step".to_owned(),
                        found: format!(
                            "`{}` and `{}` share node {}",
                            step.moves[first].part,
                            m.part,
                            model.nodes().ids()[n.index()]
                        ),
                    }
                    .into());
                }
                owner[n.index()] = Some(j);
            }
        }
    }
    Ok(())
}

/// The node positions after the rigid increments of `step` (unmoved nodes keep theirs).
pub(crate) fn step_positions(model: &ModelPart, step: &StepSetup) -> Result<Vec<Point>, Error> {
    let mut positions = model.nodes().coordinates().to_vec();
    for m in &step.moves {
        let part = model.get_part(&m.part).map_err(|e| {
            Error::from(ErrorKind::Model(format!(
                "step motion of `{}`: {e}",
                m.part
            )))
        })?;
        for n in model.part(part).nodes() {
            positions[n.index()] = m.motion.apply(&positions[n.index()]);
        }
    }
    Ok(positions)
}

/// Sets the `nodal_values` of the setup (historical vectors at buffer index 0 or 1) on the
/// nodes of their parts; the variable is added where absent.
pub(crate) fn apply_nodal_values(
    model: &mut ModelPart,
    values: &[NodalValueSetup],
) -> Result<(), Error> {
    for (i, v) in values.iter().enumerate() {
        let part = model
            .find_part(&v.part)
            .ok_or_else(|| unknown_part(format!("nodal_values[{i}].part"), &v.part, model))?;
        let nodes: Vec<NodeIdx> = model.part(part).nodes().to_vec();
        let data = model.nodal_data_mut();
        data.add_vector(v.variable);
        if let Some(col) = data.vector_mut(v.variable, v.buffer) {
            for n in nodes {
                col[n.index()] = v.value;
            }
        }
    }
    Ok(())
}
