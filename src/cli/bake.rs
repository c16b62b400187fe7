//! `bake IN -o OUT`: raw arguments → validated [`Settings`] → import → bake → export, with a
//! progress bar on stderr (when it is a terminal) and a short summary; with `--report`, the
//! lighting report on stdout (made by `cli::report`, the code path of `bake report`).

use super::progress::CliProgress;
use super::report::{ByArg, FormatArg};
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use luxbake::export::atomic::Batch;
use luxbake::export::{self, ExportOptions};
use luxbake::import::{self, ImportOptions, UpAxis};
use luxbake::progress::Progress;
use luxbake::settings::{Exposure, LightmapSettings, Quality, Settings};
use luxbake::summary::{RunRecord, RunSummary};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The main job: bake a scene.
#[derive(Args, Debug)]
pub struct BakeArgs {
    /// Input scene: .gltf, .glb or .obj (with its .mtl).
    #[arg(required = true)]
    input: Option<PathBuf>,
    /// Output file: .gltf (+ .bin beside it) or .glb.
    #[arg(short, long, required = true)]
    output: Option<PathBuf>,
    #[command(flatten)]
    pub settings: SettingsArgs,
    /// Up axis of an OBJ input (glTF is always +Y up).
    #[arg(long, value_enum, default_value_t = UpArg::Y)]
    obj_up: UpArg,
    /// No progress bar and no summary on stderr (errors and warnings still print).
    #[arg(short, long)]
    quiet: bool,
    /// Also write the run summary (settings, counts, energy balance, timings) as JSON here.
    #[arg(long, value_name = "FILE")]
    summary_json: Option<PathBuf>,
    /// Print the lighting report after baking, as `bake report OUT` would (FORMAT: table,
    /// markdown, csv, json; default table).
    #[arg(long, value_enum, value_name = "FORMAT", num_args = 0..=1, default_missing_value = "table")]
    report: Option<FormatArg>,
    /// Write the report to this file instead of standard output (implies --report).
    #[arg(long, value_name = "FILE")]
    report_out: Option<PathBuf>,
    /// The report's surface sections (implies --report; default both).
    #[arg(long, value_enum, value_name = "BY")]
    report_by: Option<ByArg>,
    /// Design targets for the report: a JSON object of average illuminances in lx (implies
    /// --report).
    #[arg(long, value_name = "FILE")]
    targets: Option<PathBuf>,
    /// Distributed bake, step 1: mesh and light the scene, write the state and the task list
    /// to DIR (state.bin, plan.json); no output yet. `dist/dask_bake.py` runs the three steps
    /// on a Dask cluster.
    #[arg(long, value_name = "DIR", help_heading = "Distributed bake",
          conflicts_with_all = ["shard_gather", "shard_merge"])]
    shard_plan: Option<PathBuf>,
    /// Number of tasks of --shard-plan (whole surfaces each; the output does not depend on it).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 2,
        help_heading = "Distributed bake"
    )]
    shard_tasks: usize,
    /// Step 2, anywhere the input and DIR are: gather the rows of task --shard-task K of the
    /// plan in DIR (DIR/task-K.bin). Run it with the plan's options.
    #[arg(
        long,
        value_name = "DIR",
        help_heading = "Distributed bake",
        requires = "shard_task",
        conflicts_with = "shard_merge"
    )]
    shard_gather: Option<PathBuf>,
    #[arg(
        long,
        value_name = "K",
        help_heading = "Distributed bake",
        requires = "shard_gather"
    )]
    shard_task: Option<usize>,
    /// Step 3: read the plan and every task's rows from DIR and finish the bake into OUTPUT,
    /// byte for byte the output of the same bake in one process.
    #[arg(long, value_name = "DIR", help_heading = "Distributed bake")]
    shard_merge: Option<PathBuf>,
}

/// What the bake computes and how: the options `bake` and `bake fit` share.
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

