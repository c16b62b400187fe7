//! False-colour plans of a finished bake (`bake plan`): the working plane or one planar node seen
//! square-on, with isolux (or isoluminance) contours labelled in their unit, the room outline, a
//! scale bar, a legend and a title with E avg / min / max and U₀ = min/avg.
//!
//! Input: a [`BakedOutput`] and [`Options`]. Output: a [`Plan`] (the sampled [`field::Field`] in
//! the plane's 2-D frame, outline segments, figures), drawn once into a device-neutral
//! [`layout::Drawing`] that [`svg`] writes as vector SVG text and [`raster`] rasterises into a
//! `picture::Rgb8Image` (PNG bytes come from `export`). Both are deterministic: same input and
//! options, same bytes.
//!
//! Frames ([`frame`]): the working plane and every horizontal surface are seen from above
//! (+Y toward the viewer): x to the right, z down the page. A vertical or tilted surface is seen
//! facing its front (along −normal) with +Y up the page (the plane's steepest ascent).

pub mod field;
pub mod frame;
pub mod layout;
pub mod outline;
pub mod raster;
pub mod surface;
pub mod svg;

use crate::picture::scale::ColourScale;
use crate::readback::BakedOutput;
use crate::{Error, Result};
use field::Field;
use frame::Frame;
use glam::DVec2;

/// What the plan shows.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// The bake's working-plane probes (upward face).
    WorkingPlane,
    /// A planar node, by name or by path (`desk_light/top`).
    Surface(String),
}

/// Which value is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quantity {
    /// lx.
    #[default]
    Illuminance,
    /// cd/m² (surfaces only: the working plane has illuminance only).
    Luminance,
}

impl Quantity {
    pub(crate) fn unit(self) -> &'static str {
        match self {
            Quantity::Illuminance => "lx",
            Quantity::Luminance => "cd/m²",
        }
    }
    /// The symbol in the title line.
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            Quantity::Illuminance => "E",
            Quantity::Luminance => "L",
        }
    }
}

/// `bake plan`'s options.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub source: Source,
    /// `None`: a round range from the values (`ColourScale::auto`); else `[lo, hi]`.
    pub range: Option<[f64; 2]>,
    pub log: bool,
    /// Colour bands (0: a smooth palette, contours at 8 bands' edges).
    pub steps: u32,
    pub quantity: Quantity,
    /// The plan's longer side in pixels (SVG user units or PNG pixels); legend and title add to it.
    pub size: u32,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            source: Source::WorkingPlane,
            range: None,
            log: false,
            steps: 10,
            quantity: Quantity::Illuminance,
            size: 800,
        }
    }
}

/// Largest `--size` (px).
pub const MAX_SIZE: u32 = 8192;
/// Smallest `--size` (px): room for the labels.
pub const MIN_SIZE: u32 = 200;

/// A plan, ready to draw.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The title: the working plane (with its height) or the node's path.
    pub name: String,
    pub quantity: Quantity,
    /// The values on a regular grid in the plane's frame.
    pub field: Field,
    pub frame: Frame,
    /// Line segments in the plane's 2-D frame (m): the room cut by the working plane, or the
    /// surface's boundary edges.
    pub outline: Vec<[DVec2; 2]>,
    /// Average, minimum, maximum of the values (working plane: over its probes; a surface: over
    /// its grid cells), in the quantity's unit.
    pub avg: f64,
    pub min: f64,
    pub max: f64,
    pub scale: ColourScale,
    /// The page size (px).
    pub size: u32,
}

impl Plan {
    /// U₀ = min / avg (0 when avg is not positive).
    pub fn uniformity(&self) -> f64 {
        if self.avg > 0.0 {
            self.min / self.avg
        } else {
            0.0
        }
    }

    /// The plan as SVG text.
    pub fn svg(&self) -> String {
        svg::render(&layout::draw(self))
    }

    /// The plan as an sRGB image.
    pub fn image(&self) -> crate::picture::Rgb8Image {
        raster::render(&layout::draw(self))
    }
}

/// Check the options (usage errors: `Error::Settings`).
pub fn check(options: &Options) -> Result<()> {
    if !(MIN_SIZE..=MAX_SIZE).contains(&options.size) {
        return Err(Error::Settings(format!(
            "--size {}: must be {MIN_SIZE} to {MAX_SIZE} px",
            options.size
        )));
    }
    if options.steps > 64 {
        return Err(Error::Settings(format!(
            "--steps {}: at most 64 bands",
            options.steps
        )));
    }
    if let Some([lo, hi]) = options.range {
        ColourScale::fixed(lo, hi, options.log, options.steps)
            .map_err(|e| Error::Settings(format!("--scale {lo}:{hi}: {e}")))?;
    }
    if options.source == Source::WorkingPlane && options.quantity == Quantity::Luminance {
        return Err(Error::Settings(
            "--quantity luminance: the working plane has illuminance only (use --surface NODE)"
                .into(),
        ));
    }
    Ok(())
}

/// The plan of `input` as `options` ask.
pub fn build(input: &BakedOutput, options: &Options) -> Result<Plan> {
    check(options)?;
    let (name, frame, field, outline, stats) = match &options.source {
        Source::WorkingPlane => field::working_plane(input, field::cells(options.size))?,
        Source::Surface(node) => {
            surface::sample(input, node, options.quantity, field::cells(options.size))?
        }
    };
    let [avg, min, max] = stats;
    let scale = match options.range {
        Some([lo, hi]) => ColourScale::fixed(lo, hi, options.log, options.steps)
            .map_err(|e| Error::Settings(format!("--scale {lo}:{hi}: {e}")))?,
        None => {
            let values: Vec<f64> = field
                .values
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .collect();
            let values: Vec<f64> = if options.log {
                values.into_iter().filter(|&v| v > 0.0).collect()
            } else {
                values
            };
            if values.is_empty() {
                return Err(Error::input(
                    &input.file,
                    "",
                    format!(
                        "{name}: no {} to draw{}",
                        if options.log {
                            "positive value"
                        } else {
                            "value"
                        },
                        if options.log {
                            " on a logarithmic scale"
                        } else {
                            ""
                        }
                    ),
                ));
            }
            ColourScale::auto(&values, options.log, options.steps)
        }
    };
    Ok(Plan {
        name,
        quantity: options.quantity,
        field,
        frame,
        outline,
        avg,
        min,
        max,
        scale,
        size: options.size,
    })
}
