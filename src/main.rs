//! The `bake` command line. Raw arguments are turned into validated settings before any work;
//! errors print as one line naming the file and the element, with exit code 2 for usage errors
//! (invalid arguments or option values) and 1 for everything else; nothing is written unless
//! everything succeeded. Subcommands live in `cli/`.

mod cli;

use clap::{Parser, Subcommand};

/// Solve the inter-reflection of light in a photometric glTF/OBJ room and write the lit result
/// as glTF (units: m, lx, cd/m², lm; +Y up).
#[derive(Parser, Debug)]
#[command(
    name = "bake",
    version,
    about,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    bake: cli::bake::BakeArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Summarise a photometric file (.ies, .ldt) and optionally draw its polar curve.
    Luminaire(cli::luminaire::LuminaireArgs),
    /// Print the lighting report of a baked output (per material, per node, working plane).
    Report(cli::report::ReportArgs),
    /// Compare two bakes: vertex or lightmap texel by texel, by node/material means or by probes (exit 0 within
    /// tolerance, 1 not, 2 not comparable).
    Diff(cli::diff::DiffArgs),
    /// Render a luminance image (EXR, cd/m²) of a baked output from a camera, tone mapped or in
    /// false colour.
    View(Box<cli::view::ViewArgs>),
    /// Draw a false-colour isolux plan of the working plane or of a planar node (SVG or PNG).
    Plan(cli::plan::PlanArgs),
    /// Print the flux table of a design (Lynes' method): the direct flux each surface needs for
    /// its design illuminance.
    Design(cli::design::DesignArgs),
    /// Fit dimming factors of luminaire groups to a design (least squares on relative error)
    /// and write the fitted scene.
    Fit(Box<cli::fit::FitArgs>),
    /// The distributed bake's steps (plan, gather tasks anywhere, merge): the same output as one
    /// bake, byte for byte.
    Shard(Box<cli::bake::ShardArgs>),
    /// Write a scene built in code as an input glTF (e.g. the benchmark's open-plan office).
    Generate(cli::generate::GenerateArgs),
}

fn main() {
    luxbake::heap::return_large_blocks();
    // SIGINT/SIGTERM remove the run's temporary files before exiting (130/143).
    if let Err(e) = luxbake::export::atomic::install_signal_handler() {
        eprintln!("warning: cannot handle SIGINT/SIGTERM: {e}");
    }
    let args = match Cli::try_parse() {
        Ok(args) => args,
        Err(e) if e.use_stderr() => {
            // One line, like every other error: clap's first line, and where to look.
            let text = e.render().to_string();
            let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
            let mut first = lines
                .next()
                .unwrap_or("error: invalid arguments")
                .to_string();
            if first.ends_with(':') {
                // "the following required arguments were not provided:" — name them.
                first = format!("{first} {}", lines.next().unwrap_or(""));
            }
            eprintln!("{first} (see bake --help)");
            std::process::exit(2);
        }
        Err(e) => e.exit(), // --help, --version
    };
    if let Some(Command::Diff(a)) = &args.command {
        std::process::exit(cli::diff::run(a));
    }
    let result = match &args.command {
        None => cli::bake::run(&args.bake),
        Some(Command::Luminaire(a)) => cli::luminaire::run(a),
        Some(Command::Report(a)) => cli::report::run(a),
        Some(Command::Diff(_)) => unreachable!("handled above"),
        Some(Command::Generate(a)) => cli::generate::run(a),
        Some(Command::Shard(a)) => cli::bake::run_shard(a),
        Some(Command::View(a)) => cli::view::run(a),
        Some(Command::Plan(a)) => cli::plan::run(a),
        Some(Command::Design(a)) => cli::design::run(a),
        Some(Command::Fit(a)) => cli::fit::run(a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(exit_code(&e));
    }
}

/// 2 for a usage error (an invalid option value: [`luxbake::Error::Settings`]), 1 for any other
/// error (input, output, bake).
fn exit_code(e: &anyhow::Error) -> i32 {
    let usage = e
        .chain()
        .any(|c| matches!(c.downcast_ref(), Some(luxbake::Error::Settings(_))));
    if usage { 2 } else { 1 }
}
