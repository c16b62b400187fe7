//! The run summary: what a bake records about itself, one typed tree. The pipeline fills it, the
//! exporter writes it (the output scene's `extras.luxbake`, `--summary-json`), and whoever reads a
//! finished bake gets it back typed (`readback::read`).
//!
//! The serde form is the file format: field names and their order are what outputs hold, so a
//! change here is a change of format. Reading is strict: a field an older output lacks is an
//! error naming it, never a default. Fields that may be `null` are written as `null`, not left
//! out ([`required`]).

pub use crate::gmres::SolveStats;
use crate::settings::{Exposure, ProbeGrid, Quality, QualityParams, Settings};
pub use crate::transport::operator::BalanceStats;
use serde::{Deserialize, Deserializer, Serialize};

/// The run summary of one bake.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct RunSummary {
    /// `luxbake <version>`.
    pub tool: String,
    pub settings: SettingsRecord,
    /// What the quality level meant in numbers (with the settings' overrides).
    pub quality: QualityParams,
    /// Longest patch edge of the uniform mesh (m).
    pub patch_size: f64,
    pub counts: Counts,
    /// `null` for uniform patches (or a scene with nothing to adapt to).
    #[serde(deserialize_with = "required")]
    pub adaptive_meshing: Option<MeshingRecord>,
    /// Where surfaces cover one another (absent from bakes made before contacts were found).
    #[serde(default)]
    pub contacts: ContactsRecord,
    pub solver: SolveStats,
    pub balancing: BalanceStats,
    pub energy: EnergyBalance,
    /// Every light, luminaire and profiled emitting surface, in the bake's order.
    pub sources: Vec<SourceRecord>,
    pub exposure: ExposureRecord,
    pub units: Units,
    /// The lightmaps' layout and how their texels were read (`--lightmaps`; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lightmaps: Option<LightmapRecord>,
    /// Wall-clock seconds per stage: only when asked for (`--timings-in-output`), since they make
    /// bakes differ run to run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timings_seconds: Option<StageSeconds>,
}

/// The settings a bake ran with, as the summary records them (the settings that change the
/// result; thread count and testing switches are left out).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct SettingsRecord {
    pub quality: Quality,
    /// m; `null`: derived from the quality.
    #[serde(deserialize_with = "required")]
    pub patch_size: Option<f64>,
    /// Far-field ratio overriding the quality's; `null`: none.
    #[serde(deserialize_with = "required")]
    pub far_field: Option<f64>,
    pub exposure: Exposure,
    pub keep_lit_materials: bool,
    pub uniform_patches: bool,
    /// `--receiver-tolerance` as asked (absent: the quality's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub receiver_tolerance: Option<f64>,
    #[serde(deserialize_with = "required")]
    pub probe_grid: Option<ProbeGrid>,
    /// The working plane (height above the floor and spacing, m); `null`: none.
    #[serde(deserialize_with = "required")]
    pub working_plane: Option<ProbeGrid>,
    pub probe_glyphs: bool,
    /// `--lightmaps` as asked (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lightmaps: Option<crate::settings::LightmapSettings>,
    /// The light cut's fraction (`--light-cut-fraction`; absent: 0, every luminaire summed).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub light_cut: f64,
    /// The direct-light budget as asked (`--direct-budget`, `--exact-direct`: 0; absent: the
    /// quality's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direct_budget: Option<f64>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl From<&Settings> for SettingsRecord {
    fn from(s: &Settings) -> Self {
        SettingsRecord {
            quality: s.quality,
            patch_size: s.patch_size,
            far_field: s.far_field,
            exposure: s.exposure,
            keep_lit_materials: s.keep_lit_materials,
            uniform_patches: s.uniform_patches,
            receiver_tolerance: s.receiver_tolerance,
            probe_grid: s.probe_grid,
            working_plane: s.working_plane,
            probe_glyphs: s.probe_glyphs,
            lightmaps: s.lightmaps,
            light_cut: s.light_cut,
            direct_budget: s.direct_budget,
        }
    }
}

