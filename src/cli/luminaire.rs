//! `bake luminaire FILE.ies|FILE.ldt [--polar OUT.svg] [--json]`: a photometric file's summary
//! (flux, symmetry, beam and field angles, peak intensity, opening) and its polar curve.

use anyhow::{Context, Result};
use clap::Args;
use luxbake::photometry::{Format, Photometry};
use std::path::PathBuf;

/// Summarise a photometric file (IES LM-63 or EULUMDAT).
#[derive(Args, Debug)]
pub struct LuminaireArgs {
    /// The file: .ies (IES LM-63) or .ldt (EULUMDAT).
    file: PathBuf,
    /// Also write the polar intensity curve (C0-C180 and C90-C270 planes, cd) as SVG here.
    #[arg(long, value_name = "OUT.svg")]
    polar: Option<PathBuf>,
    /// Print the summary as JSON instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &LuminaireArgs) -> Result<()> {
    let file = &args.file;
    let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
    let format = Format::from_mime_or_extension(ext).with_context(|| {
        format!(
            "{}: unknown photometric format (use .ies or .ldt)",
            file.display()
        )
    })?;
    if let Some(svg) = &args.polar {
        luxbake::export::check_files(&[file], &[svg])?;
        super::formats::extension(svg, "--polar", &["svg"], "the polar curve")?;
    }
    let bytes = luxbake::import::files::read(file)
        .with_context(|| format!("{}: cannot read", file.display()))?;
    let photometry = Photometry::parse(&bytes, format)
        .map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
    if let Some(svg) = &args.polar {
        luxbake::export::atomic::write_atomic(svg, photometry.polar_svg().as_bytes())?;
    }
    let summary = photometry.summary();
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!("{}", file.display());
        println!("{summary}");
    }
    Ok(())
}
