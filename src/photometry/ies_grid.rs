//! IES angle tables → the expanded interpolation [`Grid`], and the IES luminous opening.
//!
//! Input: the vertical and horizontal angles as read (with their line numbers, for errors) and
//! the candela planes (one per horizontal angle, absolute cd). Output: the declared
//! [`Symmetry`] and the grid, or a [`ParseError`] at the angle that breaks LM-63-2002's ranges.
//! Type C: vertical 0°/90° → 90°/180°; horizontal 0° → 0° (axial), 90° (quadrant), 180°
//! (bilateral about C0–C180), 360° (none; also a run ending short of 360° by exactly its last
//! step), or 90° → 270° (LM-63-95: bilateral about C90–C270). Types A/B: both ranges −90° or 0°
//! → 90°; a range from 0° is mirrored (H → −H mirrors about the C0–C180 plane, V → −V about
//! C90–C270 in the photometric frame). B planes are the vertical angles (θ = H + 90°), A planes
//! the horizontal angles (θ = V + 90°), see [`super::frame`].

use super::frame::{Frame, PhotometricType};
use super::grid::Grid;
use super::symmetry::{Plane, Symmetry, complete_c, mirror_planes, mirror_thetas};
use super::tokens::err;
use super::{Opening, OpeningShape, ParseError};

/// Angles equal within this many degrees.
const TOL: f64 = 1e-6;

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < TOL
}

/// Width (Y), length (X), height (Z) in metres → the opening.
pub(super) fn opening(width: f64, length: f64, height: f64) -> Opening {
    let round = width < 0.0 || length < 0.0 || height < 0.0;
    let (mut w, mut l) = (width.abs(), length.abs());
    if round && w == 0.0 {
        w = l;
    }
    if round && l == 0.0 {
        l = w;
    }
    Opening {
        length: l,
        width: w,
        height: height.abs(),
        shape: if round {
            OpeningShape::Round
        } else {
            OpeningShape::Rectangular
        },
    }
}

pub(super) struct Ranges<'a> {
    pub(super) v: &'a [f64],
    pub(super) v_lines: &'a [usize],
    pub(super) h: &'a [f64],
    pub(super) h_lines: &'a [usize],
}

pub(super) fn grid_c(r: &Ranges, planes: Vec<Plane>) -> Result<(Symmetry, Grid), ParseError> {
    let (v0, v1) = (r.v[0], r.v[r.v.len() - 1]);
    if !(same(v0, 0.0) || same(v0, 90.0)) || !(same(v1, 90.0) || same(v1, 180.0)) {
        return Err(err(
            r.v_lines[0],
            format!(
                "expected type C vertical angles from 0° or 90° to 90° or 180°, found {v0}° to {v1}°"
            ),
        ));
    }
    let n = r.h.len();
    let (h0, h1) = (r.h[0], r.h[n - 1]);
    let short_of_360 = n >= 2 && h1 > 180.0 && h1 < 360.0 && same(360.0 - h1, h1 - r.h[n - 2]);
    let symmetry = if same(h0, 0.0) && n == 1 {
        Symmetry::Axial
    } else if same(h0, 0.0) && same(h1, 90.0) {
        Symmetry::Quadrant
    } else if same(h0, 0.0) && same(h1, 180.0) {
        Symmetry::BilateralC0C180
    } else if same(h0, 0.0) && (same(h1, 360.0) || short_of_360) {
        Symmetry::None
    } else if same(h0, 90.0) && same(h1, 270.0) {
        Symmetry::BilateralC90C270
    } else {
        return Err(err(
            r.h_lines[n - 1],
            format!(
                "expected type C horizontal angles from 0° to 0°, 90°, 180° or 360°, or from 90° \
                 to 270°, found {h0}° to {h1}°"
            ),
        ));
    };
    let full = complete_c(planes, symmetry);
    let (angles, values): (Vec<f64>, Vec<Vec<f64>>) = full.into_iter().unzip();
    let grid = Grid::new(
        Frame::of(PhotometricType::C),
        angles,
        r.v.to_vec(),
        values.concat(),
    );
    Ok((symmetry, grid))
}

/// Types A/B: (φ, θ) = (V, H + 90°) for B, (H, V + 90°) for A; ranges −90°/0° → 90°.
pub(super) fn grid_ab(
    ty: PhotometricType,
    r: &Ranges,
    planes: Vec<Plane>,
) -> Result<(Symmetry, Grid), ParseError> {
    let name = if ty == PhotometricType::B { "B" } else { "A" };
    for (a, lines, what) in [(r.v, r.v_lines, "vertical"), (r.h, r.h_lines, "horizontal")] {
        let (a0, a1) = (a[0], a[a.len() - 1]);
        if !(same(a0, -90.0) || same(a0, 0.0)) || !same(a1, 90.0) {
            return Err(err(
                lines[0],
                format!(
                    "expected type {name} {what} angles from −90° or 0° to 90°, found {a0}° to {a1}°"
                ),
            ));
        }
    }
    let h_half = same(r.h[0], 0.0);
    let v_half = same(r.v[0], 0.0);
    // Re-slice the table as half-planes: B planes are the vertical angles, A planes the horizontal.
    let (mut plane_list, theta_src): (Vec<Plane>, &[f64]) = if ty == PhotometricType::B {
        let list =
            r.v.iter()
                .enumerate()
                .map(|(k, &va)| (va, planes.iter().map(|p| p.1[k]).collect()))
                .collect();
        (list, r.h)
    } else {
        (planes, r.v)
    };
    let mut thetas: Vec<f64> = theta_src.iter().map(|a| a + 90.0).collect();
    let (phi_half, theta_half) = if ty == PhotometricType::B {
        (v_half, h_half)
    } else {
        (h_half, v_half)
    };
    if theta_half {
        let (t, p) = mirror_thetas(&thetas, plane_list);
        (thetas, plane_list) = (t, p);
    }
    if phi_half {
        plane_list = mirror_planes(plane_list);
    }
    // H = −H mirrors Y (the C0–C180 plane), V = −V mirrors X (the C90–C270 plane) for A and B.
    let symmetry = match (h_half, v_half) {
        (true, true) => Symmetry::Quadrant,
        (true, false) => Symmetry::BilateralC0C180,
        (false, true) => Symmetry::BilateralC90C270,
        (false, false) => Symmetry::None,
    };
    let (angles, values): (Vec<f64>, Vec<Vec<f64>>) = plane_list.into_iter().unzip();
    Ok((
        symmetry,
        Grid::new(Frame::of(ty), angles, thetas, values.concat()),
    ))
}
