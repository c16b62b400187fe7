//! Declared symmetries and the expansion of stored planes to the full measured range.
//!
//! Input: the planes a file stores (angle, values at every θ node) and its declared symmetry.
//! Output: every plane the symmetry implies, sorted, each angle once (a duplicate produced by a
//! mirror is dropped; a file's own value wins). Type C angles are normalised into [0°, 360°)
//! (a 360° plane is the 0° plane). Symmetries are named in the photometric frame for every type:
//! the C0–C180 plane is the X/Z plane, the C90–C270 plane the Y/Z plane.

use super::grid::EPS_DEG;

/// The symmetry a file declares, in the photometric frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum Symmetry {
    /// Rotational symmetry about the vertical axis (one plane).
    Axial,
    /// Symmetric about both the C0–C180 and the C90–C270 planes (one quadrant stored).
    Quadrant,
    /// Symmetric about the C0–C180 plane: I(C) = I(360° − C).
    BilateralC0C180,
    /// Symmetric about the C90–C270 plane: I(C) = I(180° − C).
    BilateralC90C270,
    /// No symmetry: the whole range is stored.
    None,
}

impl Symmetry {
    /// Human-readable name.
    pub(crate) fn describe(self) -> &'static str {
        match self {
            Symmetry::Axial => "axial (rotational)",
            Symmetry::Quadrant => "quadrant (C0-C180 and C90-C270)",
            Symmetry::BilateralC0C180 => "bilateral about C0-C180",
            Symmetry::BilateralC90C270 => "bilateral about C90-C270",
            Symmetry::None => "none",
        }
    }
}

/// A stored plane: its angle (degrees) and its values at every θ node.
pub(super) type Plane = (f64, Vec<f64>);

/// Type C planes completed to [0°, 360°) by `sym`.
pub(super) fn complete_c(planes: Vec<Plane>, sym: Symmetry) -> Vec<Plane> {
    let images: &[fn(f64) -> f64] = match sym {
        Symmetry::Axial | Symmetry::None => &[|c| c],
        Symmetry::Quadrant => &[|c| c, |c| 180.0 - c, |c| 180.0 + c, |c| 360.0 - c],
        Symmetry::BilateralC0C180 => &[|c| c, |c| 360.0 - c],
        Symmetry::BilateralC90C270 => &[|c| c, |c| 180.0 - c],
    };
    let mut out: Vec<Plane> = Vec::new();
    for image in images {
        for (c, v) in &planes {
            let mut a = image(*c).rem_euclid(360.0);
            if a > 360.0 - EPS_DEG {
                a = 0.0;
            }
            out.push((a, v.clone()));
        }
    }
    dedup_sorted(out)
}

/// Non-periodic planes (types A/B) completed by the mirror φ → −φ.
pub(super) fn mirror_planes(planes: Vec<Plane>) -> Vec<Plane> {
    let mirrored = planes.iter().map(|(a, v)| (-a, v.clone()));
    let all: Vec<Plane> = planes.iter().cloned().chain(mirrored).collect();
    dedup_sorted(all)
}

/// θ nodes in [90°, 180°] completed by the mirror θ → 180° − θ (values follow).
pub(super) fn mirror_thetas(thetas: &[f64], planes: Vec<Plane>) -> (Vec<f64>, Vec<Plane>) {
    let skip = usize::from((thetas[0] - 90.0).abs() < EPS_DEG);
    let mut full: Vec<f64> = thetas.iter().skip(skip).rev().map(|t| 180.0 - t).collect();
    full.extend_from_slice(thetas);
    let planes = planes
        .into_iter()
        .map(|(a, v)| {
            let mut w: Vec<f64> = v.iter().skip(skip).rev().copied().collect();
            w.extend_from_slice(&v);
            (a, w)
        })
        .collect();
    (full, planes)
}

fn dedup_sorted(mut planes: Vec<Plane>) -> Vec<Plane> {
    // Stable sort: for equal angles the file's own plane (pushed first) stays first.
    planes.sort_by(|a, b| a.0.total_cmp(&b.0));
    planes.dedup_by(|b, a| (b.0 - a.0).abs() < EPS_DEG);
    planes
}
