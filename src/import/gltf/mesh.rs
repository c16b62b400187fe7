//! glTF mesh primitives → world-space [`Surface`]s, one per (node instance, primitive).
//!
//! Inputs: a node's mesh, the node's `world_from_local`, the loaded buffers. Output: the surfaces
//! (triangles only; POINTS and LINES primitives are skipped with a warning).
//! Invariants and choices: TRIANGLES, TRIANGLE_STRIP (every second triangle's winding reversed as
//! the spec says) and TRIANGLE_FAN, indexed or not. Positions go to world space; normals by the
//! inverse transpose, renormalised; missing normals become flat face normals. Under a negative
//! determinant each triangle's winding is reversed so fronts stay counter-clockwise in world
//! space. Non-finite positions and out-of-range indices are errors naming the attribute pointer
//! (`/meshes/M/primitives/P/attributes/POSITION`) and `/accessors/N`. TEXCOORD_0/1 are read;
//! other attributes and morph targets are ignored with one warning per kind.

use super::accessor;
use crate::Result;
use crate::import::context::Ctx;
use crate::import::geometry::{Origin, RawMesh, into_surface};
use crate::scene::Surface;
use ::gltf::mesh::{Mode, Semantic};
use glam::{DMat3, DMat4, DVec2, DVec3};

/// Where a node's surfaces go and which material primitives without one use.
pub(super) struct Placement {
    pub node: usize,
    pub world_from_local: DMat4,
    pub default_material: usize,
}

/// Surfaces of every triangle primitive of `mesh`, placed by `placement`.
pub(super) fn surfaces(
    ctx: &mut Ctx,
    buffers: &[Vec<u8>],
    mesh: &::gltf::Mesh,
    placement: &Placement,
) -> Result<Vec<Surface>> {
    let mut out = Vec::new();
    for primitive in mesh.primitives() {
        let at = format!("/meshes/{}/primitives/{}", mesh.index(), primitive.index());
        if !matches!(
            primitive.mode(),
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            ctx.warn_once(
                &format!("mode {:?}", primitive.mode()),
                format!(
                    "{at}: {:?} primitives are skipped (only triangles are baked); later ones \
                     are skipped silently",
                    primitive.mode()
                ),
            );
            continue;
        }
        out.push(surface(ctx, buffers, &primitive, &at, placement)?);
    }
    Ok(out)
}

fn surface(
    ctx: &mut Ctx,
    buffers: &[Vec<u8>],
    primitive: &::gltf::Primitive,
    at: &str,
    placement: &Placement,
) -> Result<Surface> {
    warn_ignored(ctx, primitive, at);
    let attr = |name: &str| format!("{at}/attributes/{name}");
    let position_accessor = primitive
        .get(&Semantic::Positions)
        .ok_or_else(|| ctx.err(format!("{at}/attributes"), "primitive has no POSITION"))?;
    let pos_at = attr("POSITION");
    let raw_positions = accessor::read(ctx, buffers, &position_accessor, 3, &pos_at)?;
    let count = position_accessor.count();
    if let Some(bad) = raw_positions.iter().position(|v| !v.is_finite()) {
        return Err(ctx.err(
            pos_at,
            format!(
                "accessor /accessors/{} holds a non-finite position ({}) at vertex {}",
                position_accessor.index(),
                raw_positions[bad],
                bad / 3
            ),
        ));
    }
    let world = placement.world_from_local;
    let positions: Vec<DVec3> = raw_positions
        .chunks_exact(3)
        .map(|p| world.transform_point3(DVec3::new(p[0], p[1], p[2])))
        .collect();

    // Under a singular transform normals cannot be mapped: flat face normals replace them.
    let normals = match (primitive.get(&Semantic::Normals), normal_matrix(world)) {
        (Some(a), Some(m)) => {
            let values = read_per_vertex(ctx, buffers, &a, 3, &attr("NORMAL"), count)?;
            Some(
                values
                    .chunks_exact(3)
                    .map(|n| m * DVec3::new(n[0], n[1], n[2]))
                    .collect(),
            )
        }
        _ => None,
    };
    let mut uvs = [None, None];
    for (set, uv) in uvs.iter_mut().enumerate() {
        if let Some(a) = primitive.get(&Semantic::TexCoords(set as u32)) {
            let name = format!("TEXCOORD_{set}");
            let values = read_per_vertex(ctx, buffers, &a, 2, &attr(&name), count)?;
            *uv = Some(
                values
                    .chunks_exact(2)
                    .map(|t| DVec2::new(t[0], t[1]))
                    .collect(),
            );
        }
    }
    let [uv0, uv1] = uvs;

    let indices: Vec<u32> = match primitive.indices() {
        Some(a) => {
            let indices_at = format!("{at}/indices");
            let indices = accessor::read_indices(ctx, buffers, &a, &indices_at)?;
            if let Some(&bad) = indices.iter().find(|&&i| i as usize >= count) {
                return Err(ctx.err(
                    indices_at,
                    format!(
                        "accessor /accessors/{} holds index {bad} but there are only {count} \
                         vertices",
                        a.index()
                    ),
                ));
            }
            indices
        }
        None => (0..count as u32).collect(),
    };
    if primitive.mode() == Mode::Triangles && !indices.len().is_multiple_of(3) {
        let (where_, what) = match primitive.indices() {
            Some(a) => (
                format!("{at}/indices"),
                format!("accessor /accessors/{}", a.index()),
            ),
            None => (pos_at.clone(), "POSITION (not indexed)".to_owned()),
        };
        return Err(ctx.err(
            where_,
            format!(
                "{what} has {} elements, not a multiple of 3 as TRIANGLES needs",
                indices.len()
            ),
        ));
    }
    let mut triangles = assemble(primitive.mode(), &indices);
    if world.determinant() < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let mesh = RawMesh {
        positions,
        normals,
        uv0,
        uv1,
        triangles,
    };
    Ok(into_surface(
        mesh,
        Origin {
            node: placement.node,
            primitive: primitive.index(),
            source_path: at.to_owned(),
            material: primitive
                .material()
                .index()
                .unwrap_or(placement.default_material),
        },
    ))
}

