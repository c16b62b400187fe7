//! The luminaires' luminous openings as meshes a viewer draws: a photometric luminaire lights
//! the room, but its fitting has no emitting surface, so without these a viewer shows the
//! brightest things in the room as dull boxes.
//!
//! Input: the [`Scene`] and the display exposure k. Output: one [`OpeningMesh`] per luminaire
//! whose opening has area ([`crate::direct::opening`]), in luminaire order.
//! Rules: a flat opening is its rectangle (or a 32-sided ellipse) in the photometric XY plane,
//! drawn twice, once facing photometric −Z and once +Z; a box its six faces, a cylinder its two
//! caps and 32 side quads, each facing outward. Each face shows the opening's luminance along
//! its outward normal (the rule of `direct::opening`, constant over the face), as
//! COLOR_0 = shoulder(k·π·L) over a white base — what a surface of reflectance 1 under that
//! illuminance would show. Faces that show nothing (no light that way) are left out. The faces
//! lie on the opening itself; a fitting's own diffuser modelled 1 mm behind it stays hidden.

use super::display;
use crate::direct::bounds::ProfileBounds;
use crate::direct::opening::{self, Opening};
use crate::result::OpeningMesh;
use crate::scene::{Scene, luma};
use glam::{DVec2, DVec3};

/// Sides of a round opening's outline.
const SEGMENTS: usize = 32;

/// The openings' meshes at exposure `k` (COLOR_0 = shoulder(k·E)).
pub(crate) fn meshes(scene: &Scene, k: f64) -> Vec<OpeningMesh> {
    if scene.luminaires.is_empty() {
        return Vec::new();
    }
    let bounds = ProfileBounds::new(scene);
    opening::all(scene, &bounds)
        .iter()
        .filter_map(|o| mesh(o, k))
        .collect()
}

/// One opening's faces, or `None` when no face shows light.
fn mesh(o: &Opening, k: f64) -> Option<OpeningMesh> {
    let to_world = |p: DVec3| o.source.position + o.source.world_from_photometric * p;
    let mut out = OpeningMesh {
        luminaire: o.luminaire,
        positions: Vec::new(),
        normals: Vec::new(),
        luminance: Vec::new(),
        color: Vec::new(),
    };
    for face in faces(o) {
        let normal = (o.source.world_from_photometric * face.normal).normalize();
        // Seen from outside: the eye looks along −normal.
        let l = o.luminance(-normal);
        if luma(l).is_nan() || luma(l) <= 0.0 {
            continue;
        }
        let color = display::luminance_color(l, k);
        for t in face.triangles {
            for p in t {
                out.positions.push(to_world(p));
                out.normals.push(normal);
                out.luminance.push(luma(l) as f32);
                out.color.push(color);
            }
        }
    }
    (!out.positions.is_empty()).then_some(out)
}

/// A planar face in the photometric frame: outward normal and triangles wound counter-clockwise
/// seen from outside.
struct Face {
    normal: DVec3,
    triangles: Vec<[DVec3; 3]>,
}

/// The faces of `o` (see the module's rules).
fn faces(o: &Opening) -> Vec<Face> {
    let h = o.half;
    let outline: Vec<DVec2> = match o.round {
        true => (0..SEGMENTS)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / SEGMENTS as f64;
                DVec2::new(h.x * a.cos(), h.y * a.sin())
            })
            .collect(),
        false => vec![
            DVec2::new(-h.x, -h.y),
            DVec2::new(h.x, -h.y),
            DVec2::new(h.x, h.y),
            DVec2::new(-h.x, h.y),
        ],
    };
    // The outline runs counter-clockwise seen from +Z.
    let cap = |z: f64, up: bool| {
        let at = |q: DVec2| DVec3::new(q.x, q.y, z);
        let triangles = (1..outline.len() - 1)
            .map(|i| {
                let (a, b, c) = (at(outline[0]), at(outline[i]), at(outline[i + 1]));
                if up { [a, b, c] } else { [a, c, b] }
            })
            .collect();
        Face {
            normal: if up { DVec3::Z } else { DVec3::NEG_Z },
            triangles,
        }
    };
    let mut faces = vec![cap(-h.z, false), cap(h.z, true)];
    if h.z > 0.0 {
        for i in 0..outline.len() {
            let (a, b) = (outline[i], outline[(i + 1) % outline.len()]);
            let edge = b - a;
            let normal = DVec3::new(edge.y, -edge.x, 0.0).normalize();
            let [p, q, r, s] = [
                DVec3::new(a.x, a.y, -h.z),
                DVec3::new(b.x, b.y, -h.z),
                DVec3::new(b.x, b.y, h.z),
                DVec3::new(a.x, a.y, h.z),
            ];
            faces.push(Face {
                normal,
                triangles: vec![[p, q, r], [p, r, s]],
            });
        }
    }
    faces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photometry::{Opening as Dimensions, OpeningShape};

    /// One linear fitting 2.8 m up, nadir down (−Y), C0 along +Z, with the given opening.
    fn opening(length: f64, width: f64, height: f64, shape: OpeningShape) -> Scene {
        let mut b = crate::fixtures::SceneBuilder::new();
        let opening = Dimensions {
            length,
            width,
            height,
            shape,
        };
        b.luminaire(
            "fitting",
            crate::fixtures::openplan::LINEAR_IES,
            crate::photometry::Format::Ies,
            DVec3::new(0.0, 2.8, 0.0),
            DVec3::NEG_Y,
            DVec3::Z,
            1.0,
            Some(opening),
        );
        b.build()
    }

    /// Every face's triangles are wound to face its normal, and a face shows I(n)/A⊥(n).
    #[test]
    fn faces_are_wound_outward_and_show_intensity_over_projected_area() {
        for (height, shape) in [
            (0.0, OpeningShape::Rectangular),
            (0.1, OpeningShape::Rectangular),
            (0.0, OpeningShape::Round),
            (0.1, OpeningShape::Round),
        ] {
            let scene = opening(0.6, 0.3, height, shape);
            let bounds = ProfileBounds::new(&scene);
            let all = opening::all(&scene, &bounds);
            let m = mesh(&all[0], 1.0).expect("the opening shows light");
            assert_eq!(m.positions.len() % 3, 0);
            for t in 0..m.positions.len() / 3 {
                let [a, b, c] = [0, 1, 2].map(|i| m.positions[3 * t + i]);
                let n = (b - a).cross(c - a);
                assert!(n.length() > 0.0 && n.normalize().dot(m.normals[3 * t]) > 0.999);
                let l = all[0].luminance(-m.normals[3 * t]);
                assert!((m.luminance[3 * t] as f64 - luma(l)).abs() <= 1e-4 * luma(l));
            }
            // Seen from straight below the photometric frame, L = I(nadir) / A.
            let down = all[0].source.world_from_photometric * DVec3::NEG_Z;
            let area = match shape {
                OpeningShape::Round => std::f64::consts::PI * 0.3 * 0.15,
                _ => 0.6 * 0.3,
            };
            let expected = all[0].source.intensity(down) / area;
            let shown = luma(all[0].luminance(-down)) / luma(all[0].source.color);
            assert!(
                (shown - expected).abs() <= 1e-9 * expected,
                "{shown} {expected}"
            );
        }
    }
}
