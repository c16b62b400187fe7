//! Photometric types A, B and C and how their angles map into the photometric frame.
//!
//! Every type is stored as half-planes around a polar axis `P`: the plane angle φ turns about
//! `P` from the reference direction `R` towards `Q`, and θ is the angle from `P` within the
//! half-plane, so a direction is `cos θ·P + sin θ·(cos φ·R + sin φ·Q)`.
//!
//! | type | file angles (h, v) | φ | θ | P | R (φ = 0, θ = 90°) | Q (φ = 90°, θ = 90°) |
//! | --- | --- | --- | --- | --- | --- | --- |
//! | C | C, γ | h | v | −Z (nadir) | +X | +Y |
//! | B | H, V | v | h + 90° | +Y | −Z | +X |
//! | A | H, V | h | v + 90° | −X | −Z | −Y |
//!
//! Type C: C counter-clockwise seen from +Z, γ from the nadir (LM-63 and EULUMDAT).
//! Types A and B follow EXT_lights_ies: the aiming direction (H, V) = (0, 0) is −Z and the
//! vertical photometric plane (H = 0) is the X/Z plane, with V > 0 towards +X (LM-63's
//! "photometric horizontal" H = 0, V = 90° is +X for types B and C alike). LM-63 measures A/B
//! horizontal angles clockwise, so H > 0 turns towards −Y. B planes share the horizontal axis Y
//! (V selects the plane, H is the lateral angle within it); A planes share the axis X (H selects
//! the plane, V is the elevation within it). Note that LM-63 calls type A's V = −90° "photometric
//! zero" (nadir); here, as EXT_lights_ies says, the aim (0, 0) is −Z, so that direction is −X.

use glam::DVec3;

/// The photometric type (goniometer system) of the file's angles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum PhotometricType {
    /// Type A (LM-63 code 3): planes about the luminaire's major (here X) axis.
    A,
    /// Type B (LM-63 code 2): planes about the horizontal (here Y) axis; floodlights.
    B,
    /// Type C (LM-63 code 1, EULUMDAT): planes about the vertical axis.
    C,
}

impl PhotometricType {
    /// Unit direction in the photometric frame of the file's angle pair, in degrees:
    /// `(horizontal, vertical)` = (C, γ) for type C, (H, V) for types A and B.
    pub fn direction(self, horizontal_deg: f64, vertical_deg: f64) -> DVec3 {
        let (phi, theta) = self.to_grid(horizontal_deg, vertical_deg);
        Frame::of(self).direction(phi, theta)
    }

    /// The file's angle pair (degrees) of a direction: (C in [0°, 360°), γ) for type C,
    /// (H, V) in [−180°, 180°] × [−90°, 90°] for type B and [−90°, 90°] × [−180°, 180°] for A.
    pub fn angles(self, dir: DVec3) -> (f64, f64) {
        let (phi, theta) = Frame::of(self).angles(dir);
        match self {
            PhotometricType::C => (phi, theta),
            PhotometricType::B => (theta - 90.0, phi),
            PhotometricType::A => (phi, theta - 90.0),
        }
    }

    /// (φ, θ) in degrees of the file's (horizontal, vertical) angles.
    pub(super) fn to_grid(self, h: f64, v: f64) -> (f64, f64) {
        match self {
            PhotometricType::C => (h, v),
            PhotometricType::B => (v, h + 90.0),
            PhotometricType::A => (h, v + 90.0),
        }
    }
}

/// The axes of a photometric type's half-plane system (see the module docs).
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    p: DVec3,
    r: DVec3,
    q: DVec3,
    /// φ is periodic over 360° (type C); otherwise φ is in (−180°, 180°].
    pub(super) periodic: bool,
}

impl Frame {
    pub(super) fn of(ty: PhotometricType) -> Frame {
        let (p, r, q) = match ty {
            PhotometricType::C => (DVec3::NEG_Z, DVec3::X, DVec3::Y),
            PhotometricType::B => (DVec3::Y, DVec3::NEG_Z, DVec3::X),
            PhotometricType::A => (DVec3::NEG_X, DVec3::NEG_Z, DVec3::NEG_Y),
        };
        Frame {
            p,
            r,
            q,
            periodic: ty == PhotometricType::C,
        }
    }

    /// Unit direction of (φ, θ) in degrees.
    pub(super) fn direction(&self, phi: f64, theta: f64) -> DVec3 {
        let (sp, cp) = phi.to_radians().sin_cos();
        let (st, ct) = theta.to_radians().sin_cos();
        ct * self.p + st * (cp * self.r + sp * self.q)
    }

    /// (φ, θ) in degrees of any non-zero direction; φ in [0°, 360°) when periodic.
    #[inline]
    pub(super) fn angles(&self, dir: DVec3) -> (f64, f64) {
        let (z, x, y) = (dir.dot(self.p), dir.dot(self.r), dir.dot(self.q));
        let theta = crate::geom::atan::atan2((x * x + y * y).sqrt(), z).to_degrees();
        let mut phi = crate::geom::atan::atan2(y, x).to_degrees();
        if self.periodic && phi < 0.0 {
            phi += 360.0;
            if phi >= 360.0 {
                phi = 0.0;
            }
        }
        (phi, theta)
    }
}
