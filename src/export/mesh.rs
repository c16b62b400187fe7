//! The output's meshes: one new mesh per node that has surfaces (lighting differs per instance,
//! so meshes are never shared), with the baked attributes.
//!
//! Input: the [`Scene`] (nodes, surfaces), the [`BakeResult`] and the [`Binary`] being filled.
//! Output: [`Meshes`]: the `meshes` JSON array, each node's mesh index, and which materials were
//! baked with a back side. Invariants: a node's primitives follow its `surfaces` order, each
//! surface giving its `Side::Front` primitive and then, if baked, its `Side::Back` one; every
//! surface of a node must have a front result (else [`Error::Bake`]); baked sides without
//! triangles are left out, and a node left with no primitive gets no mesh. Attributes: POSITION
//! (with min/max), NORMAL, TEXCOORD_0/1 when present, COLOR_0 (float VEC3), `_ILLUMINANCE` (lx),
//! `_ILLUMINANCE_DIRECT` (lx) and `_LUMINANCE` (cd/m²), float SCALAR; indices u16 or u32; mode
//! TRIANGLES. An unbaked scene ([`super::write_scene`]) gets POSITION, NORMAL and TEXCOORD_n only.
//! A lightmapped surface (`lightmap: Some(k)`) is written with its material's variant for atlas
//! k ([`Variants`]), its layout `uv1` as TEXCOORD_1 (and as TEXCOORD_0 too when it has no other
//! UVs: sets must start at 0) and no COLOR_0 (a viewer would multiply the lightmap by it).
//! A baked primitive with a covered part (`BakedSurface::covered_from`) gets
//! `extras: {"luxbake": {"coveredFrom": N}}`: its triangles N… (in index order) are covered,
//! without light, and readers leave them out of figures.

use super::buffer::Binary;
use super::geometry::{LocalFrame, LocalPrimitive, to_local};
use super::lightmap_material::Variants;
use crate::{
    Error, Result,
    result::{BakeResult, BakedSurface, Side},
    scene::Scene,
};
use serde_json::{Map, Value, json};

const TRIANGLES: u32 = 4;

/// The meshes written for the scene's nodes.
#[derive(Debug, Default)]
pub struct Meshes {
    pub json: Vec<Value>,
    /// `node_mesh[node]`: the mesh index of each node, if it has one.
    pub node_mesh: Vec<Option<usize>>,
    /// `back_baked[material]`: some surface with this material was baked with a back side.
    pub back_baked: Vec<bool>,
}

/// Front and back results of each scene surface.
fn index_results(scene: &Scene, result: &BakeResult) -> Result<Vec<[Option<usize>; 2]>> {
    let mut sides = vec![[None, None]; scene.surfaces.len()];
    for (i, b) in result.surfaces.iter().enumerate() {
        let slot = sides.get_mut(b.surface).ok_or_else(|| {
            Error::Bake(format!(
                "baked surface {i} names missing surface {}",
                b.surface
            ))
        })?;
        let side = match b.side {
            Side::Front => 0,
            Side::Back => 1,
        };
        if slot[side].replace(i).is_some() {
            return Err(Error::Bake(format!(
                "surface {} was baked twice on the {:?} side",
                b.surface, b.side
            )));
        }
    }
    Ok(sides)
}

