//! Validated bake settings. The CLI turns its raw arguments into a [`Settings`] (checking every
//! value) before any work starts; library users build one directly.

use crate::error::{Error, Result};
pub use crate::probes::{Probe, ProbeGrid};

/// Speed/accuracy trade-off. Each level fixes the patch count target, the far-field acceptance
/// ratio and the solver tolerance (see [`Quality::params`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Quality {
    Draft,
    #[default]
    Default,
    High,
}

/// What a quality level means in numbers.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct QualityParams {
    /// Patch size is √(total area / this), unless `--patch-size` overrides it.
    pub target_patches: f64,
    /// Far-field acceptance: a cluster is one source when radius/distance < tau.
    pub tau: f64,
    /// Same for direct light from emitting surfaces.
    pub tau_direct: f64,
    /// Relative residual at which the solver stops.
    pub tolerance: f64,
}

impl Quality {
    pub(crate) fn params(self) -> QualityParams {
        match self {
            Quality::Draft => QualityParams {
                target_patches: 2_000.0,
                tau: 0.45,
                tau_direct: 0.2,
                tolerance: 1e-5,
            },
            Quality::Default => QualityParams {
                target_patches: 8_000.0,
                tau: 0.3,
                tau_direct: 0.1,
                tolerance: 1e-7,
            },
            Quality::High => QualityParams {
                target_patches: 32_000.0,
                tau: 0.2,
                tau_direct: 0.05,
                tolerance: 1e-9,
            },
        }
    }
}

impl Quality {
    /// The default lightmap texel edge (m) and the most texels the default may make: the texel
    /// is this edge, at most a quarter patch, and at least what keeps the count under the cap.
    pub(crate) fn lightmap_texel(self) -> (f64, f64) {
        match self {
            Quality::Draft => (0.1, 250_000.0),
            Quality::Default => (0.05, 1_000_000.0),
            Quality::High => (0.025, 4_000_000.0),
        }
    }

    /// How far the first-bounce light may spread across the gathered receivers a vertex reads
    /// (fraction of its illuminance) for it to read their rows instead of gathering its own
    /// (`transport::sharing`); 0 gathers at every vertex.
    pub(crate) fn receiver_tolerance(self) -> f64 {
        match self {
            Quality::Draft => 0.03,
            Quality::Default => 0.01,
            Quality::High => 0.0,
        }
    }

    /// How far a lightmap triangle's interpolated inter-reflected light may miss a gather at
    /// its middle texel (fraction of the texel's illuminance) before every texel is gathered.
    pub(crate) fn lightmap_tolerance(self) -> f64 {
        match self {
            Quality::Draft => 0.03,
            Quality::Default => 0.01,
            Quality::High => 0.0,
        }
    }

    /// The direct-light budget (`direct::cut`, [`Settings::direct_budget`]): a group of
    /// luminaires no proof settles takes its visibility from two rays when its light could be
    /// at most this fraction of the direct light summed before it.
    pub(crate) fn direct_budget(self) -> f64 {
        match self {
            Quality::Draft => 0.03,
            Quality::Default => 0.01,
            Quality::High => 0.003,
        }
    }
}

/// How baked illuminance maps to the display colour `COLOR_0`.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", tag = "mode")]
pub enum Exposure {
    /// The area-weighted 95th percentile of illuminance on non-emitting surfaces shows at 0.8.
    #[default]
    Auto,
    /// This illuminance (lx) shows as full white (1.0) before the soft shoulder.
    White { lux: f64 },
}

