//! `bake fit`: dimming factors for groups of luminaires that bring each designed surface's
//! average illuminance as close as possible to the design (the seed's Figure 4 loop, closed).
//!
//! Input: a scene, design targets ([`Targets`]: keys as `bake report --targets` reads them —
//! node paths, `material:NAME`, faces, `working_plane` — each with an illuminance in lx), the
//! [`Group`]s of sources, the bake's settings and the largest factor. Output: a [`Fit`] (factor
//! per group; design, achieved and ratio per surface) and the scene with the factors applied.
//!
//! Method: light is linear in the sources. The scene is meshed once, its transport operator
//! built and balanced once, and each group (and the sources no group takes, kept as they are)
//! lights it alone: one solve each, several right-hand sides on one operator
//! (`bake::bake_groups`). Each result is read as the output it would write and measured as the
//! report measures (`report::Targets`), giving the response matrix A (surface × group, lx per
//! unit factor) and the fixed part c. The factors minimise Σ_s ((A x + c)_s / E_s − 1)², the
//! relative errors, subject to 0 ≤ x ≤ max ([`bvls`]). Adaptive meshing follows the light, so
//! the fit is repeated on the mesh of the fitted scene (at most [`PASSES`] meshes, until no
//! factor moves by more than 10⁻³ of the largest): what `fit` reports is then what a bake of
//! the fitted scene gives, on that scene's own mesh.

pub mod bvls;
pub mod groups;
mod render;

pub use groups::{Group, GroupBy, SourceId};

use crate::progress::Progress;
use crate::report::{self, Targets};
use crate::scene::Scene;
use crate::settings::Settings;
use crate::{Error, Result};

/// Most meshes the fit is solved on.
pub const PASSES: usize = 3;

/// What the fit may do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Largest factor (1: dimming only; more when the installation may be driven harder).
    pub max_factor: f64,
    /// Working-plane border zone (m) left out of a `working_plane` target, as `bake report
    /// --border` leaves it out.
    pub border: f64,
}

/// One group's factor.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GroupFactor {
    pub name: String,
    /// The sources in it, by name.
    pub sources: Vec<String>,
    pub factor: f64,
    /// The factor is the largest allowed: the design wants more light from this group than
    /// `max_factor` gives (raise it, or add luminaires).
    pub at_maximum: bool,
    /// The factor is 0: the design is better off without this group.
    pub off: bool,
}

/// One designed surface.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SurfaceFit {
    /// The design's name for it.
    pub name: String,
    /// What it names in the bake (`wall_back`, `material:picture`, `working_plane`...).
    pub key: String,
    /// lx.
    pub design: f64,
    /// lx, with the fitted factors.
    pub achieved: f64,
    /// achieved / design.
    pub ratio: f64,
    /// lx per unit factor of each group, in group order.
    pub response: Vec<f64>,
    /// lx from the sources no group takes.
    pub fixed: f64,
}

/// The fit's result.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Fit {
    pub groups: Vec<GroupFactor>,
    /// Sources kept as they are.
    pub fixed_sources: Vec<String>,
    pub surfaces: Vec<SurfaceFit>,
    /// √(mean of (ratio − 1)²).
    pub rms_relative_error: f64,
    pub max_factor: f64,
    /// Meshes the fit was solved on.
    pub passes: usize,
}

/// A design target: the design's name for the surface, and the target it becomes.
pub struct Design {
    pub names: Vec<String>,
    pub targets: Targets,
}

