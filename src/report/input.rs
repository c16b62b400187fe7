//! What the report is computed from: exactly the data a luxbake output glTF holds, so the report
//! of a finished bake can be recomputed from its file.
//!
//! Two producers: [`ReportInput::from_bake`] (in memory, at bake time) and
//! [`crate::import::load_baked`] (reading an output back). Both must give identical values, so
//! the in-memory path takes the same route as the file: positions are brought into each node's
//! local space and rounded to `f32` by the exporter's own code, then placed in the world by the
//! transform composed from the nodes' local transforms (as the importer composes it); vertex
//! values are the `f32` the file stores; probe values are rounded to `f32` on both paths (the
//! file may hold them as f64 or f32). Primitives come in output order: nodes by index, each
//! node's surfaces in order, front side then back side, empty ones left out.

use crate::Result;
use crate::export::geometry::{LocalFrame, to_local};
use crate::probes::ProbeOrigin;
use crate::result::{BakeResult, Side};
use crate::scene::{Node, Scene, luma};
use glam::{DMat4, DVec3};
use serde_json::Value;

/// Everything the report needs, in the shape of the output file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReportInput {
    /// Every node of the output, by glTF index.
    pub nodes: Vec<NodeInfo>,
    /// Every material of the output, by glTF index.
    pub materials: Vec<MaterialInfo>,
    /// The baked primitives (those with `_ILLUMINANCE`), in output order.
    pub primitives: Vec<Primitive>,
    /// The working-plane probes, when the bake measured at least one.
    pub working_plane: Option<PlaneInput>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct NodeInfo {
    pub name: Option<String>,
    pub parent: Option<usize>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct MaterialInfo {
    pub name: Option<String>,
    /// Photometric reflectance: Y of the linear RGB reflectance the bake used.
    pub reflectance: f64,
}

/// One baked primitive in world space (m); values per vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct Primitive {
    pub node: usize,
    pub material: usize,
    pub positions: Vec<DVec3>,
    /// Counter-clockwise seen from the baked side, in world space.
    pub triangles: Vec<[u32; 3]>,
    /// lx.
    pub illuminance: Vec<f32>,
    /// lx.
    pub illuminance_direct: Vec<f32>,
    /// cd/m².
    pub luminance: Vec<f32>,
}

/// The working plane: its grid (from the run summary's settings) and its points' upward face.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneInput {
    /// Height above the floor (m).
    pub height: Option<f64>,
    /// Grid spacing (m).
    pub spacing: Option<f64>,
    pub points: Vec<PlanePoint>,
}

/// The `+y` face of one working-plane probe (lx), rounded to `f32`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanePoint {
    pub total: f32,
    pub direct: f32,
    pub indirect: f32,
}

impl PlanePoint {
    pub fn new(total: f64, direct: f64, indirect: f64) -> Self {
        PlanePoint {
            total: total as f32,
            direct: direct as f32,
            indirect: indirect as f32,
        }
    }
}

impl PlaneInput {
    /// The grid read from a run summary (`settings.workingPlane`), with these points; `None`
    /// without points.
    pub fn new(summary: Option<&Value>, points: Vec<PlanePoint>) -> Option<Self> {
        let grid = summary.map(|s| &s["settings"]["workingPlane"]);
        let number = |key: &str| grid.and_then(|g| g[key].as_f64());
        (!points.is_empty()).then(|| PlaneInput {
            height: number("height"),
            spacing: number("spacing"),
            points,
        })
    }
}

/// `world_from_local` of every node, composed parent × local from the parentless nodes down,
/// exactly as the importer composes it.
pub fn world_transforms(nodes: &[Node]) -> Vec<DMat4> {
    let mut parent = vec![None; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        for &c in &n.children {
            parent[c] = Some(i);
        }
    }
    let mut world = vec![None; nodes.len()];
    let mut stack: Vec<usize> = (0..nodes.len()).filter(|&i| parent[i].is_none()).collect();
    while let Some(i) = stack.pop() {
        let up = parent[i].and_then(|p| world[p]).unwrap_or(DMat4::IDENTITY);
        world[i] = Some(up * nodes[i].local.to_matrix());
        stack.extend(&nodes[i].children);
    }
    world
        .into_iter()
        .map(|w| w.unwrap_or(DMat4::IDENTITY))
        .collect()
}

impl ReportInput {
    /// The report's input from a bake in memory, equal to what [`crate::import::load_baked`]
    /// reads from the file the exporter writes for it.
    pub fn from_bake(scene: &Scene, result: &BakeResult) -> Result<Self> {
        let mut parent = vec![None; scene.nodes.len()];
        for (i, n) in scene.nodes.iter().enumerate() {
            for &c in &n.children {
                parent[c] = Some(i);
            }
        }
        let nodes = scene
            .nodes
            .iter()
            .zip(parent)
            .map(|(n, parent)| NodeInfo {
                name: n.name.clone(),
                parent,
            })
            .collect();
        let materials = scene
            .materials
            .iter()
            .map(|m| MaterialInfo {
                name: m.name.clone(),
                reflectance: luma(m.reflectance),
            })
            .collect();
        let world = world_transforms(&scene.nodes);
        let mut primitives = Vec::new();
        for (n, node) in scene.nodes.iter().enumerate() {
            if node.surfaces.is_empty() {
                continue;
            }
            let Some(frame) = LocalFrame::new(node.world_from_local) else {
                continue; // the exporter refuses such a node
            };
            for &s in &node.surfaces {
                for side in [Side::Front, Side::Back] {
                    let Some(baked) = result
                        .surfaces
                        .iter()
                        .find(|b| b.surface == s && b.side == side)
                    else {
                        continue;
                    };
                    if baked.triangles.is_empty() {
                        continue;
                    }
                    let local = to_local(baked, &frame, &node.source_path)?;
                    primitives.push(Primitive {
                        node: n,
                        material: scene.surfaces[s].material,
                        positions: local
                            .positions
                            .iter()
                            .map(|p| world[n].transform_point3(DVec3::from(p.map(f64::from))))
                            .collect(),
                        triangles: baked.triangles.clone(),
                        illuminance: local.illuminance,
                        illuminance_direct: local.illuminance_direct,
                        luminance: local.luminance,
                    });
                }
            }
        }
        let points = result
            .probes
            .iter()
            .filter(|p| p.probe.origin == ProbeOrigin::WorkingPlane)
            .map(|p| PlanePoint::new(p.cubic.total[2], p.cubic.direct[2], p.cubic.indirect[2]))
            .collect();
        Ok(ReportInput {
            nodes,
            materials,
            primitives,
            working_plane: PlaneInput::new(Some(&result.summary), points),
        })
    }

    /// The node's name, or `node N`.
    pub fn node_name(&self, i: usize) -> String {
        self.nodes[i]
            .name
            .clone()
            .unwrap_or_else(|| format!("node {i}"))
    }

    /// The node's names joined by `/` from its root (`desk_dark/top`).
    pub fn node_path(&self, mut i: usize) -> String {
        let mut names = vec![self.node_name(i)];
        while let Some(p) = self.nodes[i].parent {
            names.push(self.node_name(p));
            i = p;
        }
        names.reverse();
        names.join("/")
    }

    /// The material's name, or `material N`.
    pub fn material_name(&self, i: usize) -> String {
        self.materials[i]
            .name
            .clone()
            .unwrap_or_else(|| format!("material {i}"))
    }
}
