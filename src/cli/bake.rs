//! `bake IN -o OUT` and the distributed bake's steps (`bake shard plan|gather|merge`): raw
//! arguments → a [`Job`] (validated settings, the step, every file read and written) → import →
//! bake (or one step of it) → export, with a progress bar on stderr (when it is a terminal) and a
//! short summary; with `--report`, the lighting report on stdout (made by `cli::report`, the code
//! path of `bake report`).

use super::progress::CliProgress;
use super::report::{ByArg, FormatArg};
use super::settings::{SettingsArgs, UpArg, settings, worker_pool};
use anyhow::Result;
use clap::{Args, Subcommand};
use luxbake::export::atomic::Batch;
use luxbake::export::{self, ExportOptions};
use luxbake::import::{self, ImportOptions, UpAxis};
use luxbake::progress::Progress;
use luxbake::report::Options as ReportOptions;
use luxbake::result::BakeResult;
use luxbake::scene::Scene;
use luxbake::settings::Settings;
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
}

/// The distributed bake's three steps. Each takes the bake's whole command line (IN, -o OUT and
/// every option, the same in all three: gather and merge refuse settings or a scene other than
/// the plan's) and the folder of the plan; plan and gather write only into it.
/// `dask/dask_bake.py` runs them on a Dask cluster.
#[derive(Args, Debug)]
pub struct ShardArgs {
    #[command(subcommand)]
    step: ShardStep,
}

#[derive(Subcommand, Debug)]
enum ShardStep {
    /// Step 1: mesh and light the scene, write the state and the task list to DIR (state.bin,
    /// plan.json); no output yet.
    Plan {
        /// The plan's folder (created if missing).
        #[arg(long, value_name = "DIR")]
        dir: PathBuf,
        /// Number of gather tasks (whole surfaces each; the output does not depend on it).
        #[arg(long, value_name = "N", default_value_t = 2,
              value_parser = clap::value_parser!(u32).range(1..=65_536))]
        tasks: u32,
        #[command(flatten)]
        bake: BakeArgs,
    },
    /// Step 2, anywhere the input and DIR are: gather the rows of task K of the plan in DIR
    /// (writes DIR/task-K.bin).
    Gather {
        /// The plan's folder.
        #[arg(long, value_name = "DIR")]
        dir: PathBuf,
        /// The task to gather (0 to the plan's task count − 1).
        #[arg(long, value_name = "K")]
        task: usize,
        #[command(flatten)]
        bake: BakeArgs,
    },
    /// Step 3: read the plan and every task's rows from DIR and finish the bake into OUTPUT, byte
    /// for byte the output of the same bake in one process.
    Merge {
        /// The plan's folder.
        #[arg(long, value_name = "DIR")]
        dir: PathBuf,
        #[command(flatten)]
        bake: BakeArgs,
    },
}