/// Fit `groups` of `scene`'s sources to `design`; returns the fit and the fitted scene.
pub fn fit(
    scene: &Scene,
    design: &Design,
    groups: &[Group],
    settings: &Settings,
    options: Options,
    progress: &dyn Progress,
) -> Result<(Fit, Scene)> {
    if groups.is_empty() {
        return Err(Error::Settings(
            "the scene has no light source to fit (no luminaire, light or emitting material)"
                .into(),
        ));
    }
    if !(options.max_factor.is_finite() && options.max_factor > 0.0) {
        return Err(Error::Settings(format!(
            "--max-factor must be a number > 0, got {}",
            options.max_factor
        )));
    }
    if !(options.border.is_finite() && options.border >= 0.0) {
        return Err(Error::Settings(format!(
            "--border {}: a length ≥ 0 m is expected (e.g. 0.5)",
            options.border
        )));
    }
    if let Some((key, _)) = (design.targets.entries.iter()).find(|(_, e)| e.is_nan() || *e <= 0.0) {
        return Err(Error::input(
            &design.targets.file,
            "",
            format!("'{key}' is designed at 0 lx: a relative error needs a design above 0"),
        ));
    }
    let fixed = groups::ungrouped(scene, groups);
    let mut lit: Vec<Scene> = (groups.iter())
        .map(|g| groups::lit_by(scene, &g.sources))
        .collect();
    if !fixed.is_empty() {
        lit.push(groups::lit_by(scene, &fixed));
    }
    let mut factors = vec![1.0; groups.len()];
    let mut passes = 0;
    let mut responses;
    loop {
        let mesh_scene = groups::scaled(scene, groups, &factors);
        responses = measure(&mesh_scene, &lit, design, settings, options, progress)?;
        passes += 1;
        let next = solve(
            &responses,
            &design.targets,
            groups.len(),
            options.max_factor,
        );
        // Solved on the mesh the factors it started from make: done when they hardly move.
        let largest = next.iter().fold(0.0_f64, |a, b| a.max(*b));
        let moved = (next.iter().zip(&factors)).any(|(a, b)| (a - b).abs() > 1e-3 * largest);
        factors = next;
        if passes == PASSES || !moved {
            break;
        }
    }
    let fitted = groups::scaled(scene, groups, &factors);
    let surfaces: Vec<SurfaceFit> = (design.targets.entries.iter())
        .zip(&design.names)
        .enumerate()
        .map(|(s, ((key, target), name))| {
            let response: Vec<f64> = (0..groups.len()).map(|g| responses[g][s]).collect();
            let fixed_lx = match fixed.is_empty() {
                true => 0.0,
                false => responses[groups.len()][s],
            };
            let achieved = fixed_lx
                + (response.iter().zip(&factors))
                    .map(|(a, x)| a * x)
                    .sum::<f64>();
            SurfaceFit {
                name: name.clone(),
                key: key.clone(),
                design: *target,
                achieved,
                ratio: achieved / target,
                response,
                fixed: fixed_lx,
            }
        })
        .collect();
    let rms = (surfaces
        .iter()
        .map(|s| (s.ratio - 1.0).powi(2))
        .sum::<f64>()
        / surfaces.len().max(1) as f64)
        .sqrt();
    let fit = Fit {
        groups: (groups.iter().zip(&factors))
            .map(|(g, &factor)| GroupFactor {
                name: g.name.clone(),
                sources: (g.sources.iter())
                    .map(|&id| groups::describe(scene, id))
                    .collect(),
                factor,
                at_maximum: factor >= options.max_factor,
                off: factor == 0.0,
            })
            .collect(),
        fixed_sources: fixed
            .iter()
            .map(|&id| groups::describe(scene, id))
            .collect(),
        surfaces,
        rms_relative_error: rms,
        max_factor: options.max_factor,
        passes,
    };
    Ok((fit, fitted))
}

/// Per lit scene, the average illuminance on each target (lx), on the mesh of `mesh_scene`.
fn measure(
    mesh_scene: &Scene,
    lit: &[Scene],
    design: &Design,
    settings: &Settings,
    options: Options,
    progress: &dyn Progress,
) -> Result<Vec<Vec<f64>>> {
    let results = crate::bake::bake_groups(mesh_scene, lit, settings, progress)?;
    let targets = &design.targets;
    let options = report::Options {
        by: report::By::Node,
        targets: Some(targets.clone()),
        border: options.border,
    };
    (lit.iter().zip(&results))
        .map(|(scene, result)| {
            let baked = crate::readback::as_written(scene, result)?;
            let rows = report::build(&baked, &options)?
                .targets
                .expect("targets were asked for");
            rows.iter()
                .map(|r| r.achieved.ok_or_else(|| targets.no_working_plane()))
                .collect()
        })
        .collect()
}

/// The factors minimising the relative errors (responses: per lit scene, per target; a last
/// entry beyond the groups is the fixed part).
fn solve(responses: &[Vec<f64>], targets: &Targets, groups: usize, max: f64) -> Vec<f64> {
    let m: Vec<Vec<f64>> = (targets.entries.iter().enumerate())
        .map(|(s, (_, t))| (0..groups).map(|g| responses[g][s] / t).collect())
        .collect();
    let y: Vec<f64> = (targets.entries.iter().enumerate())
        .map(|(s, (_, t))| 1.0 - responses.get(groups).map_or(0.0, |c| c[s]) / t)
        .collect();
    bvls::solve(&m, &y, max)
}

impl Fit {
    /// The fit as text in `format`.
    pub fn render(&self, format: crate::design::Format) -> String {
        render::render(self, format)
    }
}
