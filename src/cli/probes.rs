//! The probe options of `bake`: where to measure (`--probe-grid`, `--probe-height`, `--probes`,
//! `--working-plane`, `--working-plane-spacing`), glyphs (`--probe-glyphs`) and the
//! `--probes-out` file. Raw arguments are checked and turned into [`Settings`] fields before any
//! work; a bad `--probes` file is one error naming the file and the line.

use anyhow::{Result, anyhow};
use clap::Args;
use luxbake::probes::{ProbeResult, csv, output};
use luxbake::settings::{ProbeGrid, Settings};
use std::path::{Path, PathBuf};

/// Probe options (flattened into `bake`'s arguments).
#[derive(Args, Debug, Default)]
pub struct ProbeArgs {
    /// Measure cubic illuminance on a grid over the floor, every SPACING metres.
    #[arg(long, value_name = "SPACING", allow_negative_numbers = true)]
    probe_grid: Option<f64>,
    /// Height of the --probe-grid points above the floor, in metres [default: 1.2].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    probe_height: Option<f64>,
    /// Measure at the points of a CSV file: rows x,y,z[,name] in metres (world, +Y up).
    #[arg(long, value_name = "FILE.csv")]
    probes: Option<PathBuf>,
    /// Measure on a working plane H metres above the floor.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    working_plane: Option<f64>,
    /// Grid spacing of the working plane, in metres [default: 0.25].
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    working_plane_spacing: Option<f64>,
    /// Add a glyph per probe to the output: illumination vector arrow and symmetric sphere.
    #[arg(long)]
    probe_glyphs: bool,
    /// Also write every probe's results here: .csv (a table) or .json (as in the glTF extras).
    #[arg(long, value_name = "FILE.csv|FILE.json")]
    probes_out: Option<PathBuf>,
}

impl ProbeArgs {
    /// Fill the probe fields of `settings` (reads the `--probes` file).
    pub fn apply(&self, settings: &mut Settings) -> Result<()> {
        if self.probe_height.is_some() && self.probe_grid.is_none() {
            return Err(usage("--probe-height needs --probe-grid SPACING"));
        }
        if self.working_plane_spacing.is_some() && self.working_plane.is_none() {
            return Err(usage("--working-plane-spacing needs --working-plane H"));
        }
        settings.probe_grid = self.probe_grid.map(|spacing| ProbeGrid {
            spacing,
            height: self.probe_height.unwrap_or(1.2),
        });
        settings.working_plane = self.working_plane.map(|height| ProbeGrid {
            spacing: self.working_plane_spacing.unwrap_or(0.25),
            height,
        });
        settings.probe_glyphs = self.probe_glyphs;
        if let Some(path) = &self.probes {
            settings.extra_probes = read_csv(path)?;
        }
        if let Some(path) = &self.probes_out {
            output::Format::for_path(path).map_err(|m| anyhow!("{}: {m}", path.display()))?;
            let same = |a: &Path, b: &Path| {
                a.canonicalize()
                    .is_ok_and(|a| b.canonicalize().is_ok_and(|b| a == b))
            };
            if self
                .probes
                .as_deref()
                .is_some_and(|input| same(input, path))
            {
                return Err(anyhow!(
                    "{}: refusing to overwrite the --probes input file; choose another --probes-out name",
                    path.display()
                ));
            }
        }
        Ok(())
    }

    /// The `--probes-out` file, to be checked with the other outputs before baking.
    pub fn out_path(&self) -> Option<&Path> {
        self.probes_out.as_deref()
    }

    /// The `--probes` file, an input of the run.
    pub fn in_path(&self) -> Option<&Path> {
        self.probes.as_deref()
    }
}

/// The bytes of a `--probes-out` file at `path` (its format by extension).
pub fn out_bytes(path: &Path, results: &[ProbeResult]) -> Result<Vec<u8>> {
    let format = output::Format::for_path(path).map_err(|m| anyhow!("{m}"))?;
    Ok(output::bytes(format, results))
}

/// The probes of a `--probes` file; errors read `FILE:LINE: message`.
fn read_csv(path: &Path) -> Result<Vec<luxbake::probes::Probe>> {
    let text = luxbake::import::files::read_text(path)
        .map_err(|e| anyhow!("{}: cannot read the probes file: {e}", path.display()))?;
    csv::parse(&text).map_err(|(line, m)| anyhow!("{}:{line}: {m}", path.display()))
}

/// One line on stderr when probes were measured: how many, per layer, and the highest scalar
/// illuminance.
pub fn report(results: &[ProbeResult]) {
    if results.is_empty() {
        return;
    }
    let mut counts: Vec<(&'static str, usize)> = Vec::new();
    for r in results {
        let kind = luxbake::probes::table::origin_kind(&r.probe.origin);
        match counts.iter_mut().find(|(k, _)| *k == kind) {
            Some((_, n)) => *n += 1,
            None => counts.push((kind, 1)),
        }
    }
    let parts: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
    let max = results.iter().map(|r| r.metrics.scalar).fold(0.0, f64::max);
    eprintln!(
        "  probes: {} measured ({}), highest scalar illuminance {max:.1} lx",
        results.len(),
        parts.join(", ")
    );
}

fn usage(message: &str) -> anyhow::Error {
    luxbake::Error::Settings(message.into()).into()
}
