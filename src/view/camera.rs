//! The pinhole camera of a view, as glTF's perspective camera: eye, unit forward (the camera's
//! local −Z), up (+Y by default) and right; `yfov` the vertical field of view; image row 0 at
//! the top. Rays go through points of the image plane given in pixel coordinates (x right from
//! the left edge, y down from the top edge, pixel (i, j) spans [i, i + 1] × [j, j + 1]) and
//! start on the near plane (`near` m in front of the eye along forward, as a rasteriser clips).
//!
//! Invariants: forward, up and right are orthonormal and right-handed (right = forward × up);
//! the size is 1…[`MAX_EDGE`] pixels on each side.

use crate::readback::{Camera as CameraNode, Projection};
use crate::{Error, Result};
use glam::{DVec2, DVec3};

/// Largest image edge (pixels).
pub const MAX_EDGE: u32 = 16384;

/// Default image width (pixels); the default height is 720, or the width over a camera's aspect.
pub const DEFAULT_WIDTH: u32 = 1280;
pub const DEFAULT_HEIGHT: u32 = 720;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub forward: DVec3,
    pub up: DVec3,
    pub right: DVec3,
    /// Vertical field of view (rad).
    pub yfov: f64,
    pub width: u32,
    pub height: u32,
    /// Distance of the near plane (m), ≥ 0.
    pub near: f64,
}

/// Check an image size given by the user.
pub fn check_size(width: u32, height: u32) -> Result<()> {
    if width == 0 || height == 0 || width > MAX_EDGE || height > MAX_EDGE {
        return Err(Error::Settings(format!(
            "view size {width}x{height}: each side must be 1 to {MAX_EDGE} pixels"
        )));
    }
    Ok(())
}

impl Camera {
    /// A camera at `eye` looking at `target`, `up` giving the image's up direction (it need not
    /// be orthogonal to the view direction, only not parallel to it); `fov_deg` the vertical
    /// field of view in degrees.
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_deg: f64,
        (width, height): (u32, u32),
        near: f64,
    ) -> Result<Camera> {
        let bad = |m: String| Err(Error::Settings(m));
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return bad("eye, target and up must be finite".into());
        }
        let forward = (target - eye).normalize_or_zero();
        if forward == DVec3::ZERO {
            return bad("the target must differ from the eye".into());
        }
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return bad(format!(
                "field of view {fov_deg}°: it must be between 0 and 180 degrees"
            ));
        }
        Camera::with_axes(
            eye,
            forward,
            up,
            fov_deg.to_radians(),
            (width, height),
            near,
        )
    }

    /// The camera of a glTF camera node: its origin, local −Z forward and local +Y up (scale
    /// removed); `size` given, or 1280 wide and as high as its aspect ratio makes it (720 without
    /// one); `near` given, or its `znear`.
    pub(crate) fn from_node(
        node: &CameraNode,
        size: Option<(u32, u32)>,
        near: Option<f64>,
    ) -> Result<Camera> {
        let Projection::Perspective {
            yfov,
            aspect_ratio,
            znear,
        } = node.projection
        else {
            return Err(Error::Settings(format!(
                "camera {}: orthographic cameras are not supported (perspective only)",
                node.name.as_deref().unwrap_or("(unnamed)")
            )));
        };
        let size = size.unwrap_or_else(|| match aspect_ratio {
            Some(a) => {
                let h = (DEFAULT_WIDTH as f64 / a)
                    .round()
                    .clamp(1.0, MAX_EDGE as f64);
                (DEFAULT_WIDTH, h as u32)
            }
            None => (DEFAULT_WIDTH, DEFAULT_HEIGHT),
        });
        let m = node.world_from_local;
        let eye = m.transform_point3(DVec3::ZERO);
        let forward = m.transform_vector3(-DVec3::Z).normalize_or_zero();
        let up = m.transform_vector3(DVec3::Y);
        Camera::with_axes(eye, forward, up, yfov, size, near.unwrap_or(znear))
    }

    fn with_axes(
        eye: DVec3,
        forward: DVec3,
        up: DVec3,
        yfov: f64,
        (width, height): (u32, u32),
        near: f64,
    ) -> Result<Camera> {
        check_size(width, height)?;
        if !(near.is_finite() && near >= 0.0) {
            return Err(Error::Settings(format!(
                "near distance {near}: must be ≥ 0"
            )));
        }
        let right = forward.cross(up).normalize_or_zero();
        if right == DVec3::ZERO || forward == DVec3::ZERO {
            return Err(Error::Settings(
                "the up direction must not be parallel to the view direction".into(),
            ));
        }
        Ok(Camera {
            eye,
            forward,
            up: right.cross(forward),
            right,
            yfov,
            width,
            height,
            near,
        })
    }

    /// The unit direction of the ray through image point `p` (pixel coordinates).
    pub(crate) fn direction(&self, p: DVec2) -> DVec3 {
        let (w, h) = (self.width as f64, self.height as f64);
        let t = (self.yfov / 2.0).tan();
        let x = (2.0 * p.x / w - 1.0) * t * (w / h);
        let y = (1.0 - 2.0 * p.y / h) * t;
        (self.forward + self.right * x + self.up * y).normalize()
    }

    /// Where the ray along unit `dir` starts: on the near plane.
    pub(crate) fn origin(&self, dir: DVec3) -> DVec3 {
        self.eye + dir * (self.near / dir.dot(self.forward))
    }

    /// The point the camera looks at, one metre ahead (for the EXR header).
    pub fn target(&self) -> DVec3 {
        self.eye + self.forward
    }
}