/// How to bake, and where to measure besides the vertices. What of it changes the result is
/// recorded in the run summary (`summary::SettingsRecord`), which is the file format; this struct
/// is not.
#[derive(Debug, Clone)]
pub struct Settings {
    pub quality: Quality,
    /// Patch edge length in metres; `None` derives it from the quality.
    pub patch_size: Option<f64>,
    /// Far-field acceptance ratio (radius/distance) overriding the quality's `tau`.
    pub far_field: Option<f64>,
    pub exposure: Exposure,
    /// Keep the input materials instead of switching them to KHR_materials_unlit.
    pub keep_lit_materials: bool,
    /// Worker threads (`None`: all cores). Never affects the output.
    pub threads: Option<usize>,
    /// Record wall-clock timings in the output's extras (they make bakes differ run to run).
    pub record_timings: bool,
    /// Trace shadow rays even where the scene is a convex empty enclosure (testing).
    pub always_trace: bool,
    /// Gather from black patches like any other (testing: what skipping them saves).
    pub gather_black: bool,
    /// Patches of one size everywhere instead of adaptive meshing (see `bake::meshing`).
    pub uniform_patches: bool,
    /// Vertices share gathers where the light's estimate spreads by at most this fraction
    /// (`--receiver-tolerance`); `None`: the quality's; 0 gathers at every vertex.
    pub receiver_tolerance: Option<f64>,
    /// A grid of probes over the floor (`--probe-grid SPACING --probe-height H`).
    pub probe_grid: Option<ProbeGrid>,
    /// Probes given explicitly (read from a `--probes` CSV file by the caller).
    pub extra_probes: Vec<Probe>,
    /// The working plane of the report: a grid of upward-facing probes at this height above the
    /// floor (m), and its spacing.
    pub working_plane: Option<ProbeGrid>,
    /// Add a glyph mesh per probe (illumination vector arrow, symmetric sphere) to the output.
    pub probe_glyphs: bool,
    /// Bake lightmap atlases too (`--lightmaps`).
    pub lightmaps: Option<LightmapSettings>,
    /// Most patches a bake may make (`--max-patches`; `None`: what the machine's memory holds,
    /// see `bake::budget`). Never affects the output of a bake it allows.
    pub max_patches: Option<u64>,
    /// Most probes (`--max-probes`; `None`: as for patches).
    pub max_probes: Option<u64>,
    /// Light cut (`direct::cut`): far groups of luminaires proved visible are evaluated as
    /// bounded clusters while the summed bound stays within this fraction of the direct light at
    /// the receiver; 0 sums every luminaire exactly.
    pub light_cut: f64,
    /// The direct-light budget (`--direct-budget`, `--exact-direct` for 0); `None`: the
    /// quality's ([`Quality::direct_budget`]).
    pub direct_budget: Option<f64>,
}

/// What `--lightmaps` asks for.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct LightmapSettings {
    /// Texel edge in metres; `None`: the quality's.
    pub texel_size: Option<f64>,
    /// Largest atlas edge in texels.
    pub max_size: u32,
    /// Inter-reflected light interpolated where a check gather misses by at most this fraction
    /// of the illuminance; `None`: the quality's; 0 gathers at every texel (benchmarks).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
}

impl Default for LightmapSettings {
    fn default() -> Self {
        LightmapSettings {
            texel_size: None,
            max_size: 2048,
            tolerance: None,
        }
    }
}

impl LightmapSettings {
    /// Texel edge `t` (m), the rest as default.
    pub fn with_texel(t: f64) -> Self {
        LightmapSettings {
            texel_size: Some(t),
            ..LightmapSettings::default()
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            quality: Quality::Default,
            patch_size: None,
            far_field: None,
            exposure: Exposure::Auto,
            keep_lit_materials: false,
            threads: None,
            record_timings: false,
            always_trace: false,
            gather_black: false,
            uniform_patches: false,
            receiver_tolerance: None,
            probe_grid: None,
            extra_probes: Vec::new(),
            working_plane: None,
            probe_glyphs: false,
            lightmaps: None,
            max_patches: None,
            max_probes: None,
            light_cut: 0.0,
            direct_budget: None,
        }
    }
}

