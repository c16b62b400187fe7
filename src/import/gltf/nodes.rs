//! The glTF node hierarchy: choosing the scene, checking the tree, composing world transforms.
//!
//! Inputs: the validated document and its raw JSON. Output: [`Hierarchy`] — one
//! [`scene::Node`] per glTF node (same indices; surfaces and lights are filled in later), the
//! chosen scene's roots, its name and extras, and the nodes reachable from those roots in
//! depth-first order.
//! Choices and invariants: the scene is `scene` if given, else scene 0, else every node without a
//! parent is a root. A node with two parents, a cycle, a scene root that is someone's child, a
//! non-unit rotation, a non-affine matrix or a non-finite world transform is an error naming
//! `/nodes/N` (or `/scenes/N/nodes/K`). `world_from_local` = parent's × local, computed for every
//! node (unreachable subtrees relative to their own top node). `local` is kept as given.

use super::raw;
use crate::Result;
use crate::import::context::Ctx;
use crate::scene::{LocalTransform, Node};
use glam::{DMat4, DQuat, DVec3, DVec4};
use serde_json::Value;

pub(super) struct Hierarchy {
    pub nodes: Vec<Node>,
    pub roots: Vec<usize>,
    pub name: Option<String>,
    pub extras: Option<Value>,
    /// Nodes of the imported scene, parents before children.
    pub reachable: Vec<usize>,
}

pub(super) fn build(ctx: &Ctx, doc: &::gltf::Document, raw: &Value) -> Result<Hierarchy> {
    let n = doc.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for node in doc.nodes() {
        for child in node.children() {
            let c = child.index();
            if let Some(p) = parent[c] {
                return Err(ctx.err(
                    format!("/nodes/{c}"),
                    format!(
                        "node has two parents (/nodes/{p} and /nodes/{}); glTF nodes form a tree",
                        node.index()
                    ),
                ));
            }
            parent[c] = Some(node.index());
        }
    }
    check_acyclic(ctx, &parent)?;

    let mut nodes = Vec::with_capacity(n);
    for node in doc.nodes() {
        let i = node.index();
        nodes.push(Node {
            name: node.name().map(str::to_owned),
            source_path: format!("/nodes/{i}"),
            children: node.children().map(|c| c.index()).collect(),
            local: local_transform(ctx, raw, i)?,
            world_from_local: DMat4::IDENTITY,
            mesh_name: node.mesh().and_then(|m| m.name().map(str::to_owned)),
            surfaces: Vec::new(),
            light: None,
            camera: node.camera().map(|c| c.index()),
            extras: raw::cloned(raw, &format!("/nodes/{i}/extras")),
        });
    }
    // World transforms, top-down from every parentless node.
    let tops: Vec<usize> = (0..n).filter(|&i| parent[i].is_none()).collect();
    for &top in &tops {
        for i in depth_first(&nodes, &[top]) {
            let parent_world = parent[i].map_or(DMat4::IDENTITY, |p| nodes[p].world_from_local);
            let world = parent_world * nodes[i].local.to_matrix();
            if !world.is_finite() {
                return Err(ctx.err(
                    format!("/nodes/{i}"),
                    "the composed world transform is not finite",
                ));
            }
            nodes[i].world_from_local = world;
        }
    }

    let (roots, name, extras) = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            let roots: Vec<usize> = scene.nodes().map(|r| r.index()).collect();
            for (k, &r) in roots.iter().enumerate() {
                let at = format!("/scenes/{}/nodes/{k}", scene.index());
                if let Some(p) = parent[r] {
                    return Err(ctx.err(
                        at,
                        format!("scene root /nodes/{r} is a child of /nodes/{p}"),
                    ));
                }
                if roots[..k].contains(&r) {
                    return Err(ctx.err(at, format!("scene lists /nodes/{r} twice")));
                }
            }
            let extras = raw::cloned(raw, &format!("/scenes/{}/extras", scene.index()));
            (roots, scene.name().map(str::to_owned), extras)
        }
        None => (tops, None, None),
    };
    let reachable = depth_first(&nodes, &roots);
    Ok(Hierarchy {
        nodes,
        roots,
        name,
        extras,
        reachable,
    })
}

/// Every node below `starts` (inclusive), parents first. The hierarchy must be a forest.
fn depth_first(nodes: &[Node], starts: &[usize]) -> Vec<usize> {
    let mut order = Vec::new();
    let mut stack: Vec<usize> = starts.iter().rev().copied().collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        stack.extend(nodes[i].children.iter().rev());
    }
    order
}

/// Error if following parents from some node comes back to it.
fn check_acyclic(ctx: &Ctx, parent: &[Option<usize>]) -> Result<()> {
    // 0 = unvisited, 1 = on the current walk, 2 = known to reach a top node.
    let mut state = vec![0u8; parent.len()];
    for start in 0..parent.len() {
        let mut walk = Vec::new();
        let mut at = Some(start);
        while let Some(i) = at {
            match state[i] {
                2 => break,
                1 => {
                    return Err(ctx.err(
                        format!("/nodes/{i}"),
                        "the node hierarchy has a cycle through this node",
                    ));
                }
                _ => {
                    state[i] = 1;
                    walk.push(i);
                    at = parent[i];
                }
            }
        }
        for i in walk {
            state[i] = 2;
        }
    }
    Ok(())
}

fn local_transform(ctx: &Ctx, raw: &Value, i: usize) -> Result<LocalTransform> {
    let base = format!("/nodes/{i}");
    if let Some(m) = raw::numbers::<16>(raw, &format!("{base}/matrix")) {
        let matrix = DMat4::from_cols_array(&m);
        if (matrix.row(3) - DVec4::W).abs().max_element() > 1e-9 {
            return Err(ctx.err(
                format!("{base}/matrix"),
                "the matrix is not affine (its last row must be 0, 0, 0, 1)",
            ));
        }
        return Ok(LocalTransform::Matrix(matrix));
    }
    let translation = raw::numbers::<3>(raw, &format!("{base}/translation")).unwrap_or([0.0; 3]);
    let rotation = raw::numbers::<4>(raw, &format!("{base}/rotation")).unwrap_or([0., 0., 0., 1.]);
    let scale = raw::numbers::<3>(raw, &format!("{base}/scale")).unwrap_or([1.0; 3]);
    let rotation = DQuat::from_array(rotation);
    if (rotation.length() - 1.0).abs() > 1e-3 {
        return Err(ctx.err(
            format!("{base}/rotation"),
            format!(
                "rotation is not a unit quaternion (length {})",
                rotation.length()
            ),
        ));
    }
    Ok(LocalTransform::Trs {
        translation: DVec3::from_array(translation),
        rotation,
        scale: DVec3::from_array(scale),
    })
}
