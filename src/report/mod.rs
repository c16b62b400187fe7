//! The lighting report: per-surface figures like the seed paper's Table 2, the working plane, and
//! design targets beside what the bake achieved.
//!
//! Input: a [`BakedOutput`] — what a luxbake output holds, read from an output file or from the
//! bytes the exporter is about to write (`crate::readback`); both give the same values, so
//! `bake report OUT` prints exactly what `bake … --report` printed.
//! Output: a [`Report`] with up to four sections:
//! - surfaces **by material** and **by node** ([`rows`]): area, area-weighted reflectance,
//!   average / minimum / maximum illuminance, average direct and indirect, uniformity
//!   U₀ = E_min/E_avg, average luminance: from the lightmap texels of a lightmapped primitive
//!   (footprint-weighted averages, minima and maxima over texels with a footprint), from the
//!   vertices of another (area integrals of the piecewise-linear values, minima and maxima over
//!   vertices); each row says which (`source`), each section's title too;
//! - the **working plane** (the `+y` face of the bake's working-plane probes): points, average,
//!   minimum, maximum, U₀, U_d = E_min/E_max, direct and indirect averages, height and spacing,
//!   over the points inside a border zone along its edges (`Options::border`);
//! - **targets** ([`targets`]), only when given: target, achieved average, ratio, pass (achieved
//!   ≥ target: EN 12464-1's maintained illuminance is a floor the average must not fall below);
//! - the **luminaire schedule** ([`schedule`]) from the run summary's sources;
//! - **cubic illuminance** ([`cubic`]) at the probes: vector/scalar ratio, the flow of light.
//!
//! Surfaces covered by another (the floor under a desk leg: `Primitive::covered_from`) are left
//! out of every figure and reported as each row's `covered_area`.
//!
//! It renders as an aligned plain-text table, Markdown, CSV or JSON ([`Format`]).

mod csv;
pub mod cubic;
pub mod render;
pub mod rows;
pub mod schedule;
mod sums;
pub mod targets;

pub use cubic::{Cubic, ProbeRow, ProbeSummary};
pub use rows::{Filter, PlaneRow, Row, Source};
pub use schedule::ScheduleRow;
pub use targets::{TargetRow, Targets};

use crate::Result;
use crate::readback::BakedOutput;

/// Which surface sections to include.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum By {
    Node,
    Material,
    #[default]
    Both,
}

/// How the report is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// Aligned columns for the terminal.
    #[default]
    Table,
    Markdown,
    /// One table per section, each with a `section` column, separated by blank lines.
    Csv,
    Json,
}

/// What to put in the report.
#[derive(Debug, Clone, Default)]
pub struct Options {
    pub by: By,
    pub targets: Option<Targets>,
    /// Working-plane border zone (m, ≥ 0): points closer than this to the edge of its extent
    /// are left out (EN 12464-1 calculation grids); 0 keeps all.
    pub border: f64,
}

/// The report's sections (absent ones are `None`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Report {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by_material: Option<Vec<Row>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by_node: Option<Vec<Row>>,
    /// `null` when the bake measured no working plane.
    pub working_plane: Option<PlaneRow>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub targets: Option<Vec<TargetRow>>,
    /// The luminaire schedule, when the output has a run summary with sources.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub luminaires: Option<Vec<ScheduleRow>>,
    /// Cubic illuminance at the probes, when the bake has probes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cubic: Option<Cubic>,
}

/// Compute the report (errors for targets naming nothing in the bake, and `Error::Settings` for a
/// border that is negative or leaves no working-plane point).
pub fn build(input: &BakedOutput, options: &Options) -> Result<Report> {
    let want = |b: By| options.by == b || options.by == By::Both;
    if !(options.border.is_finite() && options.border >= 0.0) {
        return Err(crate::Error::Settings(format!(
            "--border must be a length ≥ 0 m, got {}",
            options.border
        )));
    }
    let working_plane = match &input.working_plane {
        // The grid is in the run summary: read typed, so an output lacking it is an error.
        Some(plane) => {
            let grid = input.run_summary()?.and_then(|s| s.settings.working_plane);
            Some(rows::plane(plane, grid, options.border).ok_or_else(|| {
                crate::Error::Settings(format!(
                    "--border {} m leaves no working-plane point",
                    options.border
                ))
            })?)
        }
        None => None,
    };
    // The schedule only where the summary reads (an older output's report still builds).
    let luminaires = (input.run_summary().ok().flatten())
        .filter(|s| !s.sources.is_empty())
        .map(|s| schedule::schedule(input, &s.sources));
    let inside = |p: glam::DVec3| {
        (working_plane.as_ref()).is_none_or(|w| rows::inside_border(w.extent, w.border, p))
    };
    let cubic = cubic::cubic(input, inside);
    let targets = match &options.targets {
        Some(t) => Some(t.rows(input, working_plane.as_ref().map(|p| p.e_avg))?),
        None => None,
    };
    Ok(Report {
        by_material: want(By::Material).then(|| rows::by_material(input, &Filter::All)),
        by_node: want(By::Node).then(|| rows::by_node(input, &Filter::All)),
        working_plane,
        targets,
        luminaires,
        cubic,
    })
}

impl Report {
    /// The report as text in `format` (ends with a newline).
    pub fn render(&self, format: Format) -> String {
        match format {
            Format::Table => render::render(self, false),
            Format::Markdown => render::render(self, true),
            Format::Csv => csv::render(self),
            Format::Json => {
                let mut s = serde_json::to_string_pretty(self).expect("the report serialises");
                s.push('\n');
                s
            }
        }
    }
}
