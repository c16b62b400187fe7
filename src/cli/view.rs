//! `bake view LIT.gltf|.glb -o VIEW.exr …`: a luminance image of a finished bake.

use anyhow::{Result, bail};
use clap::Args;
use std::path::PathBuf;

/// Render a luminance image (EXR, cd/m²) of a luxbake output from a camera.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// A glTF written by bake (.gltf or .glb).
    file: PathBuf,
    /// The EXR to write (R, G, B and luminance in cd/m²).
    #[arg(short, long, value_name = "VIEW.exr")]
    output: PathBuf,
}

pub fn run(_a: &ViewArgs) -> Result<()> {
    bail!("bake view: not built yet")
}
