//! The output's node tree, scene, cameras and punctual lights.
//!
//! Input: the [`Scene`] (nodes, roots, cameras, lights, scene extras), each node's mesh index and
//! the bake summary. Output: the `nodes`, `scenes` and `cameras` arrays and the root
//! `KHR_lights_punctual` extension object (`None` without lights). Invariants: node order,
//! names, children, extras, cameras and the local transform (matrix or TRS, as given) are kept;
//! default transform parts are omitted; a light is referenced from the node that places it
//! (`Node::light`, else `Light::node`), whose transform already positions and aims it; a
//! directional light gets no `range`. A node placing a luminaire gets the `EXT_lights_ies` /
//! `LUXBAKE_luminaire` objects made by [`super::luminaires`] beside its light (extension names
//! sorted). Light colours are linear RGB
//! scaled so the largest component is 1 (glTF requires [0, 1]; chromaticity kept, the intensity
//! in cd or lx is written unchanged). Scene extras gain `"luxbake": <summary>`.

use super::extras::with_luxbake;
use super::summary::to_json;
use crate::scene::{LightKind, LocalTransform, Scene};
use crate::summary::RunSummary;
use glam::{DMat4, DQuat, DVec3};
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

pub const LIGHTS: &str = "KHR_lights_punctual";

/// The `nodes` array; `node_mesh[i]` is node `i`'s mesh index, `node_extensions[i]` the
/// luminaire extension objects of node `i`.
pub(crate) fn nodes(
    scene: &Scene,
    node_mesh: &[Option<usize>],
    node_extensions: &[Vec<(&'static str, Value)>],
) -> Vec<Value> {
    let mut node_light = vec![None; scene.nodes.len()];
    for (i, light) in scene.lights.iter().enumerate() {
        if let Some(slot) = node_light.get_mut(light.node) {
            slot.get_or_insert(i);
        }
    }
    scene
        .nodes
        .iter()
        .enumerate()
        .map(|(i, node)| {
            let mut out = Map::new();
            if let Some(name) = &node.name {
                out.insert("name".into(), json!(name));
            }
            if !node.children.is_empty() {
                out.insert("children".into(), json!(node.children));
            }
            transform(&node.local, &mut out);
            if let Some(mesh) = node_mesh.get(i).copied().flatten() {
                out.insert("mesh".into(), json!(mesh));
            }
            if let Some(camera) = node.camera {
                out.insert("camera".into(), json!(camera));
            }
            let mut extensions: BTreeMap<&str, Value> = BTreeMap::new();
            if let Some(light) = node.light.or(node_light[i]) {
                extensions.insert(LIGHTS, json!({ "light": light }));
            }
            for (name, value) in node_extensions.get(i).into_iter().flatten() {
                extensions.insert(name, value.clone());
            }
            if !extensions.is_empty() {
                out.insert("extensions".into(), json!(extensions));
            }
            if let Some(extras) = &node.extras {
                out.insert("extras".into(), extras.clone());
            }
            Value::Object(out)
        })
        .collect()
}

fn transform(local: &LocalTransform, out: &mut Map<String, Value>) {
    match *local {
        LocalTransform::Matrix(m) => {
            if m != DMat4::IDENTITY {
                out.insert("matrix".into(), json!(m.to_cols_array()));
            }
        }
        LocalTransform::Trs {
            translation,
            rotation,
            scale,
        } => {
            if translation != DVec3::ZERO {
                out.insert("translation".into(), json!(translation.to_array()));
            }
            if rotation != DQuat::IDENTITY {
                out.insert("rotation".into(), json!(rotation.to_array()));
            }
            if scale != DVec3::ONE {
                out.insert("scale".into(), json!(scale.to_array()));
            }
        }
    }
}

/// The single scene: name, root nodes and extras with the run summary (`None`: the scene's
/// extras as they are, for an unbaked scene).
pub(crate) fn scene(scene: &Scene, summary: Option<&RunSummary>) -> Value {
    let mut out = Map::new();
    if let Some(name) = &scene.name {
        out.insert("name".into(), json!(name));
    }
    if !scene.roots.is_empty() {
        out.insert("nodes".into(), json!(scene.roots));
    }
    let extras = match summary {
        Some(summary) => Some(with_luxbake(scene.extras.as_ref(), to_json(summary))),
        None => scene.extras.clone(),
    };
    if let Some(extras) = extras {
        out.insert("extras".into(), extras);
    }
    Value::Object(out)
}

/// The root `KHR_lights_punctual` object (`{"lights": [...]}`), or `None` without lights.
pub(crate) fn lights(scene: &Scene) -> Option<Value> {
    if scene.lights.is_empty() {
        return None;
    }
    let lights: Vec<Value> = scene
        .lights
        .iter()
        .map(|l| {
            let mut out = Map::new();
            if let Some(name) = &l.name {
                out.insert("name".into(), json!(name));
            }
            let max = l.color.max_element();
            let color = if max.is_finite() && max > 0.0 {
                l.color / max
            } else {
                DVec3::ONE
            };
            out.insert("color".into(), json!(color.to_array()));
            out.insert("intensity".into(), json!(l.intensity));
            let kind = match l.kind {
                LightKind::Point => "point",
                LightKind::Directional => "directional",
                LightKind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => {
                    out.insert(
                        "spot".into(),
                        json!({
                            "innerConeAngle": inner_cone_angle,
                            "outerConeAngle": outer_cone_angle,
                        }),
                    );
                    "spot"
                }
            };
            out.insert("type".into(), json!(kind));
            if let (Some(range), false) = (l.range, l.kind == LightKind::Directional) {
                out.insert("range".into(), json!(range));
            }
            Value::Object(out)
        })
        .collect();
    Some(json!({ "lights": lights }))
}