/// How big the bake was and how much it traced.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Counts {
    /// Surfaces of the scene (one per node instance and triangle primitive).
    pub surfaces: usize,
    pub patches: usize,
    /// Vertices of the patch mesh, where light is gathered.
    pub receivers: usize,
    /// Links of all receivers' gather rows, and of those the two-sided cluster links.
    pub links: usize,
    pub cluster_links: usize,
    /// Receivers whose rows were normalised because they are enclosed.
    pub closed_receivers: usize,
    /// Receivers that gathered their own rows; the others read a blend of those
    /// (`transport::sharing`).
    #[serde(default)]
    pub gathered_receivers: usize,
    /// Shadow and escape rays traced, in all and by stage.
    pub rays: u64,
    pub rays_by_stage: RaysByStage,
    /// The scene is one convex empty enclosure: no visibility rays were needed.
    pub convex_empty_scene: bool,
}

/// Rays traced by each stage of the bake (up to and including the energy report).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct RaysByStage {
    pub meshing: u64,
    pub direct_at_receivers: u64,
    pub direct_into_patches: u64,
    pub links: u64,
    pub energy: u64,
}

impl RaysByStage {
    /// All of them.
    pub fn total(&self) -> u64 {
        self.meshing
            + self.direct_at_receivers
            + self.direct_into_patches
            + self.links
            + self.energy
    }
}

/// What adaptive meshing did (see `bake::meshing`); lengths in m, illuminance in lx.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct MeshingRecord {
    pub coarse_patch_size: f64,
    pub smallest_patch_size: f64,
    pub coarse_patches: usize,
    /// The split rule: relative to the local level, and to the scene's mean direct light.
    pub relative: f64,
    pub absolute: f64,
    pub contact_distance: f64,
    pub indirect_estimate_lx: f64,
}

/// What the contacts found: surfaces covering others (a cube's bottom on a floor, a panel on a
/// ceiling), whose covered parts take no part in the light transport.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ContactsRecord {
    /// The largest gap between parallel faces counted as contact (m).
    pub gap_m: f64,
    /// Covering triangles over covered ones (pairs).
    pub covers: usize,
    /// Area of the covered parts, all sides (m²).
    pub covered_area_m2: f64,
}

/// What `--lightmaps` made.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct LightmapRecord {
    /// Texel edge of the layout (m).
    pub texel_size_m: f64,
    /// Largest atlas edge allowed (texels).
    pub max_size: u32,
    /// Each atlas's size in texels.
    pub atlases: Vec<[u32; 2]>,
    /// Texels standing for some surface (the rest is padding).
    pub texels: usize,
    /// Charts made, and how many surfaces kept their own `TEXCOORD_1` layout.
    pub charts: usize,
    pub kept_input_layouts: usize,
    /// Surfaces laid out coarser than `texelSizeM` to fit one atlas, and their texel edges (m).
    pub coarser: Vec<CoarserSurface>,
    /// Texels whose inter-reflected light was gathered at the texel rather than interpolated
    /// from the vertices' gathers.
    pub gathered_texels: usize,
}

/// A surface laid out coarser than asked, to fit one atlas.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct CoarserSurface {
    pub surface: usize,
    pub texel_size_m: f64,
}

/// The energy report: photometric fluxes in lm, each measured on its own (see `bake::energy`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct EnergyBalance {
    pub emitted_lm: f64,
    pub emitted_by_lights_lm: f64,
    pub emitted_by_surfaces_lm: f64,
    pub direct_received_lm: f64,
    pub reflected_lm: f64,
    pub absorbed_lm: f64,
    pub escaped_lm: f64,
    /// Of which: straight from punctual lights, and from surfaces (emitted or reflected).
    pub escaped_from_lights_lm: f64,
    pub escaped_from_surfaces_lm: f64,
    /// emitted − absorbed − escaped.
    pub balance_error_lm: f64,
    /// |balance error| / emitted.
    pub balance_error_relative: f64,
}