/// Read an attribute that must have one element per vertex.
fn read_per_vertex(
    ctx: &Ctx,
    buffers: &[Vec<u8>],
    a: &::gltf::Accessor,
    dims: usize,
    at: &str,
    count: usize,
) -> Result<Vec<f64>> {
    if a.count() != count {
        return Err(ctx.err(
            at,
            format!(
                "accessor /accessors/{} has {} elements but POSITION has {count}",
                a.index(),
                a.count()
            ),
        ));
    }
    accessor::read(ctx, buffers, a, dims, at)
}

/// Inverse transpose of the linear part, or `None` for a singular transform.
fn normal_matrix(world: DMat4) -> Option<DMat3> {
    let linear = DMat3::from_mat4(world);
    let det = linear.determinant();
    (det.is_finite() && det.abs() > 1e-300).then(|| linear.inverse().transpose())
}

/// Triangles of a primitive from its vertex sequence.
pub(super) fn assemble(mode: Mode, v: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [v[i], v[i + 1], v[i + 2]]
                } else {
                    [v[i], v[i + 2], v[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..v.len().saturating_sub(1))
            .map(|i| [v[i], v[i + 1], v[0]])
            .collect(),
        _ => v.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}

/// One warning per kind of attribute (and for morph targets) that the bake does not use.
fn warn_ignored(ctx: &mut Ctx, primitive: &::gltf::Primitive, at: &str) {
    for (semantic, _) in primitive.attributes() {
        let kind = match semantic {
            Semantic::Positions | Semantic::Normals => continue,
            Semantic::TexCoords(0 | 1) => continue,
            Semantic::TexCoords(_) => "TEXCOORD_n (n ≥ 2)".to_owned(),
            Semantic::Tangents => "TANGENT".to_owned(),
            Semantic::Colors(_) => "COLOR_n".to_owned(),
            Semantic::Joints(_) => "JOINTS_n".to_owned(),
            Semantic::Weights(_) => "WEIGHTS_n".to_owned(),
            Semantic::Extras(name) => name,
        };
        ctx.warn_once(
            &format!("attribute {kind}"),
            format!("{at}: {kind} attributes are ignored by the bake (first seen here)"),
        );
    }
    if primitive.morph_targets().next().is_some() {
        ctx.warn_once(
            "morph targets",
            format!(
                "{at}: morph targets are ignored; the base geometry is baked (first seen here)"
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans() {
        let v = [0, 1, 2, 3, 4];
        assert_eq!(
            assemble(Mode::TriangleStrip, &v),
            vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]
        );
        assert_eq!(
            assemble(Mode::TriangleFan, &v),
            vec![[1, 2, 0], [2, 3, 0], [3, 4, 0]]
        );
        assert_eq!(assemble(Mode::Triangles, &v), vec![[0, 1, 2]]);
        assert!(assemble(Mode::TriangleStrip, &v[..2]).is_empty());
    }
}
