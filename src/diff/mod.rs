//! `bake diff`: comparing two luxbake outputs.
//!
//! Input: two [`BakedOutput`]s (read by [`crate::readback::read`]), A (the candidate)
//! and B (the reference), and [`Options`]. Output: a [`Diff`] (rendered as text by [`text`] or as
//! JSON by [`Diff::json`]), or a [`Mismatch`] when the two cannot be compared in the chosen
//! [`Mode`] (see [`matching`] for how nodes, primitives, vertices, materials and probes pair up).
//!
//! Modes:
//! - [`Mode::Vertices`] (default): `_ILLUMINANCE`, `_ILLUMINANCE_DIRECT` and `_LUMINANCE` vertex
//!   by vertex (same nodes, primitives, vertex counts and positions), plus probes; when both
//!   bakes have lightmaps (and [`Options::lightmaps`]) it becomes [`Mode::Texels`] for the same
//!   layout, else [`Mode::Samples`] ([`lightmaps`]);
//! - [`Mode::Texels`]: the lightmaps' `illuminance`, `illuminanceDirect` and luminance Y texel by
//!   texel, over the texels with a footprint in either bake (the same matching, the same atlas
//!   sizes, each matched primitive's TEXCOORD_1 within 10⁻⁶), plus probes;
//! - [`Mode::Samples`]: the same three read bilinearly from each bake's lightmap at its own
//!   TEXCOORD_1, at every matched vertex and triangle centroid (the same matching), plus probes;
//! - [`Mode::Means`]: for bakes of different topology (another patch size): each baked node's and
//!   each material's area-weighted mean of the three attributes (the report's E avg, direct avg,
//!   L avg: [`crate::report::rows::row`]; from texels when both bakes have lightmaps), one value
//!   per node and per material, plus probes;
//! - [`Mode::Probes`]: probes only; meshes may differ in any way.
//!
//! Probes (nodes with `extras.luxbake.faces`) are compared face by face in every mode
//! (`probeFaces`); `workingPlane` is the `+y` face of the probes under `probes/working_plane`.
//!
//! Tolerance: a value passes when |a − b| ≤ atol + rtol·max(|b|, floor). `atol` and `floor` are
//! in lx; for `_LUMINANCE` they are divided by π (cd/m², the luminance of a white Lambertian
//! surface under that illuminance). The default floor is 1 % of the nearest-rank 99th
//! percentile of |b| of B's vertex `_ILLUMINANCE` (1 lx when that is 0), the same in every mode.
//! The relative difference is |a − b| / max(|b|, floor). p95 is the nearest-rank 95th
//! percentile. A non-finite value fails with an infinite difference (`null` in JSON).
//!
//! Invariants: the result depends only on the two files and the options (fixed orders, no
//! hashing order, no threads); the work is linear in the number of values apart from the final
//! sort of the worst places.

mod by_position;
mod compare;
mod lightmaps;
pub mod matching;
pub mod render;
mod stats;
mod surfaces;

pub use compare::{compare, default_floor};

pub use crate::readback::{BakedOutput, ProbeNode};
use serde::Serialize;
use std::f64::consts::PI;

/// What is compared (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    #[default]
    Vertices,
    Texels,
    Samples,
    Means,
    Probes,
}

impl Mode {
    /// How the mode compares (`compared vertex by vertex`), for the text and error messages.
    pub fn describe(self) -> &'static str {
        match self {
            Mode::Vertices => "vertex by vertex",
            Mode::Texels => "lightmap texel by texel",
            Mode::Samples => {
                "at surface points (vertices and triangle centroids, each bake's lightmap read \
                 bilinearly at its own TEXCOORD_1)"
            }
            Mode::Means => "by area-weighted means per node and per material",
            Mode::Probes => "by probes only",
        }
    }

    /// Whether the mode pairs nodes, primitives and vertices one to one.
    pub(crate) fn by_vertex(self) -> bool {
        matches!(self, Mode::Vertices | Mode::Texels | Mode::Samples)
    }
}

