//! Reading a luxbake output back (`bake report`, `bake diff`), from a file or from the bytes the
//! exporter is about to write.
//!
//! Input: a [`GltfFile`] (the importer's parsing, validation, bounds-checked accessors and
//! folder-confined buffers). Output: a [`BakedOutput`]:
//! - every node's name and parent; every material's name and the photometric reflectance the bake
//!   used (Y of `extras.luxbake.reflectance`, required of materials that baked primitives use);
//! - every primitive carrying `_ILLUMINANCE` (others, such as probe glyphs, are skipped) of the
//!   nodes of the scene, in node order: world positions (the node's composed transform applied
//!   to the stored `f32` positions), triangles wound counter-clockwise in world space,
//!   `_ILLUMINANCE`, `_ILLUMINANCE_DIRECT`, `_LUMINANCE`, and where its covered part starts
//!   (`extras.luxbake.coveredFrom`, absent in older outputs: nothing covered);
//! - the primitives of nodes drawn for viewers only (`extras.luxbake.displayOnly`: luminous
//!   openings) with COLOR_0, as [`Shown`]: world positions, triangles, COLOR_0, base colour;
//! - every node's `extras.power_W` and `LUXBAKE_luminaire.maintenanceFactor` (luminaires);
//! - every probe node of the scene (a node whose `extras.luxbake.faces` is an object): its
//!   position (`extras.luxbake.probe.position`, else the node's world origin) and its six
//!   `faces` (lx, as stored);
//! - the working plane: the children of the scene root node `probes` → child `working_plane`,
//!   each probe node carrying `extras.luxbake.faces["+y"]`, `facesDirect["+y"]` and
//!   `facesIndirect["+y"]` (lx), and its position (as a probe node's);
//! - the run summary as stored (read typed by whoever needs it: `BakedOutput::run_summary`);
//! - the lightmap atlases its materials name ([`super::lightmaps`]) and, per primitive whose
//!   material names one, its layout (`TEXCOORD_<texCoord>`) and the texels it stands on
//!   ([`super::texels`]); a lightmapped variant's `extras.luxbake.variantOf`;
//! - each material's display factors ([`Look`]) and each baked primitive's `COLOR_0`; the
//!   scene's camera nodes ([`super::cameras`]).
//!
//! A file with no `_ILLUMINANCE` anywhere is not a luxbake output: an error saying so.

use super::lightmaps::{self, Layouts};
use super::model::{
    BakedOutput, LightmapUse, Look, MaterialInfo, NodeInfo, PlaneInput, PlanePoint, Primitive,
    ProbeNode, Shown, parents,
};
use super::texels::{Scratch, rasterise};
use crate::export::{ExportOptions, Prepared};
use crate::import::{GltfFile, GltfPrimitive};
use crate::probes::FACE_NAMES;
use crate::result::{BakeResult, Lightmaps};
use crate::scene::{Node, Scene, luma};
use crate::{Error, Result};
use glam::{DMat4, DVec2, DVec3};
use serde_json::Value;
use std::path::Path;

/// Read the luxbake output at `path` (`.gltf` or `.glb`).
pub fn read(path: &Path) -> Result<BakedOutput> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("gltf" | "glb")) {
        return Err(Error::input(
            path,
            "",
            "not a luxbake output: bake writes .gltf or .glb files",
        ));
    }
    from_file(&mut GltfFile::open(path)?, None)
}

/// Read an output held in memory as GLB bytes, named `name` in messages (one with lightmaps
/// cannot be read so: its EXR files are not in memory; see [`from_prepared`]).
pub fn from_glb(name: &Path, bytes: &[u8]) -> Result<BakedOutput> {
    from_file(&mut GltfFile::from_bytes(name, bytes)?, None)
}

/// An output built but not yet written, named `name` in messages: its document as the `.glb`
/// bytes, its lightmaps as the atlases its EXR files will be written from.
pub fn from_prepared(name: &Path, prepared: &Prepared) -> Result<BakedOutput> {
    let mut file = GltfFile::from_bytes(name, &prepared.glb()?)?;
    from_file(&mut file, prepared.lightmaps())
}