/// Run the bake (the input and output are present: clap requires them without a subcommand).
pub fn run(args: &BakeArgs) -> Result<()> {
    let (Some(input), Some(output)) = (&args.input, &args.output) else {
        return Err(luxbake::Error::Settings(
            "an input scene and -o OUTPUT are required (see bake --help)".into(),
        )
        .into());
    };
    let start = Instant::now();
    let settings = settings(&args.settings)?;
    let mut progress = CliProgress::new(!args.quiet && std::io::stderr().is_terminal());
    if args.summary_json.is_some() {
        progress = progress.trace_memory("import");
    }
    let obj_up = match args.obj_up {
        UpArg::Y => UpAxis::Y,
        UpArg::Z => UpAxis::Z,
    };
    // Every output against the inputs named on the command line and each other, before any
    // work; again with every file the import read once it is done.
    let read: Vec<&Path> = [Some(input.as_path()), args.targets.as_deref()]
        .into_iter()
        .flatten()
        .chain(args.settings.probes.in_path())
        .collect();
    let extra: Vec<&Path> = args
        .summary_json
        .iter()
        .chain(&args.report_out)
        .map(|p| p.as_path())
        .chain(args.settings.probes.out_path())
        .collect();
    export::check_run(output, &luxbake::scene::Scene::default(), &read, &extra)?;
    let scene = import::load(input, &ImportOptions { obj_up })?;
    let wants_report = args.report.is_some()
        || args.report_out.is_some()
        || args.report_by.is_some()
        || args.targets.is_some();
    let report_options = wants_report
        .then(|| {
            super::report::options(
                args.report_by.unwrap_or(ByArg::Both),
                args.targets.as_deref(),
            )
        })
        .transpose()?;
    if let Some(t) = report_options.as_ref().and_then(|o| o.targets.as_ref())
        && t.wants_working_plane()
        && settings.working_plane.is_none()
    {
        return Err(t.no_working_plane().into());
    }
    export::check_run(output, &scene, &read, &extra)?;
    for w in &scene.warnings {
        progress.warn(w);
    }
    let pool = worker_pool(&settings, &progress)?;
    if let Some(dir) = &args.shard_plan {
        let tasks = args.shard_tasks;
        return pool.install(|| super::shard::plan(dir, tasks, &scene, &settings, &progress));
    }
    if let (Some(dir), Some(k)) = (&args.shard_gather, args.shard_task) {
        return pool.install(|| super::shard::gather(dir, k, &scene, &settings, &progress));
    }
    let result = match &args.shard_merge {
        Some(dir) => pool.install(|| super::shard::merge(dir, &scene, &settings, &progress))?,
        None => pool.install(|| luxbake::bake::bake(&scene, &settings, &progress))?,
    };
    progress.mark("output");
    let options = ExportOptions {
        unlit: !settings.keep_lit_materials,
        probe_glyphs: settings
            .probe_glyphs
            .then(|| export::glyph_scale(&settings)),
    };
    // One batch: the lightmaps, the .bin and the glTF (its rename commits the set), then the
    // probes, summary and report files, each renamed after the glTF.
    let mut batch = Batch::default();
    let prepared =
        pool.install(|| export::Prepared::staged(output, &scene, &result, &options, &mut batch))?;
    // The report is made from the bytes about to be written, before anything is renamed (a bad
    // target fails the run cleanly).
    let report_text = match &report_options {
        Some(o) => {
            let baked = luxbake::baked::from_prepared(output, &prepared)?;
            let format = args.report.unwrap_or(FormatArg::Table);
            Some(super::report::render(&baked, o, format)?)
        }
        None => None,
    };
    let staged = prepared.stage(&scene, &mut batch)?;
    args.settings.probes.stage_out(&result.probes, &mut batch)?;
    let total = start.elapsed().as_secs_f64();
    if let Some(path) = &args.summary_json {
        let summary = RunSummary {
            timings_seconds: Some(result.timings),
            ..result.summary.clone()
        };
        let memory = progress.memory();
        let record = RunRecord {
            summary: &summary,
            input,
            output,
            threads: pool.current_num_threads(),
            total_seconds: total,
            memory_kib: &memory,
        };
        batch.stage(path, &export::summary::bytes(&record))?;
    }
    if let (Some(text), Some(path)) = (&report_text, &args.report_out) {
        batch.stage(path, text.as_bytes())?;
    }
    staged.commit(batch, &extra)?;
    progress.done();
    if !args.quiet {
        report(&result.summary, output, total);
        super::probes::report(&result.probes);
    }
    if let (Some(text), None) = (report_text, &args.report_out) {
        print!("{text}");
    }
    Ok(())
}

/// A few lines on stderr: what was baked and how well.
fn report(s: &RunSummary, output: &Path, seconds: f64) {
    let (c, e) = (&s.counts, &s.energy);
    eprintln!(
        "baked {} patches, {} receivers in {seconds:.2} s → {}",
        c.patches,
        c.receivers,
        output.display()
    );
    eprintln!(
        "  emitted {:.1} lm, absorbed {:.1} lm, escaped {:.1} lm, balance error {:.2e}; solver residual {:.1e} after {} iterations",
        e.emitted_lm,
        e.absorbed_lm,
        e.escaped_lm,
        e.balance_error_relative,
        s.solver.relative_residual,
        s.solver.iterations,
    );
}
