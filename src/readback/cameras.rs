//! The cameras of an output: every node of the scene that names a glTF camera, with its world
//! transform and projection (what `bake view --camera NAME` looks through).
//!
//! Input: the output's [`GltfFile`] (nodes with world transforms; `cameras` JSON). Output: a
//! [`Camera`] per camera node, in node order. glTF conventions: the camera looks down its local
//! −Z with +Y up; `yfov` is the vertical field of view (rad); `aspectRatio` (width / height) and
//! `zfar` are optional. A camera whose projection is missing or out of range is an error naming
//! its pointer (`/cameras/2/perspective/yfov`).

use crate::Result;
use crate::import::GltfFile;
use glam::DMat4;
use serde_json::Value;

/// A camera node of the output.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// The node's index and name.
    pub node: usize,
    pub name: Option<String>,
    /// The node's world transform (may carry scale; the view removes it).
    pub world_from_local: DMat4,
    pub projection: Projection,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    Perspective {
        /// Vertical field of view (rad), in (0, π).
        yfov: f64,
        /// Width / height, when the file gives one.
        aspect_ratio: Option<f64>,
        /// Near clipping distance (m), > 0.
        znear: f64,
    },
    Orthographic,
}

/// Every camera node of the file's scene, in node order.
pub(super) fn read(file: &GltfFile) -> Result<Vec<Camera>> {
    let json = file.json();
    let mut out = Vec::new();
    for i in file.scene_nodes() {
        let Some(c) = json["nodes"][i]["camera"].as_u64() else {
            continue;
        };
        let at = format!("/cameras/{c}");
        let camera = &json["cameras"][c as usize];
        let projection = match camera["type"].as_str() {
            Some("orthographic") => Projection::Orthographic,
            Some("perspective") => perspective(file, &camera["perspective"], &at)?,
            _ => return Err(file.err(at, "a camera without a known type")),
        };
        let node = &file.nodes()[i];
        out.push(Camera {
            node: i,
            name: node.name.clone(),
            world_from_local: node.world_from_local,
            projection,
        });
    }
    Ok(out)
}

fn perspective(file: &GltfFile, p: &Value, at: &str) -> Result<Projection> {
    let number = |key: &str| p[key].as_f64().filter(|v| v.is_finite());
    let yfov = number("yfov")
        .filter(|&v| v > 0.0 && v < std::f64::consts::PI)
        .ok_or_else(|| {
            file.err(
                format!("{at}/perspective/yfov"),
                "a vertical field of view in (0, π) rad is required",
            )
        })?;
    let znear = number("znear").filter(|&v| v > 0.0).ok_or_else(|| {
        file.err(
            format!("{at}/perspective/znear"),
            "a near distance > 0 is required",
        )
    })?;
    let aspect_ratio = match &p["aspectRatio"] {
        Value::Null => None,
        v => Some(
            v.as_f64()
                .filter(|&a| a.is_finite() && a > 0.0)
                .ok_or_else(|| {
                    file.err(
                        format!("{at}/perspective/aspectRatio"),
                        "an aspect ratio must be a number > 0",
                    )
                })?,
        ),
    };
    Ok(Projection::Perspective {
        yfov,
        aspect_ratio,
        znear,
    })
}