/// Fixed antialiasing offsets from a pixel's centre (in pixels, within ±0.5): the centre alone
/// for 1 sample, the rotated grid for 4, a regular k × k grid for n = k² (see
/// [`valid_samples`]); all deterministic, centred on the pixel's centre.
pub(crate) fn sample_offsets(n: u32) -> Vec<DVec2> {
    match n {
        0 | 1 => vec![DVec2::ZERO],
        4 => [
            (0.125, 0.375),
            (0.375, -0.125),
            (-0.125, -0.375),
            (-0.375, 0.125),
        ]
        .map(|(x, y)| DVec2::new(x, y))
        .to_vec(),
        _ => {
            let k = (n as f64).sqrt().round() as u32;
            let at = |i: u32| (i as f64 + 0.5) / k as f64 - 0.5;
            (0..k * k)
                .map(|i| DVec2::new(at(i % k), at(i / k)))
                .collect()
        }
    }
}

/// Sample counts [`sample_offsets`] knows: 1, 4 and the squares of 3…16.
pub(crate) fn valid_samples(n: u32) -> bool {
    let k = (n as f64).sqrt().round() as u32;
    (1..=256).contains(&n) && k * k == n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_centres_and_corners_follow_the_field_of_view() {
        let c = Camera::look_at(
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, -5.0),
            DVec3::Y,
            90.0,
            (200, 100),
            0.0,
        )
        .unwrap();
        assert_eq!(c.right, DVec3::X);
        let centre = c.direction(DVec2::new(100.0, 50.0));
        assert!((centre - -DVec3::Z).length() < 1e-12);
        // Top edge: 45° up; left edge: atan(2 · tan 45°) to the left; row 0 is at the top.
        let top = c.direction(DVec2::new(100.0, 0.0));
        assert!((top.y - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
        let left = c.direction(DVec2::new(0.0, 50.0));
        assert!((left.x / -left.z - -2.0).abs() < 1e-12);
        assert!(Camera::look_at(DVec3::ZERO, DVec3::Y, DVec3::Y, 60.0, (4, 4), 0.0).is_err());
        assert!(check_size(0, 10).is_err() && check_size(16385, 10).is_err());
        assert!(check_size(16384, 1).is_ok());
    }

    #[test]
    fn offsets_stay_inside_the_pixel_and_average_to_its_centre() {
        for n in [1, 4, 9, 16, 256] {
            let o = sample_offsets(n);
            assert_eq!(o.len(), n as usize);
            assert!(!valid_samples(n + 1));
            assert!(o.iter().all(|p| p.x.abs() < 0.5 && p.y.abs() < 0.5));
            let mean = o.iter().sum::<DVec2>() / n as f64;
            assert!(mean.length() < 1e-12, "{n}: {mean}");
            assert!(valid_samples(n));
        }
    }
}