/// How values are compared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    pub mode: Mode,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance (lx).
    pub atol: f64,
    /// Floor of the relative difference's denominator (lx); `None`: 1 % of B's p99.
    pub floor: Option<f64>,
    /// How many worst places to list.
    pub worst: usize,
    /// Compare lightmaps when both bakes have them (vertices mode becomes texels or samples;
    /// means are taken over texels).
    pub lightmaps: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            mode: Mode::Vertices,
            rtol: 1e-3,
            atol: 0.0,
            floor: None,
            worst: 10,
            lightmaps: true,
        }
    }
}

/// Why two outputs cannot be compared in a mode: the first place where they differ
/// (`node room/floor (/nodes/0 in A, /nodes/0 in B) primitive 0: 124 vertices vs 130`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch(pub String);

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The compared quantities, in output order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    Illuminance,
    IlluminanceDirect,
    Luminance,
    ProbeFaces,
    WorkingPlane,
}

impl Quantity {
    pub const ALL: [Quantity; 5] = [
        Quantity::Illuminance,
        Quantity::IlluminanceDirect,
        Quantity::Luminance,
        Quantity::ProbeFaces,
        Quantity::WorkingPlane,
    ];

    /// The JSON name.
    pub(crate) fn key(self) -> &'static str {
        match self {
            Quantity::Illuminance => "illuminance",
            Quantity::IlluminanceDirect => "illuminanceDirect",
            Quantity::Luminance => "luminance",
            Quantity::ProbeFaces => "probeFaces",
            Quantity::WorkingPlane => "workingPlane",
        }
    }

    /// The quantity with this JSON name.
    pub(crate) fn from_key(key: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.key() == key)
    }

    /// The name in the text output (the glTF attribute).
    pub(crate) fn label(self) -> &'static str {
        match self {
            Quantity::Illuminance => "_ILLUMINANCE",
            Quantity::IlluminanceDirect => "_ILLUMINANCE_DIRECT",
            Quantity::Luminance => "_LUMINANCE",
            Quantity::ProbeFaces => "probe faces",
            Quantity::WorkingPlane => "working plane +y",
        }
    }

    /// The name in the text output when `mode` compares lightmaps (the EXR channel).
    pub(crate) fn label_in(self, mode: Mode) -> &'static str {
        match (mode, self) {
            (Mode::Texels | Mode::Samples, Quantity::Illuminance) => "illuminance",
            (Mode::Texels | Mode::Samples, Quantity::IlluminanceDirect) => "illuminanceDirect",
            (Mode::Texels | Mode::Samples, Quantity::Luminance) => "luminance Y",
            _ => self.label(),
        }
    }

    pub(crate) fn unit(self) -> &'static str {
        match self {
            Quantity::Luminance => "cd/m²",
            _ => "lx",
        }
    }

    /// A tolerance term given in lx (atol, floor) in this quantity's unit.
    fn in_unit(self, lx: f64) -> f64 {
        match self {
            Quantity::Luminance => lx / PI,
            _ => lx,
        }
    }

    /// A vertex attribute's values (empty for probe quantities).
    fn values(self, p: &crate::readback::Primitive) -> &[f32] {
        match self {
            Quantity::Illuminance => &p.illuminance,
            Quantity::IlluminanceDirect => &p.illuminance_direct,
            Quantity::Luminance => &p.luminance,
            Quantity::ProbeFaces | Quantity::WorkingPlane => &[],
        }
    }

    /// Texel `k`'s value (0 for probe quantities).
    fn texel(self, lm: &crate::readback::Lightmap, k: usize) -> f64 {
        match self {
            Quantity::Illuminance => lm.illuminance[k].into(),
            Quantity::IlluminanceDirect => lm.illuminance_direct[k].into(),
            Quantity::Luminance => lm.luminance_y(k),
            Quantity::ProbeFaces | Quantity::WorkingPlane => 0.0,
        }
    }
}

