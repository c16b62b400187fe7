//! `bake diff A.gltf|.glb B.gltf|.glb [--mode vertices|texels|samples|means|probes]
//! [--no-lightmaps] [--rtol R] [--atol A] [--floor F] [--worst N] [--json]`: compare two bakes (B
//! is the reference; see `luxbake::diff`). Output: text or JSON on stdout. Exit code 0 when every value is within
//! tolerance, 1 when not (the worst place on the last line of the text), 2 when the bakes cannot
//! be compared (unreadable, not a luxbake output, topology that differs for the mode, bad
//! options), with one line on stderr naming the file or the node.

use clap::{Args, ValueEnum};
use luxbake::diff::{self, Mode, Options};
use std::path::PathBuf;

/// `--mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// Vertex by vertex (same nodes, primitives, vertices) and probes; when both bakes have
    /// lightmaps, texel by texel (same layout) or at surface points.
    Vertices,
    /// Lightmaps texel by texel (same nodes, primitives, vertices and lightmap layout).
    Texels,
    /// Lightmaps read at every vertex and triangle centroid (same nodes, primitives, vertices).
    Samples,
    /// Area-weighted means per node and per material, and probes (topology may differ).
    Means,
    /// Probes only (meshes may differ in any way).
    Probes,
}

/// Compare two luxbake outputs (B is the reference).
#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The bake to check (.gltf or .glb written by bake).
    a: PathBuf,
    /// The reference bake.
    b: PathBuf,
    /// What to compare: `vertices` needs the same mesh topology; `means` (for other patch sizes)
    /// compares each node's and material's area-weighted means; `probes` only the probes.
    #[arg(long, value_enum, default_value = "vertices")]
    mode: ModeArg,
    /// Compare vertex values (and take means over vertices) even when both bakes have
    /// lightmaps.
    #[arg(long)]
    no_lightmaps: bool,
    /// Relative tolerance: a value passes when |a − b| ≤ atol + rtol·max(|b|, floor).
    #[arg(
        long,
        value_name = "R",
        default_value_t = 1e-3,
        allow_negative_numbers = true
    )]
    rtol: f64,
    /// Absolute tolerance in lx (÷ π for _LUMINANCE, in cd/m²).
    #[arg(
        long,
        value_name = "LX",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    atol: f64,
    /// Smallest |b| a relative difference is taken of, in lx (÷ π for _LUMINANCE)
    /// [default: 1 % of the 99th percentile of B's _ILLUMINANCE].
    #[arg(long, value_name = "LX", allow_negative_numbers = true)]
    floor: Option<f64>,
    /// How many of the worst places to list.
    #[arg(long, value_name = "N", default_value_t = 10)]
    worst: usize,
    /// Print JSON (fields documented in docs/diff.md) instead of text.
    #[arg(long)]
    json: bool,
}

/// Run the comparison; returns the exit code (errors are printed here, on one line).
pub fn run(args: &DiffArgs) -> i32 {
    match compare(args) {
        Ok(d) => {
            if args.json {
                print!("{}", d.json());
            } else {
                print!("{}", diff::render::render(&d));
            }
            if d.pass { 0 } else { 1 }
        }
        Err(message) => {
            eprintln!("{message}");
            2
        }
    }
}

fn compare(args: &DiffArgs) -> Result<diff::Diff, String> {
    let check = |name: &str, v: f64, positive: bool| {
        if !v.is_finite() || v < 0.0 || (positive && v == 0.0) {
            let what = if positive { "> 0" } else { "≥ 0" };
            Err(format!(
                "error: --{name} must be a finite number {what}, not {v}"
            ))
        } else {
            Ok(())
        }
    };
    check("rtol", args.rtol, false)?;
    check("atol", args.atol, false)?;
    if let Some(f) = args.floor {
        check("floor", f, true)?;
    }
    let load = |p: &PathBuf| luxbake::readback::read(p).map_err(|e| format!("error: {e}"));
    let (a, b) = (load(&args.a)?, load(&args.b)?);
    let mode = match args.mode {
        ModeArg::Vertices => Mode::Vertices,
        ModeArg::Texels => Mode::Texels,
        ModeArg::Samples => Mode::Samples,
        ModeArg::Means => Mode::Means,
        ModeArg::Probes => Mode::Probes,
    };
    let options = Options {
        mode,
        rtol: args.rtol,
        atol: args.atol,
        floor: args.floor,
        worst: args.worst,
        lightmaps: !args.no_lightmaps,
    };
    let names = (args.a.display().to_string(), args.b.display().to_string());
    diff::compare(&a, &b, &options, (&names.0, &names.1)).map_err(|m| {
        let hint = match mode {
            Mode::Vertices | Mode::Samples => "; --mode means compares bakes of different topology",
            Mode::Texels => {
                "; --mode samples compares other lightmap layouts, --mode means other topologies"
            }
            Mode::Means => "; --mode probes compares the probes alone",
            Mode::Probes => "",
        };
        format!(
            "error: {} and {} cannot be compared {}: {m}{hint}",
            names.0,
            names.1,
            mode.describe()
        )
    })
}