/// `result` as its output would hold it, without writing anything (the exporter's bytes read
/// back in memory).
pub fn as_written(scene: &Scene, result: &BakeResult) -> Result<BakedOutput> {
    let name = Path::new("bake.glb");
    let prepared = Prepared::new(name, scene, result, &ExportOptions::default())?;
    from_prepared(name, &prepared)
}

fn from_file(file: &mut GltfFile, memory: Option<&Lightmaps>) -> Result<BakedOutput> {
    let layouts = lightmaps::read(file, memory)?;
    let file = &*file;
    let nodes = file.nodes();
    let parent = parents(nodes.iter().map(|n| &n.children), nodes.len());
    let node_infos = nodes
        .iter()
        .zip(&parent)
        .enumerate()
        .map(|(i, (n, &parent))| NodeInfo {
            name: n.name.clone(),
            parent,
            power_w: (n.extras.as_ref()).and_then(|e| e.get("power_W")?.as_f64()),
            maintenance_factor:
                file.json()["nodes"][i]["extensions"]["LUXBAKE_luminaire"]["maintenanceFactor"]
                    .as_f64(),
        })
        .collect();
    let json = file.json();
    let names = file.material_names();
    let reflectances_rgb: Vec<Option<DVec3>> = (0..names.len())
        .map(|i| reflectance(&json["materials"][i]["extras"]["luxbake"]["reflectance"]))
        .collect();
    let reflectances: Vec<Option<f64>> = (0..names.len())
        .map(|i| {
            let v = &json["materials"][i]["extras"]["luxbake"]["reflectance"];
            v.as_f64().or(reflectances_rgb[i].map(luma))
        })
        .collect();
    let variant_of = |i: usize| {
        let v = json["materials"][i]["extras"]["luxbake"]["variantOf"].as_u64();
        v.map(|v| v as usize).filter(|&v| v < names.len() && v != i)
    };
    let probes = probe_nodes(file)?;
    let points = working_plane(file)?;
    let mut primitives = Vec::new();
    let mut shown = Vec::new();
    let mut scratch: Vec<Scratch> = (layouts.lightmaps.iter())
        .map(|l| Scratch::new(l.width, l.height))
        .collect();
    for i in file.scene_nodes() {
        let world = nodes[i].world_from_local;
        let display_only = (nodes[i].extras.as_ref())
            .is_some_and(|e| e["luxbake"]["displayOnly"] == Value::Bool(true));
        if display_only {
            for p in file.primitives(i) {
                shown.extend(shown_primitive(json, &p, world)?);
            }
            continue;
        }
        for p in file.primitives(i) {
            if let Some(prim) = primitive(file, &p, i, world, &layouts, &mut scratch)? {
                if reflectances.get(prim.material).copied().flatten().is_none() {
                    return Err(file.err(
                        format!("/materials/{}", prim.material),
                        "the material has no extras.luxbake.reflectance (not written by luxbake?)",
                    ));
                }
                primitives.push(prim);
            }
        }
    }
    if primitives.is_empty() {
        return Err(file.err(
            "",
            "not a luxbake output: no primitive has an _ILLUMINANCE attribute (bake the scene \
             first: bake IN -o OUT)",
        ));
    }
    let materials = (names.iter().enumerate())
        .map(|(i, name)| MaterialInfo {
            name: name.clone(),
            reflectance: reflectances[i].unwrap_or(0.0),
            reflectance_rgb: reflectances_rgb[i].unwrap_or(DVec3::ZERO),
            variant_of: variant_of(i),
            look: look(&json["materials"][i]),
        })
        .collect();
    Ok(BakedOutput {
        nodes: node_infos,
        materials,
        primitives,
        shown,
        probes,
        working_plane: (!points.is_empty()).then_some(PlaneInput { points }),
        lightmaps: layouts.lightmaps,
        cameras: super::cameras::read(file)?,
        summary: file
            .scene_extras()
            .map(|e| e["luxbake"].clone())
            .filter(|s| !s.is_null()),
        file: file.path().to_path_buf(),
        resources: file.resources_read().to_vec(),
    })
}

