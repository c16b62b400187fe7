//! The bake's probes in the output's node tree.
//!
//! Input: the [`Scene`], the [`BakeResult`]'s probes, the glyph scale (or none) and the arrays
//! of the document being built. Output: those arrays extended. Rules:
//! - every probe's result becomes the object of [`crate::probes::output::record`];
//! - a node probe (`extras.probe` on a scene node) gets it as its node's `extras.luxbake` (its
//!   other extras, such as `probe: true`, are kept);
//! - every other probe becomes a new node without mesh (an Empty in Blender) named after the
//!   probe, translation = position, rotation = the probe's rotation (identity for grids and CSV
//!   rows, so omitted), with the object in `extras.luxbake`; they are grouped per layer under one
//!   group node each (`grid`, `csv`, `working_plane`, in bake order) under a new root node
//!   `probes` (`extras.luxbake.probeRoot = true`) appended to the scene's root nodes;
//! - with glyphs, each probe node gets one child node carrying its glyph mesh
//!   ([`super::glyphs`]); under a scene node the glyph's vertices absorb the node's scale, so the
//!   glyph keeps its size and the probe's axes.
//!
//! Scene nodes keep their indices, so `origin.node` of a node probe is its output node index.

use super::buffer::Binary;
use super::extras::with_luxbake;
use super::glyphs::Glyphs;
use crate::probes::{ProbeOrigin, ProbeResult, output};
use crate::{Error, Result, scene::Scene};
use glam::{DMat4, DQuat};
use serde_json::{Value, json};

/// The document arrays probes add to.
pub struct Arrays<'a> {
    pub nodes: &'a mut Vec<Value>,
    pub meshes: &'a mut Vec<Value>,
    pub materials: &'a mut Vec<Value>,
    /// The scene object, whose `nodes` lists the roots.
    pub scene: &'a mut Value,
}

/// The group node a non-node probe goes under.
pub(crate) fn layer(origin: &ProbeOrigin) -> Option<String> {
    match origin {
        ProbeOrigin::Node { .. } => None,
        ProbeOrigin::Grid { layer } => Some(layer.clone()),
        ProbeOrigin::File { .. } => Some("csv".into()),
        ProbeOrigin::WorkingPlane => Some("working_plane".into()),
    }
}

/// Add the probes (and their glyphs when `glyph_scale` is given) to the document.
pub(crate) fn add(
    scene: &Scene,
    probes: &[ProbeResult],
    glyph_scale: Option<f64>,
    binary: &mut Binary,
    out: Arrays,
) -> Result<()> {
    if probes.is_empty() {
        return Ok(());
    }
    let glyphs = glyph_scale.map(|s| Glyphs::new(s, probes, out.materials));
    let mut layers: Vec<(String, Vec<usize>)> = Vec::new();
    for r in probes {
        let p = &r.probe;
        let record = output::record(r);
        let probe_world = DMat4::from_mat3_translation(p.world_from_probe, p.position);
        let (index, glyph_frame) = match (&p.origin, layer(&p.origin)) {
            (ProbeOrigin::Node { node }, _) => {
                let source = scene.nodes.get(*node).ok_or_else(|| {
                    Error::Bake(format!("probe '{}' names missing node {node}", p.name))
                })?;
                let json = &mut out.nodes[*node];
                json["extras"] = with_luxbake(source.extras.as_ref(), record);
                let frame = source.world_from_local.inverse() * probe_world;
                (*node, frame.is_finite().then_some(frame))
            }
            (_, layer) => {
                let layer = layer.expect("non-node probes have a layer");
                let mut node = json!({"name": p.name, "translation": p.position.to_array()});
                let q = DQuat::from_mat3(&p.world_from_probe).normalize();
                if !q.abs_diff_eq(DQuat::IDENTITY, 1e-15) {
                    node["rotation"] = json!(q.to_array());
                }
                node["extras"] = json!({ "luxbake": record });
                out.nodes.push(node);
                let index = out.nodes.len() - 1;
                match layers.iter_mut().find(|(name, _)| *name == layer) {
                    Some((_, members)) => members.push(index),
                    None => layers.push((layer, vec![index])),
                }
                (index, Some(DMat4::IDENTITY))
            }
        };
        if let (Some(g), Some(frame)) = (&glyphs, glyph_frame) {
            let child = g.add(r, frame, binary, out.nodes, out.meshes);
            let children = out.nodes[index]
                .as_object_mut()
                .expect("nodes are objects")
                .entry("children")
                .or_insert_with(|| json!([]));
            children
                .as_array_mut()
                .expect("children is an array")
                .push(json!(child));
        }
    }
    if layers.is_empty() {
        return Ok(());
    }
    let mut groups = Vec::new();
    for (name, members) in layers {
        out.nodes.push(json!({"name": name, "children": members}));
        groups.push(out.nodes.len() - 1);
    }
    out.nodes.push(json!({
        "name": "probes",
        "children": groups,
        "extras": {"luxbake": {"probeRoot": true}},
    }));
    let root = out.nodes.len() - 1;
    let roots = out
        .scene
        .as_object_mut()
        .expect("the scene is an object")
        .entry("nodes")
        .or_insert_with(|| json!([]));
    roots
        .as_array_mut()
        .expect("scene nodes is an array")
        .push(json!(root));
    Ok(())
}
