//! The Wavefront OBJ importer (with MTL materials).
//!
//! Input: the OBJ file's bytes, the [`Ctx`] and the file's up axis. Output: a [`Scene`] whose
//! nodes are the OBJ objects/groups (consecutive parts with the same name form one node, with
//! identity transforms) and whose surfaces are one per (node, material used).
//! Conventions: units are metres; numbers are parsed as f64 (tobj's `use_f64`). With `UpAxis::Z`, (x, y, z) ↦ (x, z, −y) (a rotation, so
//! windings are kept); `UpAxis::Y` keeps coordinates. Faces are counter-clockwise from the front
//! (the OBJ convention) and triangulated as fans. Normals come from the file when every vertex has
//! one, else flat face normals. Texture coordinates become glTF's (u, 1 − v).
//! `mtllib` files are read through the same confinement as glTF URIs (inside the OBJ's folder; an
//! escaping path is an error); a missing MTL file is a warning and its faces get the default
//! material. See `obj_mtl` for how MTL materials are converted.

use super::UpAxis;
use super::context::Ctx;
use super::geometry::{Origin, RawMesh, into_surface};
use super::obj_mtl::{self, MtlSource, ObjTextures};
use super::resources::{confine, lexically_inside};
use crate::scene::{LocalTransform, Material, Node, Scene};
use crate::{Error, Result};
use glam::{DMat4, DVec2, DVec3};
use std::cell::RefCell;
use std::path::Path;

/// What the MTL loader callback saw (tobj calls it once per `mtllib` line).
#[derive(Default)]
struct MtlLoads {
    sources: Vec<MtlSource>,
    warnings: Vec<String>,
    error: Option<Error>,
}

pub(crate) fn load(ctx: &mut Ctx, bytes: &[u8], up: UpAxis) -> Result<Scene> {
    let loads = RefCell::new(MtlLoads::default());
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = {
        let ctx_ref: &Ctx = ctx;
        tobj::load_obj_buf(&mut &bytes[..], &options, |reference| {
            load_mtl(ctx_ref, reference, &mut loads.borrow_mut())
        })
        .map_err(|e| ctx.err("", format!("cannot parse the OBJ file: {e}")))?
    };
    let loads = loads.into_inner();
    if let Some(error) = loads.error {
        return Err(error);
    }
    for w in loads.warnings {
        ctx.warn(w);
    }
    for source in &loads.sources {
        ctx.record(source.path.clone());
    }
    let tobj_materials = materials.unwrap_or_default();
    warn_unknown_usemtl(ctx, bytes, &tobj_materials);

    let mut textures = ObjTextures::default();
    let mut scene_materials = Vec::with_capacity(tobj_materials.len() + 1);
    let mut k = 0;
    for source in &loads.sources {
        for m in &tobj_materials[k..k + source.count] {
            scene_materials.push(obj_mtl::material(ctx, m, source, &mut textures)?);
        }
        k += source.count;
    }
    let default_material = scene_materials.len();

    let file_name = ctx
        .file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut nodes: Vec<Node> = Vec::new();
    let mut surfaces = Vec::new();
    let mut start = 0;
    while start < models.len() {
        let name = models[start].name.clone();
        let end = start
            + models[start..]
                .iter()
                .take_while(|m| m.name == name)
                .count();
        let node_index = nodes.len();
        let node_path = format!("{file_name}: object '{name}'");
        // Group the parts of this object by material, in order of first use.
        let mut by_material: Vec<(usize, Vec<&tobj::Mesh>)> = Vec::new();
        for model in &models[start..end] {
            let material = model.mesh.material_id.unwrap_or(default_material);
            match by_material.iter_mut().find(|(m, _)| *m == material) {
                Some((_, parts)) => parts.push(&model.mesh),
                None => by_material.push((material, vec![&model.mesh])),
            }
        }
        let mut node_surfaces = Vec::new();
        for (primitive, (material, parts)) in by_material.into_iter().enumerate() {
            let material_name = tobj_materials
                .get(material)
                .map_or("(default)", |m| m.name.as_str());
            let mesh = merge_parts(ctx, &parts, up, &node_path)?;
            node_surfaces.push(surfaces.len());
            surfaces.push(into_surface(
                mesh,
                Origin {
                    node: node_index,
                    primitive,
                    source_path: format!("{node_path}, material '{material_name}'"),
                    material,
                },
            ));
        }
        nodes.push(Node {
            name: Some(name),
            source_path: node_path,
            children: Vec::new(),
            local: LocalTransform::default(),
            world_from_local: DMat4::IDENTITY,
            mesh_name: None,
            surfaces: node_surfaces,
            light: None,
            camera: None,
            extras: None,
        });
        start = end;
    }
    if surfaces.iter().any(|s| s.material == default_material) {
        scene_materials.push(Material::default_material());
    }
    let (images, textures) = textures.into_parts();
    Ok(Scene {
        source_file: ctx.file.clone(),
        name: None,
        roots: (0..nodes.len()).collect(),
        nodes,
        surfaces,
        materials: scene_materials,
        textures,
        images,
        samplers: Vec::new(),
        lights: Vec::new(),
        profiles: Vec::new(),
        luminaires: Vec::new(),
        cameras: Vec::new(),
        extras: None,
        warnings: std::mem::take(&mut ctx.warnings),
        input_files: std::mem::take(&mut ctx.input_files),
    })
}

