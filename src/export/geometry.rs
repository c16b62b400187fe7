//! Baked world-space vertex data brought back into a node's local space, as `f32` arrays.
//!
//! Input: a [`BakedSurface`] (world space, counter-clockwise seen from the baked side) and the
//! node's `world_from_local`. Output: a [`LocalPrimitive`]. Invariants: positions are
//! `local_from_world · p`; normals are transformed by the inverse-transpose of `local_from_world`
//! (that is, `world_from_localᵀ`) and renormalised; when det(world_from_local) < 0 the winding is
//! reversed (viewers flip front faces under a mirroring transform, giving back the world winding);
//! every value written is finite and `color` lies in [0, 1]; inconsistent input is an error.

use crate::{Error, Result, result::BakedSurface};
use glam::{DMat3, DMat4, DVec2};

/// A node's frame: how to bring world-space data into its local space.
#[derive(Debug, Clone, Copy)]
pub struct LocalFrame {
    local_from_world: DMat4,
    normal_from_world: DMat3,
    /// det(world_from_local) < 0.
    pub mirrored: bool,
}

impl LocalFrame {
    /// `None` when `world_from_local` is singular or not finite.
    pub(crate) fn new(world_from_local: DMat4) -> Option<LocalFrame> {
        let det = world_from_local.determinant();
        if !det.is_finite() || det.abs() < 1e-300 {
            return None;
        }
        let local_from_world = world_from_local.inverse();
        local_from_world.is_finite().then(|| LocalFrame {
            local_from_world,
            normal_from_world: DMat3::from_mat4(world_from_local).transpose(),
            mirrored: det < 0.0,
        })
    }
}

/// One primitive's vertex data in the node's local space.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalPrimitive {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub uv0: Option<Vec<[f32; 2]>>,
    pub uv1: Option<Vec<[f32; 2]>>,
    /// Wound for the node's frame (reversed from world when the frame is mirrored).
    pub triangles: Vec<[u32; 3]>,
    pub color: Vec<[f32; 3]>,
    pub illuminance: Vec<f32>,
    pub illuminance_direct: Vec<f32>,
    pub luminance: Vec<f32>,
}

/// Convert `readback` into `frame`'s local space; `what` names it in errors.
pub(crate) fn to_local(
    baked: &BakedSurface,
    frame: &LocalFrame,
    what: &str,
) -> Result<LocalPrimitive> {
    let n = baked.positions.len();
    let bad = |m: String| Error::Bake(format!("{what}: {m}"));
    let check_len = |name: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(bad(format!("{name} has {len} entries for {n} positions")))
        }
    };
    check_len("normals", baked.normals.len())?;
    check_len("illuminance", baked.illuminance.len())?;
    check_len("direct illuminance", baked.illuminance_direct.len())?;
    check_len("luminance", baked.luminance.len())?;
    check_len("color", baked.color.len())?;
    for uv in [&baked.uv0, &baked.uv1].into_iter().flatten() {
        check_len("texture coordinates", uv.len())?;
    }
    if let Some(t) = baked.triangles.iter().flatten().find(|&&i| i as usize >= n) {
        return Err(bad(format!(
            "triangle index {t} out of range ({n} vertices)"
        )));
    }

    let positions = baked
        .positions
        .iter()
        .map(|&p| f32x3(frame.local_from_world.transform_point3(p).to_array()))
        .collect::<Vec<_>>();
    let normals = baked
        .normals
        .iter()
        .map(|&v| f32x3((frame.normal_from_world * v).normalize_or_zero().to_array()))
        .collect::<Vec<_>>();
    if positions
        .iter()
        .chain(&normals)
        .flatten()
        .any(|v| !v.is_finite())
    {
        return Err(bad(
            "positions or normals are not finite in local space".into()
        ));
    }
    if normals.contains(&[0.0; 3]) {
        return Err(bad("a normal has zero length".into()));
    }
    let finite = |name: &str, v: &[f32]| match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(bad(format!("{name} at vertex {i} is not finite"))),
        None => Ok(v.to_vec()),
    };
    let triangles = if frame.mirrored {
        baked.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
    } else {
        baked.triangles.clone()
    };
    Ok(LocalPrimitive {
        positions,
        normals,
        uv0: baked.uv0.as_deref().map(uvs),
        uv1: baked.uv1.as_deref().map(uvs),
        triangles,
        color: baked.color.iter().map(|c| c.map(unit)).collect(),
        illuminance: finite("illuminance", &baked.illuminance)?,
        illuminance_direct: finite("direct illuminance", &baked.illuminance_direct)?,
        luminance: finite("luminance", &baked.luminance)?,
    })
}

fn f32x3(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

fn uvs(v: &[DVec2]) -> Vec<[f32; 2]> {
    v.iter().map(|uv| [uv.x as f32, uv.y as f32]).collect()
}

/// A colour component forced into [0, 1] (NaN becomes 0); `COLOR_0` must never leave it.
fn unit(x: f32) -> f32 {
    debug_assert!(
        (0.0..=1.0).contains(&x),
        "colour component {x} outside [0, 1]"
    );
    if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::result::Side;
    use glam::{DQuat, DVec3};

    fn quad(world_from_local: DMat4) -> BakedSurface {
        let local = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
        BakedSurface {
            surface: 0,
            side: Side::Front,
            positions: local
                .iter()
                .map(|&p| world_from_local.transform_point3(DVec3::from(p)))
                .collect(),
            normals: vec![world_from_local.transform_vector3(DVec3::Z).normalize(); 3],
            uv0: None,
            uv1: None,
            triangles: vec![[0, 1, 2]],
            illuminance: vec![1.0; 3],
            illuminance_direct: vec![0.5; 3],
            luminance: vec![0.5; 3],
            color: vec![[0.2, 0.4, 0.6]; 3],
            lightmap: None,
            covered_from: None,
        }
    }

    #[test]
    fn round_trips_and_flips_under_mirror() {
        let m = DMat4::from_scale_rotation_translation(
            DVec3::new(-2.0, 1.0, 0.5),
            DQuat::from_rotation_y(0.7),
            DVec3::new(1.0, 2.0, 3.0),
        );
        let frame = LocalFrame::new(m).unwrap();
        assert!(frame.mirrored);
        let prim = to_local(&quad(m), &frame, "t").unwrap();
        assert_eq!(prim.triangles, vec![[0, 2, 1]]);
        for (p, want) in prim
            .positions
            .iter()
            .zip([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
        {
            for i in 0..3 {
                assert!((p[i] - want[i]).abs() < 1e-6, "{p:?}");
            }
        }
        assert!(
            (prim.normals[0][2] - 1.0).abs() < 1e-6,
            "{:?}",
            prim.normals[0]
        );
    }

    #[test]
    fn singular_frame_and_bad_lengths_are_rejected() {
        assert!(LocalFrame::new(DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0))).is_none());
        let mut q = quad(DMat4::IDENTITY);
        q.luminance.pop();
        let frame = LocalFrame::new(DMat4::IDENTITY).unwrap();
        assert!(to_local(&q, &frame, "t").is_err());
    }
}