/// Every node of the scene whose `extras.luxbake.faces` is an object, in node order.
fn probe_nodes(file: &GltfFile) -> Result<Vec<ProbeNode>> {
    let nodes = file.nodes();
    let mut probes = Vec::new();
    for i in file.scene_nodes() {
        let Some(luxbake) = nodes[i].extras.as_ref().map(|e| &e["luxbake"]) else {
            continue;
        };
        let Some(faces) = luxbake["faces"].as_object() else {
            continue;
        };
        let mut values = [0.0; 6];
        for (v, name) in values.iter_mut().zip(FACE_NAMES) {
            *v = faces.get(name).and_then(Value::as_f64).ok_or_else(|| {
                file.err(
                    format!("/nodes/{i}/extras/luxbake/faces"),
                    format!("a probe without its \"{name}\" value (lx)"),
                )
            })?;
        }
        probes.push(ProbeNode {
            node: i,
            position: probe_position(&nodes[i]),
            faces: values,
            working_plane: luxbake["probe"]["origin"]["kind"] == "workingPlane",
        });
    }
    Ok(probes)
}

/// A probe node's world position: `extras.luxbake.probe.position`, else the node's world origin.
fn probe_position(node: &Node) -> DVec3 {
    let extras = node
        .extras
        .as_ref()
        .map(|e| &e["luxbake"]["probe"]["position"]);
    let stored = extras.and_then(Value::as_array).and_then(|a| {
        let c: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
        (a.len() == 3 && c.len() == 3).then(|| DVec3::new(c[0], c[1], c[2]))
    });
    stored.unwrap_or_else(|| node.world_from_local.transform_point3(DVec3::ZERO))
}

/// A material's display factors as written.
fn look(m: &Value) -> Look {
    let numbers = |v: &Value, default: &[f64]| -> Vec<f64> {
        let got: Vec<f64> = (v.as_array().into_iter().flatten())
            .filter_map(Value::as_f64)
            .collect();
        if got.len() == default.len() {
            got
        } else {
            default.to_vec()
        }
    };
    let b = numbers(&m["pbrMetallicRoughness"]["baseColorFactor"], &[1.0; 4]);
    let e = numbers(&m["emissiveFactor"], &[0.0; 3]);
    let t = &m["emissiveTexture"];
    Look {
        base_color: [b[0], b[1], b[2], b[3]],
        emissive: [e[0], e[1], e[2]],
        emissive_texture: t["index"]
            .as_u64()
            .map(|i| (i as usize, t["texCoord"].as_u64().unwrap_or(0) as u32)),
        unlit: !m["extensions"]["KHR_materials_unlit"].is_null(),
    }
}

/// A reflectance written as `[r, g, b]` (or a single number, grey).
fn reflectance(v: &Value) -> Option<DVec3> {
    if let Some(x) = v.as_f64() {
        return Some(DVec3::splat(x));
    }
    let a = v.as_array().filter(|a| a.len() == 3)?;
    let c: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
    (c.len() == 3).then(|| DVec3::new(c[0], c[1], c[2]))
}

/// A primitive's positions in world space and its triangles wound counter-clockwise there.
fn in_world(p: &GltfPrimitive, world: DMat4) -> Result<(Vec<DVec3>, Vec<[u32; 3]>)> {
    let positions: Vec<DVec3> = (p.positions()?.into_iter())
        .map(|q| world.transform_point3(q))
        .collect();
    let mut triangles = p.triangles()?;
    if world.determinant() < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    Ok((positions, triangles))
}

/// A display-only primitive with COLOR_0 (others are skipped).
fn shown_primitive(json: &Value, p: &GltfPrimitive, world: DMat4) -> Result<Option<Shown>> {
    if !p.has("COLOR_0") || !p.is_triangles() {
        return Ok(None);
    }
    p.vertex_count()?;
    let (positions, triangles) = in_world(p, world)?;
    let base = match p.material() {
        Some(m) => look(&json["materials"][m]).base_color,
        None => [1.0; 4],
    };
    Ok(Some(Shown {
        positions,
        triangles,
        color: colors(p)?,
        base: [base[0], base[1], base[2]],
    }))
}

