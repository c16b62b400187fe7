//! The designer's flux table (Lynes' method, the seed paper's Appendix A and Table 1): from the
//! illuminance wanted on each surface to the direct flux the luminaires must put there.
//!
//! Input: [`DesignRow`]s — name, area A (m²), reflectance R (in [0, 1)), design illuminance E
//! (lx) — parsed from CSV text by [`parse`] (no I/O here; the caller reads the file).
//! Output: a [`FluxTable`]: per surface the reflected flux A·R·E (lm), the direct illuminance
//! E − E_r (lx) and the direct flux (E − E_r)·A (lm); totals ΣA, ΣA·R·E, the indirect illuminance
//! E_r = ΣA·R·E / ΣA (lx) and the total direct flux. Rendered as a table, Markdown, CSV or JSON.
//!
//! The seed's Appendix A prints E_rs = A_s R_s E_s / A after "sum (5) for total reflected flux":
//! the numerator is that sum (Table 1: 15 212 lm / 163.2 m² = 93 lx), as here. The inter-reflected
//! light is taken as uniform over all surfaces (Lynes' simplification, no series over bounces).
//! A surface designed below E_r gets a negative direct part: kept (it says the design asks for
//! less than reflection alone gives) and reported in [`FluxTable::warnings`].

mod parse;
mod render;

pub use crate::table::Format;
pub use parse::{COLUMNS, OPTIONAL, parse};

/// One surface of the design: the input row.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DesignRow {
    pub name: String,
    /// m²; `None` when the table leaves it to a bake (`bake design --scene`).
    pub area: Option<f64>,
    /// Diffuse reflectance, in [0, 1).
    pub reflectance: f64,
    /// Design illuminance, lx.
    pub illuminance: f64,
    /// What the row names in a bake (`--scene`, `bake fit`); the name itself when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface: Option<String>,
    /// 1-based line of the row in its file.
    #[serde(skip)]
    pub line: usize,
}

/// One surface of the flux table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FluxRow {
    pub name: String,
    /// m².
    pub area: f64,
    pub reflectance: f64,
    /// Design illuminance E, lx.
    pub illuminance: f64,
    /// A·R·E, lm.
    pub reflected_flux: f64,
    /// E − E_r, lx (negative when the design is below the indirect illuminance).
    pub direct_illuminance: f64,
    /// (E − E_r)·A, lm.
    pub direct_flux: f64,
}

/// The sums under the table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Totals {
    /// ΣA, m².
    pub area: f64,
    /// ΣA·R·E, lm.
    pub reflected_flux: f64,
    /// E_r = ΣA·R·E / ΣA, lx: the inter-reflected illuminance taken as uniform.
    pub indirect_illuminance: f64,
    /// Σ(E − E_r)·A, lm: the flux the luminaires must put directly on the listed surfaces.
    pub direct_flux: f64,
}

/// The flux table of a design.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FluxTable {
    pub rows: Vec<FluxRow>,
    pub totals: Totals,
    /// One sentence per surface designed below E_r (its direct part is negative).
    pub warnings: Vec<String>,
}

impl FluxTable {
    /// The flux table of `rows` (at least one row: [`parse`] ensures it); the first row without
    /// an area is the error.
    pub fn compute(rows: &[DesignRow]) -> Result<FluxTable, &DesignRow> {
        if let Some(r) = rows.iter().find(|r| r.area.is_none()) {
            return Err(r);
        }
        let rows: Vec<(&DesignRow, f64)> = (rows.iter())
            .map(|r| (r, r.area.expect("checked above")))
            .collect();
        let area: f64 = rows.iter().map(|(_, a)| a).sum();
        let reflected: Vec<f64> = rows
            .iter()
            .map(|(r, a)| a * r.reflectance * r.illuminance)
            .collect();
        let reflected_flux: f64 = reflected.iter().sum();
        let e_r = if area > 0.0 {
            reflected_flux / area
        } else {
            0.0
        };
        let rows: Vec<FluxRow> = rows
            .iter()
            .zip(&reflected)
            .map(|(&(r, area), &reflected_flux)| FluxRow {
                name: r.name.clone(),
                area,
                reflectance: r.reflectance,
                illuminance: r.illuminance,
                reflected_flux,
                direct_illuminance: r.illuminance - e_r,
                direct_flux: (r.illuminance - e_r) * area,
            })
            .collect();
        let warnings = rows
            .iter()
            .filter(|r| r.direct_illuminance < 0.0)
            .map(|r| {
                format!(
                    "{}: designed at {} lx, below the indirect illuminance E_r = {:.1} lx; \
                     its direct part is negative (reflection alone gives more)",
                    r.name,
                    render::short(r.illuminance, 1),
                    e_r
                )
            })
            .collect();
        let direct_flux = rows.iter().map(|r| r.direct_flux).sum();
        Ok(FluxTable {
            rows,
            totals: Totals {
                area,
                reflected_flux,
                indirect_illuminance: e_r,
                direct_flux,
            },
            warnings,
        })
    }

    /// The table as text in `format` (ends with a newline).
    pub fn render(&self, format: Format) -> String {
        match format {
            Format::Table => render::render(self, false),
            Format::Markdown => render::render(self, true),
            Format::Csv => render::csv(self),
            Format::Json => {
                let mut s = serde_json::to_string_pretty(self).expect("the table serialises");
                s.push('\n');
                s
            }
        }
    }
}
