//! Reading a luxbake **output** back, for the report (`bake report LIT.gltf`).
//!
//! Input: the file's bytes and the [`Ctx`] (same parsing, validation, bounds-checked accessors and
//! folder-confined buffers as the importer). Output: a [`ReportInput`]:
//! - every node's name and parent; every material's name and the photometric reflectance the bake
//!   used (Y of `extras.luxbake.reflectance`, required of materials that baked primitives use);
//! - every primitive carrying `_ILLUMINANCE` (others, such as probe glyphs, are skipped) of the
//!   nodes of the scene, in node order: world positions (the node's composed transform applied
//!   to the stored `f32` positions), triangles wound counter-clockwise in world space,
//!   `_ILLUMINANCE`, `_ILLUMINANCE_DIRECT`, `_LUMINANCE`;
//! - the working plane: the children of the scene root node `probes` → child `working_plane`,
//!   each probe node carrying `extras.luxbake.faces["+y"]`, `facesDirect["+y"]` and
//!   `facesIndirect["+y"]` (lx); height and spacing from the scene's
//!   `extras.luxbake.settings.workingPlane`.
//!
//! A file with no `_ILLUMINANCE` anywhere is not a luxbake output: an error saying so.
//!
//! For `bake diff`, [`load_output`] also reads every probe node of the scene (a node whose
//! `extras.luxbake.faces` is an object): its position (`extras.luxbake.probe.position`, else the
//! node's world origin) and its six `faces` (lx, as stored).

use super::document::{self, Parsed};
use super::{accessor, buffers, mesh, nodes};
use crate::Result;
use crate::diff::{BakedOutput, ProbeNode};
use crate::import::context::Ctx;
use crate::probes::FACE_NAMES;
use crate::report::input::ReportInput;
use crate::report::input::{MaterialInfo, NodeInfo, PlaneInput, PlanePoint, Primitive};
use crate::scene::luma;
use ::gltf::mesh::{Mode, Semantic};
use glam::{DMat4, DVec3};
use serde_json::Value;

pub(crate) fn load(ctx: &mut Ctx, bytes: &[u8]) -> Result<ReportInput> {
    Ok(load_parts(ctx, bytes, false)?.report)
}

/// The report's input and every probe node (for `bake diff`).
pub(crate) fn load_output(ctx: &mut Ctx, bytes: &[u8]) -> Result<BakedOutput> {
    load_parts(ctx, bytes, true)
}

fn load_parts(ctx: &mut Ctx, bytes: &[u8], with_probes: bool) -> Result<BakedOutput> {
    let Parsed { doc, raw, bin } = document::parse(ctx, bytes)?;
    let buffers = buffers::load_buffers(ctx, &doc, bin.as_deref())?;
    let hierarchy = nodes::build(ctx, &doc, &raw)?;
    let mut parent = vec![None; hierarchy.nodes.len()];
    for (i, n) in hierarchy.nodes.iter().enumerate() {
        for &c in &n.children {
            parent[c] = Some(i);
        }
    }
    let node_infos = hierarchy
        .nodes
        .iter()
        .zip(&parent)
        .map(|(n, &parent)| NodeInfo {
            name: n.name.clone(),
            parent,
        })
        .collect();
    let reflectances: Vec<Option<f64>> = (0..doc.materials().len())
        .map(|i| reflectance(&raw["materials"][i]["extras"]["luxbake"]["reflectance"]))
        .collect();

    let probes = if with_probes {
        probe_nodes(ctx, &hierarchy.nodes, &hierarchy.reachable)?
    } else {
        Vec::new()
    };
    let mut order = hierarchy.reachable.clone();
    order.sort_unstable();
    let gltf_nodes: Vec<::gltf::Node> = doc.nodes().collect();
    let mut primitives = Vec::new();
    for i in order {
        let Some(mesh) = gltf_nodes[i].mesh() else {
            continue;
        };
        let world = hierarchy.nodes[i].world_from_local;
        for p in mesh.primitives() {
            let at = format!("/meshes/{}/primitives/{}", mesh.index(), p.index());
            if let Some(prim) = primitive(ctx, &buffers, &p, &at, i, world)? {
                if reflectances.get(prim.material).copied().flatten().is_none() {
                    return Err(ctx.err(
                        format!("/materials/{}", prim.material),
                        "the material has no extras.luxbake.reflectance (not written by luxbake?)",
                    ));
                }
                primitives.push(prim);
            }
        }
    }
    if primitives.is_empty() {
        return Err(ctx.err(
            "",
            "not a luxbake output: no primitive has an _ILLUMINANCE attribute (bake the scene \
             first: bake IN -o OUT)",
        ));
    }
    let materials = doc
        .materials()
        .zip(&reflectances)
        .map(|(m, r)| MaterialInfo {
            name: m.name().map(str::to_owned),
            reflectance: r.unwrap_or(0.0),
        })
        .collect();
    let points = working_plane(ctx, &hierarchy.nodes, &hierarchy.roots)?;
    let summary = hierarchy.extras.as_ref().map(|e| &e["luxbake"]);
    let report = ReportInput {
        nodes: node_infos,
        materials,
        primitives,
        working_plane: PlaneInput::new(summary, points),
    };
    Ok(BakedOutput { report, probes })
}

