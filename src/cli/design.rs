//! `bake design TABLE.csv [--scene LIT.gltf] [--format table|markdown|csv|json]`: the designer's
//! flux table (Lynes' method, the seed paper's Appendix A): from the illuminance wanted on each
//! surface to the direct flux each needs. Reads the CSV (`name,area_m2,reflectance,
//! illuminance_lx`, optionally `surface`), prints to stdout; writes no file. With `--scene`, each
//! row's area is the bake's: the node or material the row names (`surface`, else its name), as
//! the report measures it — covered parts (the floor under what stands on it) left out. Surfaces
//! designed below the indirect illuminance are warned about (in the text for table and
//! Markdown, on stderr for CSV and JSON, which also carry them as data).

use super::report::FormatArg;
use anyhow::Result;
use clap::Args;
use luxbake::Error;
use luxbake::design::{self, DesignRow, FluxTable, Format};
use luxbake::report::Targets;
use std::path::{Path, PathBuf};

/// Print the flux table of a design.
#[derive(Args, Debug)]
pub struct DesignArgs {
    /// CSV with a header row `name,area_m2,reflectance,illuminance_lx[,surface]`, one row per
    /// surface.
    file: PathBuf,
    /// A bake (.gltf/.glb written by bake) to take each row's area from: the node path or
    /// `material:NAME` in its `surface` column, else its name.
    #[arg(long, value_name = "LIT")]
    scene: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = FormatArg::Table)]
    format: FormatArg,
}

pub fn run(args: &DesignArgs) -> Result<()> {
    let mut rows = read(&args.file)?;
    if let Some(scene) = &args.scene {
        areas_from(scene, &args.file, &mut rows)?;
    }
    let table = FluxTable::compute(&rows).map_err(|r| {
        Error::input(
            &args.file,
            format!("line {}", r.line),
            format!(
                "'{}' has no area_m2 (give it, or take it from a bake with --scene)",
                r.name
            ),
        )
    })?;
    let format = format(args.format);
    print!("{}", table.render(format));
    if matches!(format, Format::Csv | Format::Json) {
        for w in &table.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(())
}

/// A design table's rows, read and parsed.
pub fn read(file: &Path) -> Result<Vec<DesignRow>> {
    let text = luxbake::import::files::read_text(file)
        .map_err(|e| Error::input(file, "", format!("cannot read the design table: {e}")))?;
    Ok(design::parse(file, &text)?)
}

/// What a row names in a bake: its `surface`, else its name.
pub fn key(row: &DesignRow) -> &str {
    row.surface.as_deref().unwrap_or(&row.name)
}

pub fn format(f: FormatArg) -> Format {
    match f {
        FormatArg::Table => Format::Table,
        FormatArg::Markdown => Format::Markdown,
        FormatArg::Csv => Format::Csv,
        FormatArg::Json => Format::Json,
    }
}

/// Replace each row's area by the bake's (a note on stderr where a given area differs by more
/// than 1 %).
fn areas_from(scene: &Path, file: &Path, rows: &mut [DesignRow]) -> Result<()> {
    let baked = luxbake::readback::read(scene)?;
    let lookup = Targets {
        file: file.to_path_buf(),
        entries: Vec::new(),
    };
    for r in rows.iter_mut() {
        let key = key(r).to_owned();
        if key == "working_plane" {
            return Err(Error::input(
                file,
                format!("line {}", r.line),
                "the working plane is not a surface with an area in the bake: give area_m2 \
                 and no --scene, or leave the row out",
            )
            .into());
        }
        let row = lookup
            .surface_row(&baked, &key)
            .map_err(|e| Error::input(file, format!("line {}", r.line), format!("{e}")))?;
        if let Some(given) = r.area
            && (given - row.area).abs() > 0.01 * row.area
        {
            eprintln!(
                "note: {}: area {given} m² in the table, {:.3} m² in {} (using the bake's)",
                r.name,
                row.area,
                scene.display()
            );
        }
        r.area = Some(row.area);
    }
    Ok(())
}
