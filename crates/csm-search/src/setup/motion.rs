//! csm's own setup keys of multi-step runs: `steps` (time step and rigid motion of parts) and
//! `nodal_values` (DESIGN.md §3, `docs/steps.md`).

use serde_json::{Map, Value};

use super::parse::invalid;
use super::types::{NodalValueSetup, PartMotion, RigidMotion, Rotation, StepSetup};
use crate::error::Error;

/// Rejects keys of a csm object other than `allowed` (`key` is the object's path).
fn only_keys(map: &Map<String, Value>, key: &str, allowed: &[&str]) -> Result<(), Error> {
    match map.keys().find(|k| !allowed.contains(&k.as_str())) {
        None => Ok(()),
        Some(k) => Err(invalid(
            &format!("{key}.{k}"),
            &format!("one of the keys {}", allowed.join(", ")),
            &Value::String(k.clone()),
        )),
    }
}

/// A finite number.
fn finite(v: &Value, key: &str) -> Result<f64, Error> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| invalid(key, "a finite number", v))
}

/// `[x, y, z]`, finite.
fn vector3(v: &Value, key: &str) -> Result<csm_geometry::math::Vector, Error> {
    let expected = "a list of 3 finite numbers [x, y, z]";
    let items = v
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or_else(|| invalid(key, expected, v))?;
    let mut out = [0.0; 3];
    for (o, x) in out.iter_mut().zip(items) {
        *o = x
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| invalid(key, expected, v))?;
    }
    Ok(csm_geometry::math::Vector::new(out[0], out[1], out[2]))
}

/// csm's `"steps"`: `[{"delta_time": dt, "move": {"<part>": {"translate": [..], "rotate":
/// {"axis": [..], "angle_deg": a, "centre": [..]}}}}, …]` (DESIGN.md §3). Errors name the entry
/// as `steps[<index from 0>]`.
pub(super) fn steps(v: &Value) -> Result<Vec<StepSetup>, Error> {
    let items = v
        .as_array()
        .filter(|a| !a.is_empty())
        .ok_or_else(|| invalid("steps", "a non-empty list of steps", v))?;
    let mut out = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let key = format!("steps[{i}]");
        let map = item
            .as_object()
            .ok_or_else(|| invalid(&key, "an object {\"delta_time\": dt, \"move\": {…}}", item))?;
        only_keys(map, &key, &["delta_time", "move"])?;
        let dt_key = format!("{key}.delta_time");
        let dt = map
            .get("delta_time")
            .ok_or_else(|| invalid(&key, "a `delta_time`", item))?;
        let delta_time = dt
            .as_f64()
            .filter(|x| x.is_finite() && *x > 0.0)
            .ok_or_else(|| invalid(&dt_key, "a positive finite number", dt))?;
        let mut moves: Vec<PartMotion> = Vec::new();
        if let Some(m) = map.get("move") {
            let move_key = format!("{key}.move");
            let parts = m
                .as_object()
                .ok_or_else(|| invalid(&move_key, "an object {\"<part>\": {…}}", m))?;
            for (part, motion) in parts {
                let part_key = format!("{move_key}.{part}");
                moves.push(PartMotion {
                    part: part.clone(),
                    motion: rigid_motion(motion, &part_key)?,
                });
            }
        }
        moves.sort_by(|a, b| a.part.cmp(&b.part));
        out.push(StepSetup { delta_time, moves });
    }
    Ok(out)
}

fn rigid_motion(v: &Value, key: &str) -> Result<RigidMotion, Error> {
    let map = v.as_object().ok_or_else(|| {
        invalid(
            key,
            "an object {\"translate\": [x, y, z], \"rotate\": {…}}",
            v,
        )
    })?;
    only_keys(map, key, &["translate", "rotate"])?;
    let translate = match map.get("translate") {
        Some(t) => vector3(t, &format!("{key}.translate"))?,
        None => csm_geometry::math::Vector::zeros(),
    };
    let rotate = match map.get("rotate") {
        None => None,
        Some(r) => {
            let rkey = format!("{key}.rotate");
            let rmap = r.as_object().ok_or_else(|| {
                invalid(
                    &rkey,
                    "an object {\"axis\": [x, y, z], \"angle_deg\": a, \"centre\": [x, y, z]}",
                    r,
                )
            })?;
            only_keys(rmap, &rkey, &["axis", "angle_deg", "centre"])?;
            let axis_key = format!("{rkey}.axis");
            let axis = vector3(rmap.get("axis").unwrap_or(&Value::Null), &axis_key)?;
            if axis.norm() == 0.0 {
                return Err(invalid(&axis_key, "a non-zero axis", &rmap["axis"]));
            }
            let angle_key = format!("{rkey}.angle_deg");
            let angle_deg = finite(rmap.get("angle_deg").unwrap_or(&Value::Null), &angle_key)?;
            let centre = match rmap.get("centre") {
                Some(c) => csm_geometry::math::Point::from(vector3(c, &format!("{rkey}.centre"))?),
                None => csm_geometry::math::Point::origin(),
            };
            Some(Rotation {
                axis,
                angle_deg,
                centre,
            })
        }
    };
    Ok(RigidMotion { translate, rotate })
}

/// csm's `"nodal_values"`: `[{"part": "<path>", "variable": "ACCELERATION", "buffer": 1,
/// "value": [x, y, z]}, …]`.
pub(super) fn nodal_values(v: &Value) -> Result<Vec<NodalValueSetup>, Error> {
    let items = v
        .as_array()
        .ok_or_else(|| invalid("nodal_values", "a list of nodal values", v))?;
    let mut out = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let key = format!("nodal_values[{i}]");
        let map = item.as_object().ok_or_else(|| {
            invalid(
                &key,
                "an object {\"part\", \"variable\", \"buffer\", \"value\"}",
                item,
            )
        })?;
        only_keys(map, &key, &["part", "variable", "buffer", "value"])?;
        let part_v = map.get("part").unwrap_or(&Value::Null);
        let part = part_v
            .as_str()
            .ok_or_else(|| invalid(&format!("{key}.part"), "a part name (string)", part_v))?;
        let var_v = map.get("variable").unwrap_or(&Value::Null);
        let variable = match var_v.as_str() {
            Some("DISPLACEMENT") => csm_model::VectorVar::Displacement,
            Some("VELOCITY") => csm_model::VectorVar::Velocity,
            Some("ACCELERATION") => csm_model::VectorVar::Acceleration,
            _ => {
                return Err(invalid(
                    &format!("{key}.variable"),
                    "\"DISPLACEMENT\", \"VELOCITY\" or \"ACCELERATION\"",
                    var_v,
                ));
            }
        };
        let buffer = match map.get("buffer") {
            None => 0,
            Some(b) => match b.as_u64() {
                Some(b @ (0 | 1)) => b as usize,
                _ => {
                    return Err(invalid(
                        &format!("{key}.buffer"),
                        "0 (current step) or 1 (previous step)",
                        b,
                    ));
                }
            },
        };
        let value = vector3(
            map.get("value").unwrap_or(&Value::Null),
            &format!("{key}.value"),
        )?;
        out.push(NodalValueSetup {
            part: part.to_owned(),
            variable,
            buffer,
            value,
        });
    }
    Ok(out)
}