/// Every node of the scene whose `extras.luxbake.faces` is an object, in node order.
fn probe_nodes(
    ctx: &Ctx,
    nodes: &[crate::scene::Node],
    reachable: &[usize],
) -> Result<Vec<ProbeNode>> {
    let mut order = reachable.to_vec();
    order.sort_unstable();
    let mut probes = Vec::new();
    for i in order {
        let Some(luxbake) = nodes[i].extras.as_ref().map(|e| &e["luxbake"]) else {
            continue;
        };
        let Some(faces) = luxbake["faces"].as_object() else {
            continue;
        };
        let mut values = [0.0; 6];
        for (v, name) in values.iter_mut().zip(FACE_NAMES) {
            *v = faces.get(name).and_then(Value::as_f64).ok_or_else(|| {
                ctx.err(
                    format!("/nodes/{i}/extras/luxbake/faces"),
                    format!("a probe without its \"{name}\" value (lx)"),
                )
            })?;
        }
        let stored = luxbake["probe"]["position"].as_array().and_then(|a| {
            let c: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
            (a.len() == 3 && c.len() == 3).then(|| DVec3::new(c[0], c[1], c[2]))
        });
        let position =
            stored.unwrap_or_else(|| nodes[i].world_from_local.transform_point3(DVec3::ZERO));
        probes.push(ProbeNode {
            node: i,
            position,
            faces: values,
        });
    }
    Ok(probes)
}

/// Y of a reflectance written as `[r, g, b]` (or a single number).
fn reflectance(v: &Value) -> Option<f64> {
    if let Some(x) = v.as_f64() {
        return Some(x);
    }
    let a = v.as_array().filter(|a| a.len() == 3)?;
    let c: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
    (c.len() == 3).then(|| luma(DVec3::new(c[0], c[1], c[2])))
}

/// A baked primitive, or `None` when it has no `_ILLUMINANCE` or is not made of triangles.
fn primitive(
    ctx: &Ctx,
    buffers: &[Vec<u8>],
    p: &::gltf::Primitive,
    at: &str,
    node: usize,
    world: DMat4,
) -> Result<Option<Primitive>> {
    let extra = |name: &str| p.get(&Semantic::Extras(name.into()));
    let Some(illuminance) = extra("ILLUMINANCE") else {
        return Ok(None);
    };
    if !matches!(
        p.mode(),
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Ok(None);
    }
    let position = p
        .get(&Semantic::Positions)
        .ok_or_else(|| ctx.err(format!("{at}/attributes"), "primitive has no POSITION"))?;
    let count = position.count();
    let scalar = |a: Option<::gltf::Accessor>, name: &str| -> Result<Vec<f32>> {
        let at = format!("{at}/attributes/{name}");
        let a = a.ok_or_else(|| ctx.err(&at, "missing beside _ILLUMINANCE"))?;
        if a.count() != count {
            return Err(ctx.err(&at, format!("{} values for {count} vertices", a.count())));
        }
        let v = accessor::read(ctx, buffers, &a, 1, &at)?;
        Ok(v.into_iter().map(|x| x as f32).collect())
    };
    let illuminance = scalar(Some(illuminance), "_ILLUMINANCE")?;
    let illuminance_direct = scalar(extra("ILLUMINANCE_DIRECT"), "_ILLUMINANCE_DIRECT")?;
    let luminance = scalar(extra("LUMINANCE"), "_LUMINANCE")?;
    let raw = accessor::read(
        ctx,
        buffers,
        &position,
        3,
        &format!("{at}/attributes/POSITION"),
    )?;
    let positions: Vec<DVec3> = raw
        .chunks_exact(3)
        .map(|q| world.transform_point3(DVec3::new(q[0], q[1], q[2])))
        .collect();
    let indices: Vec<u32> = match p.indices() {
        Some(a) => {
            let at = format!("{at}/indices");
            let v = accessor::read_indices(ctx, buffers, &a, &at)?;
            if v.iter().any(|&i| i as usize >= count) {
                return Err(ctx.err(at, format!("an index is ≥ the {count} vertices")));
            }
            v
        }
        None => (0..count as u32).collect(),
    };
    let mut triangles = mesh::assemble(p.mode(), &indices);
    if world.determinant() < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let material = p
        .material()
        .index()
        .ok_or_else(|| ctx.err(at, "a baked primitive without a material"))?;
    Ok(Some(Primitive {
        node,
        material,
        positions,
        triangles,
        illuminance,
        illuminance_direct,
        luminance,
    }))
}

/// The `+y` faces of the probes under the root `probes` → `working_plane`.
fn working_plane(
    ctx: &Ctx,
    nodes: &[crate::scene::Node],
    roots: &[usize],
) -> Result<Vec<PlanePoint>> {
    let named = |list: &[usize], name: &str| {
        list.iter()
            .copied()
            .find(|&i| nodes[i].name.as_deref() == Some(name))
    };
    let Some(group) =
        named(roots, "probes").and_then(|p| named(&nodes[p].children, "working_plane"))
    else {
        return Ok(Vec::new());
    };
    let mut points = Vec::new();
    for &i in &nodes[group].children {
        let extras = nodes[i].extras.as_ref().map(|e| &e["luxbake"]);
        let face = |key: &str| {
            extras.and_then(|e| e[key]["+y"].as_f64()).ok_or_else(|| {
                ctx.err(
                    format!("/nodes/{i}/extras/luxbake/{key}"),
                    "a working-plane probe without its \"+y\" value (lx)",
                )
            })
        };
        points.push(PlanePoint::new(
            face("faces")?,
            face("facesDirect")?,
            face("facesIndirect")?,
        ));
    }
    Ok(points)
}
