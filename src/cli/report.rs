//! `bake report LIT.gltf|.glb [--format table|markdown|csv|json|html] [--by node|material|both]
//! [--targets FILE] [--border M] [-o FILE]`: the lighting report of a finished bake, read back
//! from its output. The same text as `bake … --report` printed at bake time (both go through
//! [`render`]). `html`: the designer's report document (`luxbake::html_report`), with the isolux plan
//! and the camera nodes' false-colour views. `-o`: written atomically instead of printed; without
//! `--format` its extension names the format, and an extension naming none (or another) is refused.

use anyhow::Result;
use clap::{Args, ValueEnum};
use luxbake::Error;
use luxbake::html_report;
use luxbake::import::{self, ImportOptions};
use luxbake::readback::BakedOutput;
use luxbake::report::{self, By, Format, Options, Targets};
use std::path::{Path, PathBuf};

/// Print the lighting report of a luxbake output.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A glTF written by bake (.gltf or .glb).
    file: PathBuf,
    /// Output format (html: the designer's report document, self-contained) [default: from
    /// the -o file's extension (.txt, .md, .csv, .json, .html), else table].
    #[arg(long, value_enum)]
    format: Option<ReportFormat>,
    /// Surface sections: by node, by material, or both.
    #[arg(long, value_enum, default_value_t = ByArg::Both)]
    by: ByArg,
    /// Design targets (JSON object of average illuminances in lx) to compare with.
    #[arg(long, value_name = "FILE")]
    targets: Option<PathBuf>,
    /// Working-plane border zone (m): leave out points closer than this to the plane's edges
    /// (EN 12464-1 calculation grids; e.g. 0.5).
    #[arg(long, value_name = "M", default_value_t = 0.0)]
    border: f64,
    /// Write the report into this file instead of printing it.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// `bake report`'s formats: those of `bake --report`, and the HTML document.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ReportFormat {
    Table,
    Markdown,
    Csv,
    Json,
    Html,
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
    let mut options = options(args.by, args.targets.as_deref())?;
    options.border = args.border;
    if !(args.border.is_finite() && args.border >= 0.0) {
        return Err(Error::Settings(format!(
            "--border {}: a length ≥ 0 m is expected (e.g. 0.5)",
            args.border
        ))
        .into());
    }
    // The report file against every file read: the bake, its targets and, once read, the
    // bake's buffers and lightmap EXR files.
    let mut read: Vec<&Path> = std::iter::once(args.file.as_path())
        .chain(args.targets.as_deref())
        .collect();
    if let Some(out) = &args.output {
        luxbake::export::check_files(&read, &[out])?;
    }
    let format = format_of(args.format, args.output.as_deref())?;
    let input = luxbake::readback::read(&args.file)?;
    read.extend(input.resources.iter().map(PathBuf::as_path));
    if let Some(out) = &args.output {
        luxbake::export::check_files(&read, &[out])?;
    }
    let text = match format {
        ReportFormat::Table => render(&input, &options, FormatArg::Table)?,
        ReportFormat::Markdown => render(&input, &options, FormatArg::Markdown)?,
        ReportFormat::Csv => render(&input, &options, FormatArg::Csv)?,
        ReportFormat::Json => render(&input, &options, FormatArg::Json)?,
        ReportFormat::Html => {
            let rep = report::build(&input, &options)?;
            // The views need the luminaires' openings: the output imported as a scene.
            let scene = match input.cameras.is_empty() {
                true => None,
                false => Some(import::load(&args.file, &ImportOptions::default())?),
            };
            if let (Some(out), Some(scene)) = (&args.output, &scene) {
                let inputs: Vec<&Path> = scene.input_files.iter().map(PathBuf::as_path).collect();
                luxbake::export::check_files(&inputs, &[out])?;
            }
            html_report::document(
                &input,
                scene.as_ref(),
                &rep,
                &html_report::Options::default(),
            )?
        }
    };
    match &args.output {
        Some(out) => luxbake::export::atomic::write_atomic(out, text.as_bytes())?,
        None => print!("{text}"),
    }
    Ok(())
}

/// The report's format: `--format` when given, else the one the `-o` file's extension names,
/// else a table. An `-o` extension that names no report format, or another one than
/// `--format`, is refused.
fn format_of(given: Option<ReportFormat>, output: Option<&Path>) -> Result<ReportFormat> {
    let Some(out) = output else {
        return Ok(given.unwrap_or(ReportFormat::Table));
    };
    let what = "a report (.txt: table, .md, .csv, .json, .html)";
    let ext = super::formats::extension(out, "-o", &["txt", "md", "csv", "json", "html"], what)?;
    let named = match ext.as_str() {
        "md" => ReportFormat::Markdown,
        "csv" => ReportFormat::Csv,
        "json" => ReportFormat::Json,
        "html" => ReportFormat::Html,
        _ => ReportFormat::Table,
    };
    match given {
        Some(g) if std::mem::discriminant(&g) != std::mem::discriminant(&named) => {
            Err(Error::Settings(format!(
                "-o {}: --format {} does not match the file's extension (.{ext})",
                out.display(),
                format!("{g:?}").to_lowercase()
            ))
            .into())
        }
        _ => Ok(named),
    }
}
