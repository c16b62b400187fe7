//! What a finished luxbake output holds, in world space: its nodes and materials, the baked
//! primitives with their per-vertex values (and, when lightmapped, their atlas, layout and
//! texels), the lightmap atlases, the probes, the working plane and the run summary.
//! Whichever way it arrives (read from a file, or as the exporter would write a bake in
//! memory), a consumer sees the same values.

use super::cameras::Camera;
use crate::summary::RunSummary;
use crate::{Error, Result};
use glam::{DVec2, DVec3};
use serde_json::Value;
use std::path::PathBuf;

/// A luxbake output.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BakedOutput {
    /// Every node of the output, by glTF index.
    pub nodes: Vec<NodeInfo>,
    /// Every material of the output, by glTF index.
    pub materials: Vec<MaterialInfo>,
    /// The baked primitives (those with `_ILLUMINANCE`), in output order: nodes by index, each
    /// node's surfaces in order, front side then back side.
    pub primitives: Vec<Primitive>,
    /// Primitives drawn for viewers only (nodes with `extras.luxbake.displayOnly`: the
    /// luminaires' luminous openings), in node order.
    pub shown: Vec<Shown>,
    /// Every probe node (a node with `extras.luxbake.faces`), in node order.
    pub probes: Vec<ProbeNode>,
    /// The working-plane probes, when the bake measured at least one.
    pub working_plane: Option<PlaneInput>,
    /// The lightmap atlases the materials name (`LUXBAKE_lightmap`), in order of their `atlas`
    /// number; empty for a bake without lightmaps.
    pub lightmaps: Vec<Lightmap>,
    /// The camera nodes of the scene, in node order.
    pub cameras: Vec<Camera>,
    /// The run summary as stored (the scene's `extras.luxbake`), read typed by
    /// [`BakedOutput::run_summary`] only where it is needed: comparing two bakes needs none, so
    /// bakes of other versions still compare.
    pub summary: Option<Value>,
    /// The file it was read from (or the name of the output not yet written).
    pub file: PathBuf,
    /// The files read besides it (buffers, images, lightmap EXR files; canonical paths): a
    /// subcommand writing beside a bake checks its outputs against these.
    pub resources: Vec<PathBuf>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct NodeInfo {
    pub name: Option<String>,
    pub parent: Option<usize>,
    /// `extras.power_W`: a luminaire's power (W), when the input gives it.
    pub power_w: Option<f64>,
    /// `extensions.LUXBAKE_luminaire.maintenanceFactor`, when given.
    pub maintenance_factor: Option<f64>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct MaterialInfo {
    pub name: Option<String>,
    /// Photometric reflectance: Y of the linear RGB reflectance the bake used.
    pub reflectance: f64,
    /// The linear RGB reflectance the bake used (grey `reflectance` when written as one number).
    pub reflectance_rgb: DVec3,
    /// For a lightmapped variant (`extras.luxbake.variantOf`): the material it was made from.
    pub variant_of: Option<usize>,
    /// What a glTF viewer shows of it (for `bake view --display`).
    pub look: Look,
}

/// The display part of a material as written (what a glTF viewer multiplies and shows).
#[derive(Debug, Clone, PartialEq)]
pub struct Look {
    /// `pbrMetallicRoughness.baseColorFactor`, linear RGBA (glTF's default 1, 1, 1, 1).
    pub base_color: [f64; 4],
    /// `emissiveFactor`, linear RGB (default 0).
    pub emissive: [f64; 3],
    /// `emissiveTexture`: (texture index, `texCoord`).
    pub emissive_texture: Option<(usize, u32)>,
    /// `KHR_materials_unlit`.
    pub unlit: bool,
}

/// A primitive drawn for viewers only, in world space (m, +Y up): what a glTF viewer shows of
/// it is `base` × `COLOR_0`.
#[derive(Debug, Clone, PartialEq)]
pub struct Shown {
    pub positions: Vec<DVec3>,
    /// Counter-clockwise seen from the front, in world space.
    pub triangles: Vec<[u32; 3]>,
    pub color: Vec<[f32; 3]>,
    /// The material's `baseColorFactor` (RGB).
    pub base: [f64; 3],
}

/// One baked primitive in world space (m, +Y up); values per vertex.
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
    /// `COLOR_0` (linear RGB display colour, the exposure rule of the run summary), when
    /// written (not on lightmapped primitives).
    pub color: Option<Vec<[f32; 3]>>,
    /// Its lightmap, when its material has `LUXBAKE_lightmap`.
    pub lightmap: Option<LightmapUse>,
    /// Triangles from this index on are a covered part (`extras.luxbake.coveredFrom`: the floor
    /// under a desk leg), without light; `None` (outputs without the marker too): none.
    pub covered_from: Option<u32>,
}

impl Primitive {
    /// Whether triangle `j` is part of what another surface covers.
    pub(crate) fn is_covered(&self, j: usize) -> bool {
        self.covered_from.is_some_and(|k| j >= k as usize)
    }
}