/// Max, mean and p95 of a set of differences (all 0 for an empty set).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Stats {
    pub max: f64,
    pub mean: f64,
    pub p95: f64,
}

/// The figures of one group of values (a node, a material, or all of a quantity).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Group {
    pub name: String,
    pub values: usize,
    pub failed: usize,
    /// |a − b| in the quantity's unit.
    pub abs: Stats,
    /// |a − b| / max(|b|, floor).
    pub rel: Stats,
}

/// One quantity's figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct QuantityDiff {
    /// `illuminance`, `illuminanceDirect`, `luminance`, `probeFaces` or `workingPlane`.
    pub quantity: &'static str,
    pub unit: &'static str,
    /// atol and floor in this quantity's unit.
    pub atol: f64,
    pub floor: f64,
    /// All values of the quantity (`name` is `all`).
    pub overall: Group,
    /// Per node (path; a repeated path gets ` [k]`): baked nodes in A's order for the three
    /// attributes, probe nodes for `probeFaces`, none for `workingPlane`.
    pub by_node: Vec<Group>,
    /// Per material (B's names, in B's order), for the three attributes only.
    pub by_material: Vec<Group>,
}

/// One compared value and where it is.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Place {
    pub quantity: &'static str,
    /// `vertex`, `texel`, `sample`, `probe`, `nodeMean` or `materialMean`.
    pub kind: &'static str,
    /// Node path (`null` for a material mean).
    pub node: Option<String>,
    /// Material name in B (vertex and material mean only).
    pub material: Option<String>,
    /// Primitive of the node (vertex, texel and sample).
    pub primitive: Option<usize>,
    /// Vertex index in the primitive (vertex, and a sample at a vertex).
    pub vertex: Option<usize>,
    /// Triangle index in the primitive (a sample at a triangle's centroid only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangle: Option<usize>,
    /// Atlas number (texel only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub atlas: Option<usize>,
    /// Column and row in the atlas, row 0 at the top (texel only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texel: Option<[u32; 2]>,
    /// Probe face `+x` … `-z` (probe only).
    pub face: Option<&'static str>,
    /// World position in B (m, +Y up): a texel's centre on its triangle; a mean's area-weighted
    /// centroid.
    pub position: [f64; 3],
    pub a: f64,
    pub b: f64,
    pub abs: f64,
    pub rel: f64,
    /// atol + rtol·max(|b|, floor), in the quantity's unit.
    pub tolerance: f64,
    pub pass: bool,
}

/// The comparison of A with B.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Diff {
    pub a: String,
    pub b: String,
    /// What was compared (`texels` or `samples` where vertices mode met two lightmapped bakes).
    pub mode: Mode,
    /// How lightmaps were taken (absent from the JSON when neither bake has lightmaps).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lightmaps: Option<String>,
    pub rtol: f64,
    /// lx.
    pub atol: f64,
    /// lx.
    pub floor: f64,
    /// Whether the floor is the default (1 % of B's p99 of `_ILLUMINANCE`).
    pub floor_is_default: bool,
    /// Every value within tolerance.
    pub pass: bool,
    /// Values compared and failed, over all quantities except `workingPlane` (whose values are
    /// also `probeFaces` values).
    pub values: usize,
    pub failed: usize,
    /// Always all five, in the order of [`Quantity::ALL`].
    pub quantities: Vec<QuantityDiff>,
    /// The worst differing values (|a − b| > 0), worst first: by |a − b| / tolerance, then by
    /// the relative difference; at most `--worst N`.
    pub worst: Vec<Place>,
    /// The worst value outside tolerance (`null` when all pass), even with `--worst 0`.
    pub worst_failure: Option<Place>,
}

impl Diff {
    /// The diff as pretty JSON (ends with a newline).
    pub fn json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("the diff serialises");
        s.push('\n');
        s
    }

    /// One quantity's figures.
    pub fn quantity(&self, q: Quantity) -> &QuantityDiff {
        &self.quantities[Quantity::ALL.iter().position(|x| *x == q).expect("in ALL")]
    }
}
