//! Turning world-space vertex data into a [`Surface`] that meets the scene model's invariants.
//!
//! Input: a [`RawMesh`] — world-space positions, optional world-space (not yet unit) normals,
//! optional texture coordinates, and triangles already wound counter-clockwise from the front.
//! Output: a [`Surface`] whose normals are finite and unit length, one per position.
//! Invariants and choices: without normals, every triangle gets its own three vertices with the
//! triangle's (flat) normal, as the glTF spec prescribes; a degenerate (zero-area) triangle is kept
//! and its normal falls back to +Y. A given normal that is zero or not finite is replaced by the
//! normal of a non-degenerate triangle using that vertex, else +Y.

use crate::scene::Surface;
use glam::{DVec2, DVec3};

/// Vertex data before normals are settled.
pub(crate) struct RawMesh {
    pub positions: Vec<DVec3>,
    pub normals: Option<Vec<DVec3>>,
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
}

/// Where a surface comes from (copied into the [`Surface`]).
pub(crate) struct Origin {
    pub node: usize,
    pub primitive: usize,
    pub source_path: String,
    pub material: usize,
}

/// Unit normal of triangle `t` (counter-clockwise front), `None` if it has no area.
pub(crate) fn face_normal(positions: &[DVec3], t: [u32; 3]) -> Option<DVec3> {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    let n = (b - a).cross(c - a);
    let len = n.length();
    (len.is_finite() && len > 0.0).then(|| n / len)
}

/// Settle the normals of `mesh` and make it a [`Surface`].
pub(crate) fn into_surface(mesh: RawMesh, origin: Origin) -> Surface {
    let RawMesh {
        positions,
        normals,
        uv0,
        uv1,
        triangles,
    } = mesh;
    let (positions, normals, uv0, uv1, triangles) = match normals {
        Some(normals) => {
            let normals = repair_normals(&positions, normals, &triangles);
            (positions, normals, uv0, uv1, triangles)
        }
        None => flat_shade(&positions, uv0.as_deref(), uv1.as_deref(), &triangles),
    };
    Surface {
        node: origin.node,
        primitive: origin.primitive,
        source_path: origin.source_path,
        material: origin.material,
        positions,
        normals,
        uv0,
        uv1,
        triangles,
    }
}

type Flat = (
    Vec<DVec3>,
    Vec<DVec3>,
    Option<Vec<DVec2>>,
    Option<Vec<DVec2>>,
    Vec<[u32; 3]>,
);

/// Give every triangle its own vertices carrying its face normal.
fn flat_shade(
    positions: &[DVec3],
    uv0: Option<&[DVec2]>,
    uv1: Option<&[DVec2]>,
    triangles: &[[u32; 3]],
) -> Flat {
    let n = triangles.len() * 3;
    let mut out_p = Vec::with_capacity(n);
    let mut out_n = Vec::with_capacity(n);
    let mut out_uv0 = uv0.map(|_| Vec::with_capacity(n));
    let mut out_uv1 = uv1.map(|_| Vec::with_capacity(n));
    let mut out_t = Vec::with_capacity(triangles.len());
    for &t in triangles {
        let normal = face_normal(positions, t).unwrap_or(DVec3::Y);
        let base = out_p.len() as u32;
        for i in t {
            out_p.push(positions[i as usize]);
            out_n.push(normal);
            if let (Some(out), Some(src)) = (out_uv0.as_mut(), uv0) {
                out.push(src[i as usize]);
            }
            if let (Some(out), Some(src)) = (out_uv1.as_mut(), uv1) {
                out.push(src[i as usize]);
            }
        }
        out_t.push([base, base + 1, base + 2]);
    }
    (out_p, out_n, out_uv0, out_uv1, out_t)
}

/// Normalise given normals, replacing unusable ones.
fn repair_normals(
    positions: &[DVec3],
    mut normals: Vec<DVec3>,
    triangles: &[[u32; 3]],
) -> Vec<DVec3> {
    let mut bad = vec![false; normals.len()];
    let mut any_bad = false;
    for (n, b) in normals.iter_mut().zip(&mut bad) {
        let len = n.length();
        if len.is_finite() && len > 1e-30 {
            *n /= len;
        } else {
            *b = true;
            any_bad = true;
        }
    }
    if any_bad {
        for &t in triangles {
            if !t.iter().any(|&i| bad[i as usize]) {
                continue;
            }
            if let Some(face) = face_normal(positions, t) {
                for i in t {
                    if bad[i as usize] {
                        normals[i as usize] = face;
                        bad[i as usize] = false;
                    }
                }
            }
        }
        for (n, b) in normals.iter_mut().zip(&bad) {
            if *b {
                *n = DVec3::Y;
            }
        }
    }
    normals
}

#[cfg(test)]
mod tests {
    use super::*;

    fn origin() -> Origin {
        Origin {
            node: 0,
            primitive: 0,
            source_path: String::new(),
            material: 0,
        }
    }

    #[test]
    fn flat_normals_unweld_and_survive_degenerates() {
        let mesh = RawMesh {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X * 2.0],
            normals: None,
            uv0: Some(vec![DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE]),
            uv1: None,
            triangles: vec![[0, 1, 2], [0, 1, 3]],
        };
        let s = into_surface(mesh, origin());
        assert_eq!(s.positions.len(), 6);
        assert_eq!(s.normals[0], DVec3::Z);
        assert_eq!(s.normals[3], DVec3::Y);
        assert_eq!(s.uv0.unwrap()[5], DVec2::ONE);
        assert_eq!(s.triangles, vec![[0, 1, 2], [3, 4, 5]]);
    }

    #[test]
    fn bad_normals_are_replaced() {
        let mesh = RawMesh {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            normals: Some(vec![
                DVec3::Z * 3.0,
                DVec3::ZERO,
                DVec3::splat(f64::NAN),
                DVec3::ZERO,
            ]),
            uv0: None,
            uv1: None,
            triangles: vec![[0, 1, 2]],
        };
        let s = into_surface(mesh, origin());
        assert_eq!(s.normals, vec![DVec3::Z, DVec3::Z, DVec3::Z, DVec3::Y]);
    }
}