/// The `mtllib` callback: read the MTL file confined to the OBJ's folder.
fn load_mtl(ctx: &Ctx, reference: &Path, loads: &mut MtlLoads) -> tobj::MTLLoadResult {
    let empty = Ok((Vec::new(), Default::default()));
    if loads.error.is_some() {
        return empty;
    }
    let at = format!("mtllib '{}'", reference.display());
    if (ctx.dir.as_deref())
        .is_some_and(|d| lexically_inside(d, reference) && !d.join(reference).exists())
    {
        loads.warnings.push(format!(
            "{}: {at}: the MTL file is missing; its materials are replaced by the default \
             material",
            ctx.file.display()
        ));
        return empty;
    }
    let path = match confine(ctx, reference, &at, "MTL file") {
        Ok(path) => path,
        Err(e) => {
            loads.error = Some(e);
            return empty;
        }
    };
    let parsed = super::files::read(&path)
        .map_err(|e| e.to_string())
        .and_then(|b| check_colour_lines(&b).map(|()| b))
        .and_then(|b| tobj::load_mtl_buf(&mut &b[..]).map_err(|e| e.to_string()));
    match parsed {
        Ok((materials, map)) => {
            loads.sources.push(MtlSource {
                path: path.clone(),
                folder: reference
                    .parent()
                    .map(Path::to_path_buf)
                    .unwrap_or_default(),
                count: materials.len(),
            });
            Ok((materials, map))
        }
        Err(message) => {
            loads.error = Some(Error::input(
                path,
                "",
                format!("cannot read the MTL file: {message}"),
            ));
            empty
        }
    }
}

/// Every `Ka`/`Kd`/`Ks`/`Ke` line of an MTL file has three values: `tobj` panics on fewer.
fn check_colour_lines(bytes: &[u8]) -> std::result::Result<(), String> {
    for (i, line) in String::from_utf8_lossy(bytes).lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next()
            && words.count() < 3
        {
            return Err(format!("line {}: {key} needs three values (r g b)", i + 1));
        }
    }
    Ok(())
}

/// Map a point or direction from the file's axes to glTF's (+Y up).
fn to_y_up(up: UpAxis, v: DVec3) -> DVec3 {
    match up {
        UpAxis::Y => v,
        UpAxis::Z => DVec3::new(v.x, v.z, -v.y),
    }
}

/// Concatenate the parts of one object that use the same material.
fn merge_parts(ctx: &Ctx, parts: &[&tobj::Mesh], up: UpAxis, at: &str) -> Result<RawMesh> {
    let all_normals = parts
        .iter()
        .all(|m| !m.normals.is_empty() && m.normals.len() == m.positions.len());
    let all_uvs = parts
        .iter()
        .all(|m| !m.texcoords.is_empty() && m.texcoords.len() / 2 == m.positions.len() / 3);
    let mut mesh = RawMesh {
        positions: Vec::new(),
        normals: all_normals.then(Vec::new),
        uv0: all_uvs.then(Vec::new),
        uv1: None,
        triangles: Vec::new(),
    };
    for part in parts {
        let base = mesh.positions.len() as u32;
        let count = part.positions.len() / 3;
        for p in part.positions.chunks_exact(3) {
            let p = DVec3::new(p[0], p[1], p[2]);
            if !p.is_finite() {
                return Err(ctx.err(at, format!("vertex position {p} is not finite")));
            }
            mesh.positions.push(to_y_up(up, p));
        }
        if let Some(normals) = mesh.normals.as_mut() {
            normals.extend(
                part.normals
                    .chunks_exact(3)
                    .map(|n| to_y_up(up, DVec3::new(n[0], n[1], n[2]))),
            );
        }
        if let Some(uvs) = mesh.uv0.as_mut() {
            uvs.extend(
                part.texcoords
                    .chunks_exact(2)
                    .map(|t| DVec2::new(t[0], 1.0 - t[1])),
            );
        }
        for t in part.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= count) {
                return Err(ctx.err(at, "a face refers to a vertex that does not exist"));
            }
            mesh.triangles.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    Ok(mesh)
}

/// One warning per `usemtl` name that no loaded MTL file defines (tobj gives its faces no
/// material, so they get the default one).
fn warn_unknown_usemtl(ctx: &mut Ctx, bytes: &[u8], materials: &[tobj::Material]) {
    let text = String::from_utf8_lossy(bytes);
    let mut warned: Vec<&str> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("usemtl") {
            continue;
        }
        let name = words.next().unwrap_or("");
        if materials.iter().any(|m| m.name == name) || warned.contains(&name) {
            continue;
        }
        warned.push(name);
        let file = ctx.file.display().to_string();
        ctx.warn(format!(
            "{file} line {}: usemtl '{name}' names no material of the MTL files it loads; its \
             faces get the default reflectance 0.5",
            i + 1
        ));
    }
}