/// What one run of the bake does: the whole bake, or one step of a distributed bake.
#[derive(Clone, Copy, Debug)]
enum Step<'a> {
    Whole,
    Plan { dir: &'a Path, tasks: usize },
    Gather { dir: &'a Path, task: usize },
    Merge { dir: &'a Path },
}

/// A file a bake writes besides the glTF set (the .gltf/.glb, its .bin and lightmaps), staged
/// after it in this list's order and renamed after the glTF.
#[derive(Clone, Copy, Debug)]
enum Extra<'a> {
    /// `--probes-out`: the probes' readings.
    Probes(&'a Path),
    /// `--summary-json`: the run summary with timings and memory.
    Summary(&'a Path),
    /// `--report-out`: the lighting report.
    Report(&'a Path),
}

impl<'a> Extra<'a> {
    fn path(self) -> &'a Path {
        match self {
            Extra::Probes(p) | Extra::Summary(p) | Extra::Report(p) => p,
        }
    }
}

/// One bake run, parsed and validated before any work: the step, the settings, and every file
/// the run reads and writes (each written file one entry of `extras`, or the glTF set).
struct Job<'a> {
    args: &'a BakeArgs,
    step: Step<'a>,
    input: &'a Path,
    output: &'a Path,
    settings: Settings,
    import: ImportOptions,
    /// The command line's input files besides the scene (targets, a probe CSV).
    reads: Vec<&'a Path>,
    extras: Vec<Extra<'a>>,
    /// The report's format when one was asked for (printed, or written to `--report-out`).
    report: Option<FormatArg>,
}

impl<'a> Job<'a> {
    /// Validate the raw arguments (no file read yet).
    fn parse(args: &'a BakeArgs, step: Step<'a>) -> Result<Self> {
        let (Some(input), Some(output)) = (&args.input, &args.output) else {
            return Err(luxbake::Error::Settings(
                "an input scene and -o OUTPUT are required (see bake --help)".into(),
            )
            .into());
        };
        let settings = settings(&args.settings)?;
        let reads = [Some(input.as_path()), args.targets.as_deref()]
            .into_iter()
            .flatten()
            .chain(args.settings.probes.in_path())
            .collect();
        let extras = (args
            .settings
            .probes
            .out_path()
            .map(Extra::Probes)
            .into_iter())
        .chain(args.summary_json.as_deref().map(Extra::Summary))
        .chain(args.report_out.as_deref().map(Extra::Report))
        .collect();
        let wants_report = args.report.is_some()
            || args.report_out.is_some()
            || args.report_by.is_some()
            || args.targets.is_some();
        let obj_up = match args.obj_up {
            UpArg::Y => UpAxis::Y,
            UpArg::Z => UpAxis::Z,
        };
        Ok(Job {
            args,
            step,
            input,
            output,
            settings,
            import: ImportOptions { obj_up },
            reads,
            extras,
            report: wants_report.then(|| args.report.unwrap_or(FormatArg::Table)),
        })
    }

    /// Every output against the files the run reads (those of `scene` too) and each other.
    fn check(&self, scene: &Scene) -> Result<()> {
        let extra: Vec<&Path> = self.extras.iter().map(|e| e.path()).collect();
        Ok(export::check_run(self.output, scene, &self.reads, &extra)?)
    }

    /// The report's options (reads the targets file), when a report was asked for.
    fn report_options(&self) -> Result<Option<ReportOptions>> {
        let a = self.args;
        let Some(_) = self.report else {
            return Ok(None);
        };
        let options =
            super::report::options(a.report_by.unwrap_or(ByArg::Both), a.targets.as_deref())?;
        if let Some(t) = &options.targets
            && t.wants_working_plane()
            && self.settings.working_plane.is_none()
        {
            return Err(t.no_working_plane().into());
        }
        Ok(Some(options))
    }
}

/// Run the whole bake (the input and output are present: clap requires them without a
/// subcommand).
pub fn run(args: &BakeArgs) -> Result<()> {
    run_job(Job::parse(args, Step::Whole)?)
}

/// Run one step of a distributed bake.
pub fn run_shard(args: &ShardArgs) -> Result<()> {
    let job = match &args.step {
        ShardStep::Plan { dir, tasks, bake } => {
            let tasks = *tasks as usize;
            Job::parse(bake, Step::Plan { dir, tasks })?
        }
        ShardStep::Gather { dir, task, bake } => {
            Job::parse(bake, Step::Gather { dir, task: *task })?
        }
        ShardStep::Merge { dir, bake } => Job::parse(bake, Step::Merge { dir })?,
    };
    run_job(job)
}

/// Import, bake (or run the job's step) and write the outputs.
fn run_job(job: Job) -> Result<()> {
    let start = Instant::now();
    let mut progress = CliProgress::new(!job.args.quiet && std::io::stderr().is_terminal());
    if job.args.summary_json.is_some() {
        progress = progress.trace_memory("import");
    }
    // Every output against the inputs named on the command line and each other, before any
    // work; again with every file the import read once it is done.
    job.check(&Scene::default())?;
    let scene = import::load(job.input, &job.import)?;
    let report_options = job.report_options()?;
    job.check(&scene)?;
    for w in &scene.warnings {
        progress.warn(w);
    }
    let settings = &job.settings;
    let pool = worker_pool(settings, &progress)?;
    let result = match job.step {
        Step::Plan { dir, tasks } => {
            return pool.install(|| super::shard::plan(dir, tasks, &scene, settings, &progress));
        }
        Step::Gather { dir, task } => {
            return pool.install(|| super::shard::gather(dir, task, &scene, settings, &progress));
        }
        Step::Merge { dir } => {
            pool.install(|| super::shard::merge(dir, &scene, settings, &progress))?
        }
        Step::Whole => pool.install(|| luxbake::bake::bake(&scene, settings, &progress))?,
    };
    progress.mark("output");
    let written = Written {
        job: &job,
        scene: &scene,
        result: &result,
        pool: &pool,
    };
    let report_text = written.write(report_options.as_ref(), &progress, start)?;
    progress.done();
    if !job.args.quiet {
        report(&result.summary, job.output, start.elapsed().as_secs_f64());
        super::probes::report(&result.probes);
    }
    if let (Some(text), None) = (report_text, &job.args.report_out) {
        print!("{text}");
    }
    Ok(())
}

/// A finished bake about to be written.
struct Written<'a> {
    job: &'a Job<'a>,
    scene: &'a Scene,
    result: &'a BakeResult,
    pool: &'a rayon::ThreadPool,
}

impl Written<'_> {
    /// Stage the glTF set and every extra in one batch and commit it; the report's text, when
    /// one was asked for (to print when it has no file).
    fn write(
        &self,
        report_options: Option<&ReportOptions>,
        progress: &CliProgress,
        start: Instant,
    ) -> Result<Option<String>> {
        let (job, settings) = (self.job, &self.job.settings);
        let options = ExportOptions {
            unlit: !settings.keep_lit_materials,
            probe_glyphs: settings.probe_glyphs.then(|| export::glyph_scale(settings)),
        };
        // One batch: the lightmaps, the .bin and the glTF (its rename commits the set), then the
        // extras, each renamed after the glTF.
        let mut batch = Batch::default();
        let prepared = self.pool.install(|| {
            export::Prepared::staged(job.output, self.scene, self.result, &options, &mut batch)
        })?;
        // The report is made from the bytes about to be written, before anything is renamed (a
        // bad target fails the run cleanly).
        let report_text = match (report_options, job.report) {
            (Some(o), Some(format)) => {
                let baked = luxbake::readback::from_prepared(job.output, &prepared)?;
                Some(super::report::render(&baked, o, format)?)
            }
            _ => None,
        };
        let staged = prepared.stage(self.scene, &mut batch)?;
        for &extra in &job.extras {
            let bytes = match extra {
                Extra::Probes(path) => super::probes::out_bytes(path, &self.result.probes)?,
                Extra::Summary(_) => self.summary_bytes(progress, start),
                Extra::Report(_) => report_text.clone().unwrap_or_default().into_bytes(),
            };
            batch.stage(extra.path(), &bytes)?;
        }
        let paths: Vec<&Path> = job.extras.iter().map(|e| e.path()).collect();
        staged.commit(batch, &paths)?;
        Ok(report_text)
    }

    /// `--summary-json`'s bytes: the run summary with its timings, memory and total time.
    fn summary_bytes(&self, progress: &CliProgress, start: Instant) -> Vec<u8> {
        let summary = RunSummary {
            timings_seconds: Some(self.result.timings),
            ..self.result.summary.clone()
        };
        let memory = progress.memory();
        let record = RunRecord {
            summary: &summary,
            input: self.job.input,
            output: self.job.output,
            threads: self.pool.current_num_threads(),
            total_seconds: start.elapsed().as_secs_f64(),
            memory_kib: &memory,
        };
        export::summary::bytes(&record)
    }
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
