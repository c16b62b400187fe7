//! `bake fit SCENE --design TABLE.csv | --targets FILE -o FITTED [--group NAME=PATTERN,...]...
//! [--group-by profile|source|all] [--max-factor F] [--format ...]` plus the bake's settings:
//! dimming factors for groups of sources that bring each designed surface's average
//! illuminance as close as possible to the design (`luxbake::fit`). Writes the input scene with
//! the factors applied (multipliers of luminaires, intensities of lights, emitted amounts of
//! materials) to FITTED, and prints the factors and, per surface, design, achieved and ratio.

use super::progress::CliProgress;
use super::report::FormatArg;
use super::settings::{SettingsArgs, UpArg};
use anyhow::Result;
use clap::{Args, ValueEnum};
use luxbake::Error;
use luxbake::export;
use luxbake::fit::{self, Design, GroupBy};
use luxbake::import::{self, ImportOptions, UpAxis};
use luxbake::progress::Progress;
use luxbake::report::Targets;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Fit dimming factors of luminaire groups to a design, and write the fitted scene.
#[derive(Args, Debug)]
pub struct FitArgs {
    /// Input scene: .gltf, .glb or .obj (with its .mtl).
    scene: PathBuf,
    /// The design: a flux-table CSV (`name,area_m2,reflectance,illuminance_lx[,surface]`; its
    /// `surface`, else its name, names the node path, `material:NAME` or `working_plane`).
    #[arg(
        long,
        value_name = "TABLE.csv",
        required_unless_present = "targets",
        conflicts_with = "targets"
    )]
    design: Option<PathBuf>,
    /// The design as a targets file (a JSON object of average illuminances in lx, as `bake
    /// report --targets` reads).
    #[arg(long, value_name = "FILE")]
    targets: Option<PathBuf>,
    /// The fitted scene: .gltf (+ .bin) or .glb.
    #[arg(short, long, value_name = "FITTED")]
    output: PathBuf,
    /// A group of sources dimmed together: NAME=PATTERN[,PATTERN...], glob patterns over node,
    /// light, profile names and material:NAME. Repeat for more groups; sources in no group keep
    /// their light.
    #[arg(long = "group", value_name = "NAME=PATTERNS")]
    groups: Vec<String>,
    /// Without --group: one group per luminaire profile (each light and emitting material
    /// alone), per source, or all sources together.
    #[arg(long, value_enum, default_value_t = GroupByArg::Profile, conflicts_with = "groups")]
    group_by: GroupByArg,
    /// Largest factor (1: dimming only).
    #[arg(long, value_name = "F", default_value_t = 1.0)]
    max_factor: f64,
    /// Working-plane border zone in metres, left out of a working_plane target (as bake report
    /// --border).
    #[arg(
        long,
        value_name = "M",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    border: f64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Table)]
    format: FormatArg,
    /// Up axis of an OBJ input (glTF is always +Y up).
    #[arg(long, value_enum, default_value_t = UpArg::Y)]
    obj_up: UpArg,
    /// No progress bar on stderr (errors and warnings still print).
    #[arg(short, long)]
    quiet: bool,
    #[command(flatten)]
    settings: SettingsArgs,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum GroupByArg {
    Profile,
    Source,
    All,
}

pub fn run(args: &FitArgs) -> Result<()> {
    let settings = super::settings::settings(&args.settings)?;
    if args.settings.probes.out_path().is_some() {
        return Err(Error::Settings("bake fit writes no probes: drop --probes-out".into()).into());
    }
    let design_file = args.design.as_deref().or(args.targets.as_deref());
    let read: Vec<&Path> = [Some(args.scene.as_path()), design_file]
        .into_iter()
        .flatten()
        .chain(args.settings.probes.in_path())
        .collect();
    export::check_run(&args.output, &luxbake::scene::Scene::default(), &read, &[])?;
    let design = match (&args.design, &args.targets) {
        (Some(file), _) => {
            let rows = super::design::read(file)?;
            Design {
                names: rows.iter().map(|r| r.name.clone()).collect(),
                targets: Targets {
                    file: file.clone(),
                    entries: (rows.iter())
                        .map(|r| (super::design::key(r).to_owned(), r.illuminance))
                        .collect(),
                },
            }
        }
        (None, Some(file)) => {
            let targets = Targets::read(file)?;
            Design {
                names: targets.entries.iter().map(|(k, _)| k.clone()).collect(),
                targets,
            }
        }
        (None, None) => unreachable!("clap requires --design or --targets"),
    };
    if design.targets.wants_working_plane() && settings.working_plane.is_none() {
        return Err(design.targets.no_working_plane().into());
    }
    let obj_up = match args.obj_up {
        UpArg::Y => UpAxis::Y,
        UpArg::Z => UpAxis::Z,
    };
    let scene = import::load(&args.scene, &ImportOptions { obj_up })?;
    export::check_run(&args.output, &scene, &read, &[])?;
    let progress = CliProgress::new(!args.quiet && std::io::stderr().is_terminal());
    for w in &scene.warnings {
        progress.warn(w);
    }
    let groups = match args.groups.is_empty() {
        true => fit::groups::default_groups(
            &scene,
            match args.group_by {
                GroupByArg::Profile => GroupBy::Profile,
                GroupByArg::Source => GroupBy::Source,
                GroupByArg::All => GroupBy::All,
            },
        ),
        false => fit::groups::parse_groups(&scene, &args.groups)?,
    };
    let pool = super::settings::worker_pool(&settings, &progress)?;
    let options = fit::Options {
        max_factor: args.max_factor,
        border: args.border,
    };
    let (result, fitted) =
        pool.install(|| fit::fit(&scene, &design, &groups, &settings, options, &progress))?;
    export::write_scene(&args.output, &fitted)?;
    print!("{}", result.render(super::design::format(args.format)));
    Ok(())
}
