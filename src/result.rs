//! The bake's results in the shape the exporters and reports consume.
//!
//! Invariants: every `BakedSurface` refers to a valid `Scene::surfaces` index; its per-vertex
//! arrays all have `positions.len()` entries; triangles index into them and are wound
//! counter-clockwise seen from the side that was baked (for `Side::Back` that is the reverse of the
//! input winding), in world space. `color` lies in [0, 1].

pub use crate::patches::Side;
use crate::summary::{RunSummary, StageSeconds};
use glam::{DVec2, DVec3};

/// One surface (one side of it), refined into patches, with the baked values at its vertices.
#[derive(Debug, Clone)]
pub struct BakedSurface {
    /// Index into `Scene::surfaces`.
    pub surface: usize,
    pub side: Side,
    /// World-space positions (m).
    pub positions: Vec<DVec3>,
    /// World-space unit normals, pointing out of the baked side.
    pub normals: Vec<DVec3>,
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
    /// Illuminance incident on the baked side (lx), photometric (Y).
    pub illuminance: Vec<f32>,
    /// The direct part of `illuminance` (lx): from lights and emitting surfaces, unreflected.
    pub illuminance_direct: Vec<f32>,
    /// Luminance leaving the baked side (cd/m²), photometric (Y): (M_e + ρ·E)/π.
    pub luminance: Vec<f32>,
    /// Display colour for `COLOR_0`, linear, each component in [0, 1].
    pub color: Vec<[f32; 3]>,
    /// The lightmap atlas this surface is laid out in (`--lightmaps`): then `uv1` is its layout
    /// (`TEXCOORD_1`, in [0, 1], v down as glTF's), and vertices on chart edges are split.
    pub lightmap: Option<usize>,
    /// Where the covered part starts (`src/contacts`: the floor under a desk leg, the ceiling
    /// above a panel): triangles from this index on are covered, with vertices of their own and
    /// no light. `None`: nothing is covered. Lightmap layout keeps the triangle order.
    pub covered_from: Option<u32>,
}

/// The lightmap atlases of a bake (`--lightmaps`).
#[derive(Debug, Clone, Default)]
pub struct Lightmaps {
    /// Texel edge the layout was made for (m); a surface too large for one atlas is laid out
    /// coarser (see the run summary).
    pub texel_size: f64,
    pub atlases: Vec<Atlas>,
}

/// One atlas: per texel, row-major from the top row. Texel (col, row) covers UV
/// ((col + 0.5)/width, (row + 0.5)/height) at its centre, row 0 at v = 0 (glTF's UV axes).
#[derive(Debug, Clone, Default)]
pub struct Atlas {
    pub width: u32,
    pub height: u32,
    /// Luminance leaving the surface per channel (cd/m², linear RGB): photometric Y is
    /// 0.2126 R + 0.7152 G + 0.0722 B, as `_LUMINANCE`.
    pub luminance: Vec<[f32; 3]>,
    /// Illuminance (lx, photometric).
    pub illuminance: Vec<f32>,
    /// Its direct part (lx).
    pub illuminance_direct: Vec<f32>,
    /// Area of surface the texel stands for (m²): 0 for padding (values there are dilated from
    /// neighbours so bilinear filtering never reads an empty texel).
    pub area: Vec<f32>,
    /// Display colour, linear, each component in [0, 1]: the rule of `COLOR_0` (exposure and
    /// shoulder), to be shown times the material's base colour factor.
    pub display: Vec<[f32; 3]>,
}

impl Atlas {
    /// An atlas of `width` × `height` texels, every value 0.
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Atlas {
            width,
            height,
            luminance: vec![[0.0; 3]; n],
            illuminance: vec![0.0; n],
            illuminance_direct: vec![0.0; n],
            area: vec![0.0; n],
            display: vec![[0.0; 3]; n],
        }
    }
}

/// A luminaire's luminous opening drawn for viewers: never a receiver, an occluder or an input
/// surface (the importer skips it), so it shows the fitting lit in any glTF viewer.
#[derive(Debug, Clone, PartialEq)]
pub struct OpeningMesh {
    /// Which luminaire (index into `Scene::luminaires`).
    pub luminaire: usize,
    /// World-space positions (m, +Y up) and unit normals; three vertices a triangle, each face
    /// its own vertices.
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    /// The luminance each vertex's face shows along its normal (Y, cd/m²).
    pub luminance: Vec<f32>,
    /// Display colour, in [0, 1] (over a white base, as `COLOR_0`).
    pub color: Vec<[f32; 3]>,
}

/// Everything the bake produced.
#[derive(Debug, Clone)]
pub struct BakeResult {
    pub surfaces: Vec<BakedSurface>,
    /// Cubic illuminance at every probe (scene nodes marked `probe`, grids, CSV files, the
    /// working plane).
    pub probes: Vec<crate::probes::ProbeResult>,
    /// The lightmap atlases (`--lightmaps`).
    pub lightmaps: Option<Lightmaps>,
    /// The luminaires' luminous openings as display-only meshes (`bake::openings`).
    pub openings: Vec<OpeningMesh>,
    /// The run summary; written as the output scene's `extras.luxbake` and by `--summary-json`.
    pub summary: RunSummary,
    /// Wall-clock seconds per stage (not part of `summary` unless asked for: they differ run to
    /// run, and bakes must be byte-identical).
    pub timings: StageSeconds,
}

impl BakeResult {
    /// `scene` as if nothing had been baked: one front side per surface, every value 0, no
    /// probes, an empty summary (what an unbaked input scene is written from, without the
    /// summary).
    pub fn unbaked(scene: &crate::scene::Scene) -> Self {
        let surfaces = scene
            .surfaces
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let n = s.positions.len();
                BakedSurface {
                    surface: i,
                    side: Side::Front,
                    positions: s.positions.clone(),
                    normals: s.normals.clone(),
                    uv0: s.uv0.clone(),
                    uv1: s.uv1.clone(),
                    triangles: s.triangles.clone(),
                    illuminance: vec![0.0; n],
                    illuminance_direct: vec![0.0; n],
                    luminance: vec![0.0; n],
                    color: vec![[0.0; 3]; n],
                    lightmap: None,
                    covered_from: None,
                }
            })
            .collect();
        BakeResult {
            surfaces,
            probes: Vec::new(),
            lightmaps: None,
            openings: Vec::new(),
            summary: RunSummary::default(),
            timings: StageSeconds::default(),
        }
    }
}