impl Settings {
    /// The quality's numbers with this settings' overrides applied.
    pub(crate) fn params(&self) -> QualityParams {
        let mut p = self.quality.params();
        if let Some(t) = self.far_field {
            p.tau = t;
        }
        p
    }

    /// The direct-light budget in force.
    pub(crate) fn direct_budget(&self) -> f64 {
        (self.direct_budget).unwrap_or(self.quality.direct_budget())
    }

    /// Check every value; the bake assumes a validated `Settings`.
    pub fn validate(&self) -> Result<()> {
        if let Some(t) = self.receiver_tolerance
            && !(t.is_finite() && (0.0..1.0).contains(&t))
        {
            return Err(Error::Settings(format!(
                "--receiver-tolerance must be in [0, 1), got {t}"
            )));
        }
        if let Some(h) = self.patch_size
            && !(h.is_finite() && h > 0.0)
        {
            return Err(Error::Settings(format!(
                "--patch-size must be a positive length in metres, got {h}"
            )));
        }
        if let Some(t) = self.far_field
            && !(t.is_finite() && t > 0.0 && t < 1.0)
        {
            return Err(Error::Settings(format!(
                "--far-field must be in (0, 1), got {t}"
            )));
        }
        if !(self.light_cut.is_finite() && (0.0..=0.1).contains(&self.light_cut)) {
            return Err(Error::Settings(format!(
                "--light-cut-fraction must be in [0, 0.1], got {}",
                self.light_cut
            )));
        }
        if let Some(b) = self.direct_budget
            && !(b.is_finite() && (0.0..=0.1).contains(&b))
        {
            return Err(Error::Settings(format!(
                "--direct-budget must be in [0, 0.1], got {b}"
            )));
        }
        if let Exposure::White { lux } = self.exposure
            && !(lux.is_finite() && lux > 0.0)
        {
            return Err(Error::Settings(format!(
                "--exposure must be 'auto' or a positive illuminance in lx, got {lux}"
            )));
        }
        for (name, grid) in [
            ("--probe-grid", &self.probe_grid),
            ("--working-plane", &self.working_plane),
        ] {
            if let Some(g) = grid
                && !(g.spacing.is_finite() && g.spacing > 0.0 && g.height.is_finite())
            {
                return Err(Error::Settings(format!(
                    "{name}: spacing must be a positive length and height finite (m), got {} and {}",
                    g.spacing, g.height
                )));
            }
        }
        if let Some(l) = &self.lightmaps {
            if let Some(t) = l.texel_size
                && !(t.is_finite() && t > 0.0)
            {
                return Err(Error::Settings(format!(
                    "--texel-size must be a positive length in metres, got {t}"
                )));
            }
            if let Some(t) = l.tolerance
                && !(t.is_finite() && (0.0..1.0).contains(&t))
            {
                return Err(Error::Settings(format!(
                    "--lightmap-tolerance must be in [0, 1), got {t}"
                )));
            }
            if !(16..=16384).contains(&l.max_size) {
                return Err(Error::Settings(format!(
                    "--lightmap-size must be between 16 and 16384 texels, got {}",
                    l.max_size
                )));
            }
        }
        if self.threads == Some(0) {
            return Err(Error::Settings("--threads must be at least 1".into()));
        }
        for (name, n) in [
            ("--max-patches", self.max_patches),
            ("--max-probes", self.max_probes),
        ] {
            if n == Some(0) {
                return Err(Error::Settings(format!("{name} must be at least 1")));
            }
        }
        Ok(())
    }

    /// Worker threads to start: `threads`, at most the machine's cores (more only queue and
    /// cost memory), or all cores; with a warning when `threads` was clamped.
    pub fn worker_threads(&self) -> (usize, Option<String>) {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        match self.threads {
            None => (cores, None),
            Some(t) if t > cores => (
                cores,
                Some(format!(
                    "--threads {t} is more than this machine's {cores} cores: using {cores}"
                )),
            ),
            Some(t) => (t, None),
        }
    }
}
