//! `bake plan LIT.gltf|.glb -o PLAN.svg|PLAN.png …`: a false-colour isolux plan of a finished bake.

use anyhow::{Result, bail};
use clap::Args;
use std::path::PathBuf;

/// Draw a false-colour plan with isolux contours of the working plane or of a planar node.
#[derive(Args, Debug)]
pub struct PlanArgs {
    /// A glTF written by bake (.gltf or .glb).
    file: PathBuf,
    /// The plan to write: .svg (vector) or .png.
    #[arg(short, long, value_name = "PLAN.svg|PLAN.png")]
    output: PathBuf,
}

pub fn run(_a: &PlanArgs) -> Result<()> {
    bail!("bake plan: not built yet")
}
