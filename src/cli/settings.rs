//! The options of what a bake computes and how (`bake`, `bake shard …` and `bake fit` share
//! them), turned into validated [`Settings`] before any work.

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use luxbake::progress::Progress;
use luxbake::settings::{Exposure, LightmapSettings, Quality, Settings};

/// What the bake computes and how: the options `bake`, `bake shard …` and `bake fit` share.
#[derive(Args, Debug)]
pub struct SettingsArgs {
    /// Speed/accuracy trade-off.
    #[arg(long, value_enum, default_value_t = QualityArg::Default)]
    quality: QualityArg,
    /// Patch edge length in metres (overrides the size derived from --quality).
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    patch_size: Option<f64>,
    /// Patches of one size everywhere (default: adaptive — coarse where light is smooth,
    /// fine at shadow edges, steep gradients and contact lines).
    #[arg(long)]
    uniform_patches: bool,
    /// Trace shadow rays even inside a convex empty enclosure (to measure what skipping saves).
    #[arg(long, hide = true)]
    always_trace: bool,
    /// Gather light from black surfaces like any other (to measure what skipping them saves).
    #[arg(long, hide = true)]
    gather_black: bool,
    /// Far-field acceptance ratio, radius/distance (overrides the one of --quality).
    #[arg(long, value_name = "RATIO", hide = true, allow_negative_numbers = true)]
    far_field: Option<f64>,
    /// Light cut: far luminaires as bounded clusters within this fraction of the direct light
    /// at each receiver and patch (0: every luminaire summed exactly).
    #[arg(
        long,
        value_name = "FRACTION",
        hide = true,
        allow_negative_numbers = true
    )]
    light_cut_fraction: Option<f64>,
    /// Direct light from far groups of luminaires that no proof settles, and that could give at
    /// most this fraction of the direct light summed before them, takes its visibility from two
    /// shadow rays (default per quality: 0.03, 0.01, 0.003).
    #[arg(long, value_name = "FRACTION", allow_negative_numbers = true)]
    direct_budget: Option<f64>,
    /// Trace every luminaire's visibility (the direct-light budget 0).
    #[arg(long, conflicts_with = "direct_budget")]
    exact_direct: bool,
    /// Worker threads (default: all cores; more than the cores are clamped with a warning).
    /// The output does not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Most patches the bake may make (default: what 3/4 of the machine's memory holds at
    /// about 6 KiB a patch); the run is refused before meshing when the estimate is above.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    max_patches: Option<u64>,
    /// Most probes (grid points included) the bake may measure (default: as for patches).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    max_probes: Option<u64>,
    /// Display exposure: 'auto' or the illuminance in lx shown as white in COLOR_0.
    #[arg(long, default_value = "auto", allow_hyphen_values = true)]
    exposure: String,
    /// Keep the input materials instead of switching them to KHR_materials_unlit.
    #[arg(long)]
    keep_lit_materials: bool,
    /// Also bake lightmaps: per atlas an OpenEXR file beside the output (R, G, B luminance in
    /// cd/m², illuminance and illuminanceDirect in lx, footprint in m²) and a display PNG in it,
    /// laid out on TEXCOORD_1.
    #[arg(long)]
    lightmaps: bool,
    /// Lightmap texel edge in metres (default per --quality: draft 0.1, default 0.05, high
    /// 0.025, at most a quarter patch; coarser where the count would pass 0.25/1/4 million).
    #[arg(
        long,
        value_name = "METRES",
        requires = "lightmaps",
        allow_negative_numbers = true
    )]
    texel_size: Option<f64>,
    /// Largest lightmap atlas edge in texels; more atlases when one is full.
    #[arg(
        long,
        value_name = "PX",
        default_value_t = LightmapSettings::default().max_size,
        requires = "lightmaps"
    )]
    lightmap_size: u32,
    /// Fraction of the illuminance by which interpolated inter-reflected light may miss a check
    /// gather (default per quality: 0.03, 0.01, 0); 0 gathers at every texel.
    #[arg(long, value_name = "FRACTION", requires = "lightmaps", hide = true)]
    lightmap_tolerance: Option<f64>,
    /// Vertices read nearby vertices' gathers where the first-bounce light spreads across them by
    /// at most this fraction of the illuminance (default per quality: 0.03, 0.01, 0); 0 gathers
    /// at every vertex.
    #[arg(long, value_name = "FRACTION")]
    receiver_tolerance: Option<f64>,
    /// Record stage timings in the output's extras (makes bakes differ from run to run).
    #[arg(long)]
    timings_in_output: bool,
    #[command(flatten)]
    pub probes: super::probes::ProbeArgs,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum QualityArg {
    Draft,
    Default,
    High,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum UpArg {
    Y,
    Z,
}

/// The settings' worker threads (a warning when more than the cores were asked for).
pub fn worker_pool(settings: &Settings, progress: &dyn Progress) -> Result<rayon::ThreadPool> {
    let (threads, clamped) = settings.worker_threads();
    if let Some(w) = clamped {
        progress.warn(&w);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start worker threads")
}

/// Validate the raw arguments into settings (no work done yet).
pub fn settings(args: &SettingsArgs) -> Result<Settings> {
    let exposure = match args.exposure.trim() {
        "auto" => Exposure::Auto,
        s => Exposure::White {
            lux: s.parse().map_err(|_| {
                luxbake::Error::Settings(format!(
                    "--exposure must be 'auto' or an illuminance in lx, got '{s}'"
                ))
            })?,
        },
    };
    let mut settings = Settings {
        quality: match args.quality {
            QualityArg::Draft => Quality::Draft,
            QualityArg::Default => Quality::Default,
            QualityArg::High => Quality::High,
        },
        patch_size: args.patch_size,
        far_field: args.far_field,
        exposure,
        keep_lit_materials: args.keep_lit_materials,
        threads: args.threads,
        max_patches: args.max_patches,
        max_probes: args.max_probes,
        record_timings: args.timings_in_output,
        uniform_patches: args.uniform_patches,
        always_trace: args.always_trace,
        gather_black: args.gather_black,
        receiver_tolerance: args.receiver_tolerance,
        lightmaps: args.lightmaps.then_some(LightmapSettings {
            texel_size: args.texel_size,
            max_size: args.lightmap_size,
            tolerance: args.lightmap_tolerance,
        }),
        ..Settings::default()
    };
    if let Some(f) = args.light_cut_fraction {
        settings.light_cut = f;
    }
    settings.direct_budget = match args.exact_direct {
        true => Some(0.0),
        false => args.direct_budget,
    };
    args.probes.apply(&mut settings)?;
    settings.validate()?;
    Ok(settings)
}