/// A baked primitive, or `None` when it has no `_ILLUMINANCE` or is not made of triangles.
/// `layouts`: the lightmaps and each material's; `scratch`: one per lightmap.
fn primitive(
    file: &GltfFile,
    p: &GltfPrimitive,
    node: usize,
    world: DMat4,
    layouts: &Layouts,
    scratch: &mut [Scratch],
) -> Result<Option<Primitive>> {
    if !p.has("_ILLUMINANCE") || !p.is_triangles() {
        return Ok(None);
    }
    p.vertex_count()?;
    let scalar = |name: &str| -> Result<Vec<f32>> {
        if !p.has(name) {
            let at = format!("{}/attributes/{name}", p.at);
            return Err(file.err(at, "missing beside _ILLUMINANCE"));
        }
        Ok(p.read(name, 1)?.into_iter().map(|x| x as f32).collect())
    };
    let illuminance = scalar("_ILLUMINANCE")?;
    let illuminance_direct = scalar("_ILLUMINANCE_DIRECT")?;
    let luminance = scalar("_LUMINANCE")?;
    let color = match p.has("COLOR_0") {
        true => Some(colors(p)?),
        false => None,
    };
    let (positions, triangles) = in_world(p, world)?;
    let material = p
        .material()
        .ok_or_else(|| file.err(&p.at, "a baked primitive without a material"))?;
    let lightmap = match layouts.of_material.get(material).copied().flatten() {
        Some((k, set)) => {
            let uv: Vec<DVec2> = (p.read(&format!("TEXCOORD_{set}"), 2)?.chunks_exact(2))
                .map(|q| DVec2::new(q[0], q[1]))
                .collect();
            let (w, h) = (layouts.lightmaps[k].width, layouts.lightmaps[k].height);
            Some(LightmapUse {
                lightmap: k,
                texels: rasterise(&uv, &triangles, (w, h), &mut scratch[k]),
                uv,
            })
        }
        None => None,
    };
    let covered_from = covered_from(file, p, triangles.len())?;
    Ok(Some(Primitive {
        node,
        material,
        positions,
        triangles,
        illuminance,
        illuminance_direct,
        luminance,
        color,
        lightmap,
        covered_from,
    }))
}

/// `extras.luxbake.coveredFrom` of a primitive: an integer up to its triangle count, or absent.
fn covered_from(file: &GltfFile, p: &GltfPrimitive, triangles: usize) -> Result<Option<u32>> {
    let at = format!("{}/extras/luxbake/coveredFrom", p.at);
    match file.json().pointer(&at) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => match v.as_u64() {
            Some(k) if k as usize <= triangles => Ok(Some(k as u32)),
            _ => Err(file.err(
                at,
                format!("the first covered triangle must be an integer up to {triangles}, got {v}"),
            )),
        },
    }
}

/// `COLOR_0` as RGB (a VEC4's alpha dropped).
fn colors(p: &GltfPrimitive) -> Result<Vec<[f32; 3]>> {
    let (raw, n) = match p.read("COLOR_0", 3) {
        Ok(raw) => (raw, 3),
        Err(_) => (p.read("COLOR_0", 4)?, 4),
    };
    Ok(raw
        .chunks_exact(n)
        .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
        .collect())
}

/// The `+y` faces of the probes under the root `probes` → `working_plane`.
fn working_plane(file: &GltfFile) -> Result<Vec<PlanePoint>> {
    let nodes: &[Node] = file.nodes();
    let named = |list: &[usize], name: &str| {
        list.iter()
            .copied()
            .find(|&i| nodes[i].name.as_deref() == Some(name))
    };
    let Some(group) =
        named(file.roots(), "probes").and_then(|p| named(&nodes[p].children, "working_plane"))
    else {
        return Ok(Vec::new());
    };
    let mut points = Vec::new();
    for &i in &nodes[group].children {
        let extras = nodes[i].extras.as_ref().map(|e| &e["luxbake"]);
        let face = |key: &str| {
            extras.and_then(|e| e[key]["+y"].as_f64()).ok_or_else(|| {
                file.err(
                    format!("/nodes/{i}/extras/luxbake/{key}"),
                    "a working-plane probe without its \"+y\" value (lx)",
                )
            })
        };
        points.push(PlanePoint::new(
            probe_position(&nodes[i]),
            face("faces")?,
            face("facesDirect")?,
            face("facesIndirect")?,
        ));
    }
    Ok(points)
}
