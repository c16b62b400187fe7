//! `bake design TABLE.csv [--format table|markdown|csv|json]`: the designer's flux table (Lynes'
//! method, the seed paper's Appendix A): from the illuminance wanted on each surface to the direct
//! flux each needs. Reads the CSV (`name,area_m2,reflectance,illuminance_lx`), prints to stdout;
//! writes no file. Surfaces designed below the indirect illuminance are warned about (in the
//! text for table and Markdown, on stderr for CSV and JSON, which also carry them as data).

use super::report::FormatArg;
use anyhow::Result;
use clap::Args;
use luxbake::Error;
use luxbake::design::{self, FluxTable, Format};
use std::path::PathBuf;

/// Print the flux table of a design.
#[derive(Args, Debug)]
pub struct DesignArgs {
    /// CSV with a header row `name,area_m2,reflectance,illuminance_lx`, one row per surface.
    file: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Table)]
    format: FormatArg,
}

pub fn run(args: &DesignArgs) -> Result<()> {
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| Error::input(&args.file, "", format!("cannot read the design table: {e}")))?;
    let rows = design::parse(&args.file, &text)?;
    let table = FluxTable::compute(&rows);
    let format = match args.format {
        FormatArg::Table => Format::Table,
        FormatArg::Markdown => Format::Markdown,
        FormatArg::Csv => Format::Csv,
        FormatArg::Json => Format::Json,
    };
    print!("{}", table.render(format));
    if matches!(format, Format::Csv | Format::Json) {
        for w in &table.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(())
}
