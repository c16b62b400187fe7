//! A plane's 2-D frame for a plan: world point → (right, down) on the page, in metres.
//!
//! Horizontal planes (|n·Y| > 0.9999) are seen from above whichever way they face: right = +x,
//! down = +z (+Y toward the viewer). Other planes are seen facing their front (the viewer on the
//! side the normal points to): up the page = +Y projected into the plane, right = up × n.
//! Coordinates are absolute (no origin shift), so the working plane's are world (x, z).

use glam::{DVec2, DVec3};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The plane's normal (its front; +Y for the working plane).
    pub normal: DVec3,
    /// World direction of the page's right.
    pub right: DVec3,
    /// World direction of the page's down.
    pub down: DVec3,
}

impl Frame {
    /// The frame of a plane with unit normal `n`.
    pub(crate) fn of_normal(n: DVec3) -> Frame {
        if n.y.abs() > 0.9999 {
            return Frame {
                normal: n,
                right: DVec3::X,
                down: DVec3::Z,
            };
        }
        let up = (DVec3::Y - n * n.y).normalize();
        Frame {
            normal: n,
            right: up.cross(n),
            down: -up,
        }
    }

    /// The point's page coordinates (m).
    pub(crate) fn on_page(&self, p: DVec3) -> DVec2 {
        DVec2::new(p.dot(self.right), p.dot(self.down))
    }

    /// Whether it is seen from above (horizontal).
    pub(crate) fn seen_from_above(&self) -> bool {
        self.down == DVec3::Z && self.right == DVec3::X
    }

    /// The note under the title: how the plane is seen and which way the axes run.
    pub(crate) fn note(&self) -> String {
        if self.seen_from_above() {
            return "seen from above, +Y up (toward the viewer); x \u{2192}, z \u{2193}".into();
        }
        format!(
            "seen facing its front (normal {}), +Y up the page; right = {}",
            axis(self.normal),
            axis(self.right)
        )
    }
}

/// `+x`, `-z`, … for an axis direction, else `(x, y, z)` with two decimals.
fn axis(v: DVec3) -> String {
    for (a, name) in [(DVec3::X, "x"), (DVec3::Y, "y"), (DVec3::Z, "z")] {
        let d = v.dot(a);
        if d > 0.9999 {
            return format!("+{name}");
        }
        if d < -0.9999 {
            return format!("-{name}");
        }
    }
    format!("({:.2}, {:.2}, {:.2})", v.x, v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_right_handed_and_seen_as_documented() {
        // A wall facing +z seen from its front: x to the right, +Y up.
        let f = Frame::of_normal(DVec3::Z);
        assert!((f.right - DVec3::X).length() < 1e-12);
        assert!((f.down + DVec3::Y).length() < 1e-12);
        // Facing −x: the viewer at −x looking along +x, +Y up, has +z on the right.
        let f = Frame::of_normal(-DVec3::X);
        assert!((f.right - DVec3::Z).length() < 1e-12);
        // Right × up = toward the viewer (the normal).
        for n in [DVec3::Z, -DVec3::X, DVec3::new(0.3, 0.5, 0.8).normalize()] {
            let f = Frame::of_normal(n);
            assert!((f.right.cross(-f.down) - n).length() < 1e-12);
        }
        // Horizontal: from above, x right, z down; right × up(−z) = +Y.
        let f = Frame::of_normal(-DVec3::Y);
        assert_eq!(f.on_page(DVec3::new(1.0, 2.0, 3.0)), DVec2::new(1.0, 3.0));
        assert!((DVec3::X.cross(-DVec3::Z) - DVec3::Y).length() < 1e-12);
    }
}