/// Build every node's mesh, writing the vertex data into `binary`; without `with_values`, only
/// the geometry (no COLOR_0, `_ILLUMINANCE`, `_ILLUMINANCE_DIRECT` or `_LUMINANCE`).
pub(crate) fn build(
    scene: &Scene,
    result: &BakeResult,
    binary: &mut Binary,
    with_values: bool,
    variants: &Variants,
) -> Result<Meshes> {
    let sides = index_results(scene, result)?;
    let mut meshes = Meshes {
        json: Vec::new(),
        node_mesh: vec![None; scene.nodes.len()],
        back_baked: vec![false; scene.materials.len()],
    };
    for (n, node) in scene.nodes.iter().enumerate() {
        if node.surfaces.is_empty() {
            continue;
        }
        let frame = LocalFrame::new(node.world_from_local).ok_or_else(|| {
            Error::Bake(format!(
                "{}: the node's transform is singular; its baked mesh cannot be expressed in its \
                 local space",
                node.source_path
            ))
        })?;
        let mut primitives = Vec::new();
        for &s in &node.surfaces {
            let surface = &scene.surfaces[s];
            let [front, back] = sides[s];
            let front = front.ok_or_else(|| {
                Error::Bake(format!(
                    "{}: no baked result for its front side",
                    surface.source_path
                ))
            })?;
            if back.is_some() {
                meshes.back_baked[surface.material] = true;
            }
            for b in [Some(front), back].into_iter().flatten() {
                let baked: &BakedSurface = &result.surfaces[b];
                if baked.triangles.is_empty() {
                    continue;
                }
                let what = format!("{} ({:?} side)", surface.source_path, baked.side);
                let local = to_local(baked, &frame, &what)?;
                let lightmapped = match baked.lightmap.filter(|_| with_values) {
                    None => None,
                    Some(k) => {
                        if local.uv1.is_none() {
                            return Err(Error::Bake(format!(
                                "{what}: laid out in lightmap {k} without TEXCOORD_1"
                            )));
                        }
                        let variant = variants.get(surface.material, k).ok_or_else(|| {
                            Error::Bake(format!("{what}: no material for lightmap {k}"))
                        })?;
                        Some(variant)
                    }
                };
                let material = lightmapped.unwrap_or(surface.material);
                let lightmapped = lightmapped.is_some();
                let covered_from = baked
                    .covered_from
                    .filter(|&k| with_values && (k as usize) < baked.triangles.len());
                primitives.push(primitive(
                    &local,
                    material,
                    binary,
                    with_values,
                    lightmapped,
                    covered_from,
                ));
            }
        }
        if primitives.is_empty() {
            continue;
        }
        let mut mesh = Map::new();
        if let Some(name) = &node.mesh_name {
            mesh.insert("name".into(), json!(name));
        }
        mesh.insert("primitives".into(), Value::Array(primitives));
        meshes.node_mesh[n] = Some(meshes.json.len());
        meshes.json.push(Value::Object(mesh));
    }
    Ok(meshes)
}

/// One primitive, with the baked values if `values`; a `lightmapped` one without COLOR_0; with
/// a covered part from triangle `covered_from` on, `extras.luxbake.coveredFrom`.
fn primitive(
    p: &LocalPrimitive,
    material: usize,
    binary: &mut Binary,
    values: bool,
    lightmapped: bool,
    covered_from: Option<u32>,
) -> Value {
    let mut attributes = Map::new();
    attributes.insert("POSITION".into(), json!(binary.vec3(&p.positions, true)));
    attributes.insert("NORMAL".into(), json!(binary.vec3(&p.normals, false)));
    let uv0 = p.uv0.as_ref().map(|uv| binary.vec2(uv));
    let uv1 = p.uv1.as_ref().map(|uv| binary.vec2(uv));
    if let Some(uv) = uv0.or(uv1.filter(|_| lightmapped)) {
        attributes.insert("TEXCOORD_0".into(), json!(uv));
    }
    if let Some(uv) = uv1 {
        attributes.insert("TEXCOORD_1".into(), json!(uv));
    }
    if values {
        if !lightmapped {
            attributes.insert("COLOR_0".into(), json!(binary.vec3(&p.color, false)));
        }
        attributes.insert("_ILLUMINANCE".into(), json!(binary.scalar(&p.illuminance)));
        attributes.insert(
            "_ILLUMINANCE_DIRECT".into(),
            json!(binary.scalar(&p.illuminance_direct)),
        );
        attributes.insert("_LUMINANCE".into(), json!(binary.scalar(&p.luminance)));
    }
    let indices = binary.indices(&p.triangles, p.positions.len());
    let mut out = json!({
        "attributes": attributes,
        "indices": indices,
        "material": material,
        "mode": TRIANGLES,
    });
    if let Some(k) = covered_from {
        out["extras"] = json!({"luxbake": {"coveredFrom": k}});
    }
    out
}
