//! The luminaires' luminous openings ([`OpeningMesh`], `bake::openings`) as glTF: one root node
//! and mesh per opening, all with one `KHR_materials_unlit` material of white base colour, so any
//! viewer shows COLOR_0: the opening's luminance on the display scale of the bake.
//!
//! Output: node `"<luminaire name> opening"` (world-space vertices, no transform) with
//! `extras.luxbake = {"displayOnly": true, "opening": {"luminaire": i}}`; its one primitive has
//! POSITION, NORMAL, COLOR_0 and `_LUMINANCE` (cd/m², the face's luminance along its normal),
//! and no `_ILLUMINANCE` (readers of the bake skip it). The importer skips the mesh of every
//! `displayOnly` node, so baking the output anew does not see these faces.

use super::buffer::Binary;
use crate::result::OpeningMesh;
use crate::scene::Scene;
use serde_json::{Value, json};

/// The arrays the openings are appended to.
pub struct Arrays<'a> {
    pub nodes: &'a mut Vec<Value>,
    pub meshes: &'a mut Vec<Value>,
    pub materials: &'a mut Vec<Value>,
    pub scene: &'a mut Value,
}

/// Append `openings` to the document.
pub(crate) fn add(scene: &Scene, openings: &[OpeningMesh], binary: &mut Binary, out: Arrays) {
    if openings.is_empty() {
        return;
    }
    let material = out.materials.len();
    out.materials.push(json!({
        "name": "luxbake luminous opening",
        "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0,
        },
        "extensions": {"KHR_materials_unlit": {}},
        // Read back (by a re-bake) as black: no surface uses it, but every material must
        // state a reflectance below 1.
        "extras": {"luxbake": {"displayOnly": true,
                               "original": {"LUXBAKE_material": {"reflectance": 0.0}}}},
    }));
    for o in openings {
        let f32x3 = |v: &glam::DVec3| v.to_array().map(|x| x as f32);
        let positions: Vec<[f32; 3]> = o.positions.iter().map(f32x3).collect();
        let normals: Vec<[f32; 3]> = o.normals.iter().map(f32x3).collect();
        let triangles: Vec<[u32; 3]> = (0..positions.len() as u32 / 3)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        let name = match scene.luminaires[o.luminaire].name.as_deref() {
            Some(n) => format!("{n} opening"),
            None => format!("luminaire {} opening", o.luminaire),
        };
        let mesh = out.meshes.len();
        out.meshes.push(json!({
            "name": name,
            "primitives": [{
                "attributes": {
                    "POSITION": binary.vec3(&positions, true),
                    "NORMAL": binary.vec3(&normals, false),
                    "COLOR_0": binary.vec3(&o.color, false),
                    "_LUMINANCE": binary.scalar(&o.luminance),
                },
                "indices": binary.indices(&triangles, positions.len()),
                "material": material,
                "mode": 4,
            }],
        }));
        let node = out.nodes.len();
        out.nodes.push(json!({
            "name": name,
            "mesh": mesh,
            "extras": {"luxbake": {"displayOnly": true, "opening": {"luminaire": o.luminaire}}},
        }));
        if let Some(roots) = out.scene["nodes"].as_array_mut() {
            roots.push(json!(node));
        } else {
            out.scene["nodes"] = json!([node]);
        }
    }
}