/// How a primitive is laid out in a lightmap.
#[derive(Debug, Clone, PartialEq)]
pub struct LightmapUse {
    /// Index into [`BakedOutput::lightmaps`].
    pub lightmap: usize,
    /// The layout (`TEXCOORD_<texCoord>`), per vertex.
    pub uv: Vec<DVec2>,
    /// The texels it stands on, in texel order: those its UV triangles cover with some area (a
    /// triangle without UV area, such as a covered part's, stands on the texel holding it).
    pub texels: Vec<Texel>,
}

/// One texel of a primitive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texel {
    /// Row-major index in its atlas (row 0 at the top).
    pub index: u32,
    /// The triangle of the primitive with the most area in it.
    pub triangle: u32,
}

/// One lightmap atlas: the channels of its EXR file, row-major from the top row; texel (col,
/// row) is centred at UV ((col + 0.5)/W, (row + 0.5)/H).
#[derive(Debug, Clone, PartialEq)]
pub struct Lightmap {
    /// Its `atlas` number.
    pub atlas: usize,
    /// The EXR file, relative to the output.
    pub uri: String,
    pub width: u32,
    pub height: u32,
    /// Texel edge of the layout (m).
    pub texel_size: f64,
    /// Where it is described (`/materials/N/extensions/LUXBAKE_lightmap` of the first material
    /// naming it).
    pub at: String,
    /// Luminance leaving the surface, linear RGB (cd/m²).
    pub luminance: Vec<[f32; 3]>,
    /// lx.
    pub illuminance: Vec<f32>,
    /// lx.
    pub illuminance_direct: Vec<f32>,
    /// m² of surface each texel stands for; 0 for padding.
    pub footprint: Vec<f32>,
}

impl Lightmap {
    /// Photometric luminance Y of texel `k` (cd/m²): 0.2126 R + 0.7152 G + 0.0722 B.
    pub(crate) fn luminance_y(&self, k: usize) -> f64 {
        let [r, g, b] = self.luminance[k].map(f64::from);
        crate::scene::luma(DVec3::new(r, g, b))
    }
}

/// A node with probe results (`extras.luxbake.faces`).
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeNode {
    /// glTF node index.
    pub node: usize,
    /// World position (m).
    pub position: DVec3,
    /// Total illuminance on the faces `+x -x +y -y +z -z` (lx).
    pub faces: [f64; 6],
    /// One of the working plane's points (`extras.luxbake.probe.origin.kind` is
    /// `workingPlane`).
    pub working_plane: bool,
}

/// The working plane: its points' upward face. Its grid (height, spacing) is in the run
/// summary's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneInput {
    pub points: Vec<PlanePoint>,
}

/// The `+y` face of one working-plane probe (lx), rounded to `f32`, and where the probe is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanePoint {
    /// World position (m, +Y up): `extras.luxbake.probe.position`, else the node's world origin.
    pub position: DVec3,
    pub total: f32,
    pub direct: f32,
    pub indirect: f32,
}

impl PlanePoint {
    pub(crate) fn new(position: DVec3, total: f64, direct: f64, indirect: f64) -> Self {
        PlanePoint {
            position,
            total: total as f32,
            direct: direct as f32,
            indirect: indirect as f32,
        }
    }
}

/// Where the run summary is stored.
pub const SUMMARY_AT: &str = "/scenes/0/extras/luxbake";

impl BakedOutput {
    /// The run summary, typed; `None` when the file has none. A field it lacks (an output of
    /// another version) or holds in another form is an error naming the field.
    pub fn run_summary(&self) -> Result<Option<RunSummary>> {
        let Some(value) = &self.summary else {
            return Ok(None);
        };
        serde_path_to_error::deserialize(value)
            .map(Some)
            .map_err(|e| {
                let path = e.path().to_string();
                let at = match path.as_str() {
                    "." => SUMMARY_AT.to_string(),
                    p => format!("{SUMMARY_AT}/{}", p.replace('.', "/")),
                };
                Error::input(&self.file, at, format!("run summary: {}", e.inner()))
            })
    }

    /// The node's name, or `node N`.
    pub(crate) fn node_name(&self, i: usize) -> String {
        self.nodes[i]
            .name
            .clone()
            .unwrap_or_else(|| format!("node {i}"))
    }

    /// The node's names joined by `/` from its root (`desk_dark/top`): linear in its depth (at
    /// most the node count, should the file's parents form a cycle).
    pub(crate) fn node_path(&self, mut i: usize) -> String {
        let mut names = vec![self.node_name(i)];
        while let Some(p) = self.nodes[i].parent {
            if names.len() > self.nodes.len() {
                break;
            }
            names.push(self.node_name(p));
            i = p;
        }
        names.reverse();
        names.join("/")
    }

    /// The material's name, or `material N`.
    pub(crate) fn material_name(&self, i: usize) -> String {
        self.materials[i]
            .name
            .clone()
            .unwrap_or_else(|| format!("material {i}"))
    }
}

/// Each node's parent, from the nodes' children lists.
pub(crate) fn parents(
    children: impl Iterator<Item = impl AsRef<[usize]>>,
    n: usize,
) -> Vec<Option<usize>> {
    let mut parent = vec![None; n];
    for (i, c) in children.enumerate() {
        for &c in c.as_ref() {
            parent[c] = Some(i);
        }
    }
    parent
}
