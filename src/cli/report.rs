//! `bake report LIT.gltf|.glb [--format table|markdown|csv|json] [--by node|material|both]
//! [--targets FILE]`: the lighting report of a finished bake, read back from its output. The
//! same text as `bake … --report` printed at bake time (both go through [`render`]).

use anyhow::Result;
use clap::{Args, ValueEnum};
use luxbake::baked::BakedOutput;
use luxbake::report::{self, By, Format, Options, Targets};
use std::path::{Path, PathBuf};

/// Print the lighting report of a luxbake output.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A glTF written by bake (.gltf or .glb).
    file: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Table)]
    format: FormatArg,
    /// Surface sections: by node, by material, or both.
    #[arg(long, value_enum, default_value_t = ByArg::Both)]
    by: ByArg,
    /// Design targets (JSON object of average illuminances in lx) to compare with.
    #[arg(long, value_name = "FILE")]
    targets: Option<PathBuf>,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatArg {
    Table,
    Markdown,
    Csv,
    Json,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ByArg {
    Node,
    Material,
    Both,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Table => Format::Table,
            FormatArg::Markdown => Format::Markdown,
            FormatArg::Csv => Format::Csv,
            FormatArg::Json => Format::Json,
        }
    }
}

impl From<ByArg> for By {
    fn from(b: ByArg) -> Self {
        match b {
            ByArg::Node => By::Node,
            ByArg::Material => By::Material,
            ByArg::Both => By::Both,
        }
    }
}

/// Report options from the command line (reads and checks the targets file).
pub fn options(by: ByArg, targets: Option<&Path>) -> Result<Options> {
    Ok(Options {
        by: by.into(),
        targets: targets.map(Targets::read).transpose()?,
        border: 0.0,
    })
}

/// The report's text: the one code path of `bake report` and `bake … --report`.
pub fn render(input: &BakedOutput, options: &Options, format: FormatArg) -> Result<String> {
    Ok(report::build(input, options)?.render(format.into()))
}

pub fn run(args: &ReportArgs) -> Result<()> {
    let options = options(args.by, args.targets.as_deref())?;
    let input = luxbake::baked::read(&args.file)?;
    print!("{}", render(&input, &options, args.format)?);
    Ok(())
}