/// One light, luminaire or profiled emitting surface.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct SourceRecord {
    pub kind: SourceKind,
    #[serde(deserialize_with = "required")]
    pub name: Option<String>,
    /// Where it is defined: a JSON pointer into the input.
    pub source: String,
    /// lm (for a directional light: what the scene intercepts).
    pub emitted_lm: f64,
    /// Direct flux it put onto surfaces, front and back, as integrated (lm).
    pub reached_surfaces_lm: f64,
    /// The factor its direct flux into patches was scaled by so that they receive all it emits
    /// (a source in a closed scene: `bake::direct::closure`); 1 when none was applied.
    pub closure: f64,
    /// Luminaires only.
    #[serde(flatten)]
    pub luminaire: Option<LuminaireRecord>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum SourceKind {
    #[default]
    Point,
    Spot,
    Directional,
    Luminaire,
    ProfiledSurface,
}

/// A luminaire's profile and what its rating says.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct LuminaireRecord {
    #[serde(deserialize_with = "required")]
    pub profile: Option<String>,
    pub multiplier: f64,
    /// Rated lamp flux × the multiplier (lm); `null` for absolute photometry.
    #[serde(deserialize_with = "required")]
    pub rated_lamp_lm: Option<f64>,
    /// Light output ratio of the profile; `null` for absolute photometry.
    #[serde(deserialize_with = "required")]
    pub light_output_ratio: Option<f64>,
}

/// How `COLOR_0` was exposed (see `bake::display`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ExposureRecord {
    pub mode: ExposureMode,
    pub white_illuminance_lx: f64,
    /// The display rule, in words.
    pub rule: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ExposureMode {
    #[default]
    Auto,
    Fixed,
}

/// The units and up axis every value of the output is in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Units {
    pub illuminance: String,
    pub luminance: String,
    pub flux: String,
    pub length: String,
    pub up: String,
}

impl Default for Units {
    fn default() -> Self {
        let s = |x: &str| x.to_string();
        Units {
            illuminance: s("lx"),
            luminance: s("cd/m2"),
            flux: s("lm"),
            length: s("m"),
            up: s("+Y"),
        }
    }
}

/// Resident memory of one stage of a run (the `--summary-json` file only: it varies run to run).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct StageMemory {
    /// The stage as the progress reports name it (`import` before the first, `output` after
    /// the last).
    pub stage: String,
    /// The largest resident size while the stage ran, KiB.
    pub peak_kib: u64,
    /// Resident at its end, KiB.
    pub resident_kib: u64,
}

/// Wall-clock seconds of each stage of the bake.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct StageSeconds {
    pub mesh: f64,
    pub direct: f64,
    pub links: f64,
    pub solve: f64,
    pub energy: f64,
    pub probes: f64,
    pub output: f64,
    #[serde(default)]
    pub lightmaps: f64,
}

impl StageSeconds {
    /// The stages in order, with their names.
    pub fn named(&self) -> [(&'static str, f64); 8] {
        [
            ("mesh", self.mesh),
            ("direct", self.direct),
            ("links", self.links),
            ("solve", self.solve),
            ("energy", self.energy),
            ("probes", self.probes),
            ("output", self.output),
            ("lightmaps", self.lightmaps),
        ]
    }
}

/// What `--summary-json` holds: the summary, and what only this run knows.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct RunRecord<'a> {
    #[serde(flatten)]
    pub summary: &'a RunSummary,
    pub input: &'a std::path::Path,
    pub output: &'a std::path::Path,
    pub threads: usize,
    pub total_seconds: f64,
    /// Per stage, in order; empty (and left out) where it cannot be measured.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub memory_kib: &'a [StageMemory],
}

/// An `Option` field that must be present (possibly `null`): serde would otherwise read a
/// missing `Option` as `None`.
pub(crate) fn required<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    Option::<T>::deserialize(d)
}
