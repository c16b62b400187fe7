//! `KHR_lights_punctual` lights placed by nodes → world-space [`Light`]s.
//!
//! Inputs: the raw light definition (`/extensions/KHR_lights_punctual/lights/L`, read at f64
//! precision) and the placing node's `world_from_local`. Output: one [`Light`] per placing node.
//! Rules: point and spot intensity in cd, directional in lx, `color` normalised to luminance 1,
//! `range` kept. Position = the node's world translation; direction = the node's world −Z,
//! normalised (node scale changes neither intensity nor direction length). Spot cones default to
//! inner 0 and outer π/4.
//! Invariants: intensity finite and ≥ 0; colour with positive luminance; 0 ≤ inner < outer ≤ π/2;
//! spot/directional direction defined (no zero scale); else an error naming the light's pointer.

use super::raw;
use crate::Result;
use crate::import::context::Ctx;
use crate::import::material_values::unit_luminance_color;
use crate::scene::{Light, LightKind};
use glam::{DMat4, DVec3};
use serde_json::Value;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

/// The light `light` as placed by node `node` (with world transform `world`).
pub(super) fn light(
    ctx: &Ctx,
    raw: &Value,
    light: usize,
    node: usize,
    world: DMat4,
) -> Result<Light> {
    let at = format!("/extensions/KHR_lights_punctual/lights/{light}");
    let err = |msg: String| ctx.err(&at, msg);
    let def = raw
        .pointer(&at)
        .ok_or_else(|| err("light not found".into()))?;
    let kind = match def.get("type").and_then(Value::as_str) {
        Some("point") => LightKind::Point,
        Some("directional") => LightKind::Directional,
        Some("spot") => {
            let inner = raw::number_or(def, "/spot/innerConeAngle", 0.0);
            let outer = raw::number_or(def, "/spot/outerConeAngle", FRAC_PI_4);
            if !(inner >= 0.0 && inner < outer && outer <= FRAC_PI_2) {
                return Err(err(format!(
                    "spot cone angles must satisfy 0 ≤ innerConeAngle < outerConeAngle ≤ π/2; \
                     got inner {inner}, outer {outer} (radians)"
                )));
            }
            LightKind::Spot {
                inner_cone_angle: inner,
                outer_cone_angle: outer,
            }
        }
        other => return Err(err(format!("unknown light type {other:?}"))),
    };
    let intensity = raw::number_or(def, "/intensity", 1.0);
    if !intensity.is_finite() || intensity < 0.0 {
        return Err(err(format!("intensity {intensity} must be finite and ≥ 0")));
    }
    let color = raw::numbers::<3>(def, "/color").unwrap_or([1.0; 3]);
    let color = unit_luminance_color(DVec3::from_array(color), "color").map_err(err)?;
    let direction = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero();
    let direction = if direction == DVec3::ZERO || !direction.is_finite() {
        if kind != LightKind::Point {
            return Err(ctx.err(
                format!("/nodes/{node}"),
                format!("the node's transform collapses the direction of light {at}"),
            ));
        }
        DVec3::NEG_Z
    } else {
        direction
    };
    Ok(Light {
        name: def.get("name").and_then(Value::as_str).map(str::to_owned),
        source_path: at.clone(),
        node,
        kind,
        intensity,
        color,
        position: world.transform_point3(DVec3::ZERO),
        direction,
        range: raw::number(def, "/range"),
    })
}
