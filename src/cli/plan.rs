//! `bake plan LIT.gltf|.glb -o PLAN.svg|PLAN.png [--working-plane | --surface NODE[FACE]] [--scale
//! auto|LO:HI] [--log] [--steps N] [--quantity illuminance|luminance] [--size PX]`: a
//! false-colour isolux plan of a finished bake, as vector SVG or PNG (by the output's extension).
//! Options are checked (exit 2) and the output path too (not an input, a writable folder) before
//! the bake is read; the file is written atomically.

use anyhow::Result;
use clap::{Args, ValueEnum};
use luxbake::Error;
use luxbake::plan::{self, Options, Quantity, Source};
use std::path::{Path, PathBuf};

/// Draw a false-colour plan with isolux contours of the working plane or of a planar node.
#[derive(Args, Debug)]
pub struct PlanArgs {
    /// A glTF written by bake (.gltf or .glb).
    file: PathBuf,
    /// The plan to write: .svg (vector) or .png.
    #[arg(short, long, value_name = "PLAN.svg|PLAN.png")]
    output: PathBuf,
    /// Draw the working plane (the default): the bake's --working-plane probes, seen from above.
    #[arg(long, conflicts_with = "surface")]
    working_plane: bool,
    /// Draw this planar node instead (its name, or its path such as desk_light/top), or one
    /// face of a solid node as report keys name it (desk_light/top[+y]).
    #[arg(long, value_name = "NODE[FACE]")]
    surface: Option<String>,
    /// Colour scale range: auto (a round range over the values) or LO:HI.
    #[arg(long, value_name = "auto|LO:HI", default_value = "auto")]
    scale: String,
    /// Logarithmic colour scale.
    #[arg(long)]
    log: bool,
    /// Colour bands (0: smooth colours); contours are drawn at the bands' edges.
    #[arg(long, value_name = "N", default_value_t = 10)]
    steps: u32,
    /// What to draw (luminance: surfaces only).
    #[arg(long, value_enum, default_value_t = QuantityArg::Illuminance)]
    quantity: QuantityArg,
    /// The plan's longer side in pixels (the legend and title add to it).
    #[arg(long, value_name = "PX", default_value_t = 800)]
    size: u32,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum QuantityArg {
    Illuminance,
    Luminance,
}

/// `auto` or `LO:HI`.
fn range(scale: &str) -> luxbake::Result<Option<[f64; 2]>> {
    if scale == "auto" {
        return Ok(None);
    }
    let bad = || {
        Error::Settings(format!(
            "--scale {scale}: expected auto or LO:HI (e.g. 0:500)"
        ))
    };
    let (lo, hi) = scale.split_once(':').ok_or_else(bad)?;
    let lo: f64 = lo.trim().parse().map_err(|_| bad())?;
    let hi: f64 = hi.trim().parse().map_err(|_| bad())?;
    Ok(Some([lo, hi]))
}

pub fn run(a: &PlanArgs) -> Result<()> {
    let options = Options {
        source: match &a.surface {
            Some(node) => Source::Surface(node.clone()),
            None => Source::WorkingPlane,
        },
        range: range(&a.scale)?,
        log: a.log,
        steps: a.steps,
        quantity: match a.quantity {
            QuantityArg::Illuminance => Quantity::Illuminance,
            QuantityArg::Luminance => Quantity::Luminance,
        },
        size: a.size,
    };
    plan::check(&options)?;
    luxbake::export::check_files(&[&a.file], &[&a.output])?;
    let ext = super::formats::extension(&a.output, "-o", &["svg", "png"], "a plan")?;
    let input = luxbake::readback::read(&a.file)?;
    let read: Vec<&Path> = std::iter::once(a.file.as_path())
        .chain(input.resources.iter().map(PathBuf::as_path))
        .collect();
    luxbake::export::check_files(&read, &[&a.output])?;
    let plan = plan::build(&input, &options)?;
    let bytes = if ext == "svg" {
        plan.svg().into_bytes()
    } else {
        luxbake::export::display::png_rgb8(&plan.image())
            .map_err(|e| Error::output(&a.output, format!("cannot encode the PNG: {e}")))?
    };
    luxbake::export::atomic::write_atomic(&a.output, &bytes)?;
    Ok(())
}
