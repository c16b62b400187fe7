//! The glTF 2.0 importer (`.gltf` with external or embedded resources, `.glb`).
//!
//! Input: the file's bytes and the [`Ctx`] of the import. Output: a [`Scene`] in world space,
//! following the invariants documented in `crate::scene`.
//! Steps: parse and validate (`document`), read buffers and images confined to the input folder
//! (`buffers`), build the node tree and world transforms (`nodes`), materials (`material`,
//! `luxbake_ext`), one surface per (node instance, triangle primitive) (`mesh`, `accessor`) and
//! one light per node placing a `KHR_lights_punctual` light (`lights`), photometric profiles
//! (`profiles`: read first, parsed last, so that every index into them is checked before any
//! file is parsed) and one luminaire per node carrying `EXT_lights_ies` / `LUXBAKE_luminaire`
//! (`luminaires`). Cameras and `extras` are kept verbatim. Surfaces and lights come only from the
//! nodes of the imported scene; other nodes are kept (with their transforms) but instantiate
//! nothing. Primitives without a material use [`Material::default_material`], appended once after
//! the file's materials when needed. `readback` reads a luxbake *output* back for the report instead.

mod accessor;
mod buffers;
mod document;
pub mod file;
mod lights;
mod luminaires;
mod luxbake_ext;
mod material;
mod mesh;
mod nodes;
mod profiles;
mod raw;
mod textures;

use super::context::Ctx;
use crate::Result;
use crate::scene::{Material, Scene};
use serde_json::Value;

pub(crate) fn load(ctx: &mut Ctx, bytes: &[u8]) -> Result<Scene> {
    let document::Parsed { doc, raw, bin } = document::parse(ctx, bytes)?;
    let buffers = buffers::load_buffers(ctx, &doc, bin.as_deref())?;
    let images = buffers::load_images(ctx, &doc, &buffers)?;
    let profile_sources = profiles::read(ctx, &doc, &raw, &buffers)?;
    let mut materials = material::materials(ctx, &doc, &raw, &images, profile_sources.counts)?;
    let hierarchy = nodes::build(ctx, &doc, &raw)?;
    let mut nodes = hierarchy.nodes;

    let default_material = materials.len();
    let mut surfaces = Vec::new();
    let mut lights = Vec::new();
    let gltf_nodes: Vec<::gltf::Node> = doc.nodes().collect();
    for &i in &hierarchy.reachable {
        let node = &gltf_nodes[i];
        let world = nodes[i].world_from_local;
        if node.skin().is_some() {
            ctx.warn_once(
                "skin",
                format!("/nodes/{i}: skinning is ignored; meshes are baked in their bind pose"),
            );
        }
        // Meshes a luxbake output drew for viewers only (luminous openings) are not geometry.
        let display_only = raw::cloned(&raw, &format!("/nodes/{i}/extras/luxbake/displayOnly"))
            .is_some_and(|v| v == Value::Bool(true));
        if let Some(mesh) = node.mesh().filter(|_| !display_only) {
            let placement = mesh::Placement {
                node: i,
                world_from_local: world,
                default_material,
            };
            for surface in mesh::surfaces(ctx, &buffers, &mesh, &placement)? {
                nodes[i].surfaces.push(surfaces.len());
                surfaces.push(surface);
            }
        }
        if let Some(light) = node.light() {
            nodes[i].light = Some(lights.len());
            lights.push(lights::light(ctx, &raw, light.index(), i, world)?);
        }
    }
    if surfaces.iter().any(|s| s.material == default_material) {
        materials.push(Material::default_material());
    }
    let luminaires =
        luminaires::luminaires(ctx, &raw, &nodes, &hierarchy.reachable, &profile_sources)?;
    let profiles = profiles::parse(ctx, profile_sources)?;

    Ok(Scene {
        source_file: ctx.file.clone(),
        name: hierarchy.name,
        nodes,
        roots: hierarchy.roots,
        surfaces,
        materials,
        textures: textures::textures(&doc),
        images,
        samplers: textures::samplers(&doc, &raw),
        lights,
        profiles,
        luminaires,
        cameras: raw
            .get("cameras")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default(),
        extras: hierarchy.extras,
        warnings: std::mem::take(&mut ctx.warnings),
        input_files: std::mem::take(&mut ctx.input_files),
    })
}
