//! Assembling the glTF document: the root JSON object and its binary buffer.
//!
//! Input: the [`Scene`], the [`BakeResult`] (surfaces, probes, lightmaps), the [`ExportOptions`]
//! and each lightmap atlas's EXR URI.
//! Output: a [`Document`]:
//! the root JSON (without `buffers`, whose URI depends on the container) and the buffer bytes.
//! Invariants: fields are inserted in one fixed order and arrays follow scene order, so equal
//! inputs give equal documents; empty arrays are omitted (glTF forbids them); `extensionsUsed`
//! lists exactly the extension names that occur in the document (outside `extras`), sorted;
//! `extensionsRequired` is never written (Blender refuses files requiring extensions it does not
//! know, such as `EXT_lights_ies` and `LUXBAKE_luminaire`).

use super::lightmap_material::Variants;
use super::{
    ExportOptions, buffer::Binary, lightmaps, luminaires, material, mesh, nodes, openings, probes,
};
use crate::{Result, result::BakeResult, scene::Scene};
use serde_json::{Map, Value, json};
use std::collections::{BTreeMap, BTreeSet};

/// The document before it is packed into `.gltf` + `.bin` or `.glb`.
#[derive(Debug)]
pub struct Document {
    /// The root object; the container adds `buffers`.
    pub root: Map<String, Value>,
    /// The binary buffer (empty when there is no geometry and no image).
    pub bin: Vec<u8>,
}

/// Build the document for `scene` baked as `result`; `lightmap_uris[k]` is atlas k's EXR file.
pub(crate) fn build(
    scene: &Scene,
    result: &BakeResult,
    options: &ExportOptions,
    lightmap_uris: &[String],
) -> Result<Document> {
    assemble(scene, result, options, Some(lightmap_uris))
}

/// Build the document of `scene` as an input: the geometry of `result` without the baked
/// attributes and without the run summary in the scene's extras.
pub(crate) fn build_input(
    scene: &Scene,
    result: &BakeResult,
    options: &ExportOptions,
) -> Result<Document> {
    assemble(scene, result, options, None)
}

/// `lightmap_uris`: `None` for an input scene (no baked values, no lightmaps).
fn assemble(
    scene: &Scene,
    result: &BakeResult,
    options: &ExportOptions,
    lightmap_uris: Option<&[String]>,
) -> Result<Document> {
    let baked = lightmap_uris.is_some();
    let mut binary = Binary::default();
    let variants = Variants::plan(scene, result, baked, scene.materials.len())?;
    let meshes = mesh::build(scene, result, &mut binary, baked, &variants)?;
    let (mut textures, mut images, mut samplers) = material::textures(scene, &mut binary);
    let atlases = lightmaps::add(
        result.lightmaps.as_ref().filter(|_| baked),
        &result.summary,
        lightmap_uris.unwrap_or_default(),
        &mut binary,
        lightmaps::Arrays {
            textures: &mut textures,
            images: &mut images,
            samplers: &mut samplers,
        },
    )?;
    let profiles = luminaires::profiles(scene, &mut binary);
    let mut materials = material::materials(scene, &meshes.back_baked, options, &profiles);
    materials.extend(variants.materials(scene, &meshes.back_baked, options, &profiles, &atlases));
    let mut nodes = nodes::nodes(scene, &meshes.node_mesh, &profiles.node_extensions(scene));
    let mut scenes = vec![nodes::scene(scene, baked.then_some(&result.summary))];
    let mut mesh_json = meshes.json;
    if baked {
        openings::add(
            scene,
            &result.openings,
            &mut binary,
            openings::Arrays {
                nodes: &mut nodes,
                meshes: &mut mesh_json,
                materials: &mut materials,
                scene: &mut scenes[0],
            },
        );
    }
    probes::add(
        scene,
        &result.probes,
        options.probe_glyphs,
        &mut binary,
        probes::Arrays {
            nodes: &mut nodes,
            meshes: &mut mesh_json,
            materials: &mut materials,
            scene: &mut scenes[0],
        },
    )?;
    let lights = nodes::lights(scene);
    let (bin, views, accessors) = binary.finish();

    let mut root = Map::new();
    root.insert(
        "asset".into(),
        json!({
            "generator": concat!("luxbake ", env!("CARGO_PKG_VERSION")),
            "version": "2.0",
        }),
    );
    root.insert("extensionsUsed".into(), json!([]));
    root.insert("scene".into(), json!(0));
    let arrays = [
        ("scenes", scenes),
        ("nodes", nodes),
        ("cameras", scene.cameras.clone()),
        ("meshes", mesh_json),
        ("materials", materials),
        ("textures", textures),
        ("images", images),
        ("samplers", samplers),
        ("accessors", accessors),
        ("bufferViews", views),
    ];
    for (key, array) in arrays {
        if !array.is_empty() {
            root.insert(key.into(), Value::Array(array));
        }
    }
    // Root extensions in sorted order: EXT_lights_ies, KHR_lights_punctual, LUXBAKE_luminaire.
    let mut extensions: BTreeMap<&str, Value> = profiles.root_extensions().into_iter().collect();
    if let Some(lights) = lights {
        extensions.insert(nodes::LIGHTS, lights);
    }
    if !extensions.is_empty() {
        root.insert("extensions".into(), json!(extensions));
    }

    let mut used = BTreeSet::new();
    collect_extensions(&Value::Object(root.clone()), &mut used);
    if used.is_empty() {
        root.remove("extensionsUsed");
    } else {
        root.insert("extensionsUsed".into(), json!(used));
    }
    Ok(Document { root, bin })
}

/// Every key of every `extensions` object in `value`, not looking inside `extras`.
fn collect_extensions(value: &Value, used: &mut BTreeSet<String>) {
    match value {
        Value::Object(map) => {
            for (key, v) in map {
                match key.as_str() {
                    "extras" => {}
                    "extensions" => {
                        if let Value::Object(ext) = v {
                            used.extend(ext.keys().cloned());
                        }
                        collect_extensions(v, used);
                    }
                    _ => collect_extensions(v, used),
                }
            }
        }
        Value::Array(items) => items.iter().for_each(|v| collect_extensions(v, used)),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_are_found_outside_extras_only() {
        let doc = json!({
            "extensions": {"B": {}},
            "materials": [{"extensions": {"A": {"extensions": {"C": 1}}}}],
            "nodes": [{"extras": {"extensions": {"X": {}}}}],
        });
        let mut used = BTreeSet::new();
        collect_extensions(&doc, &mut used);
        assert_eq!(used.into_iter().collect::<Vec<_>>(), ["A", "B", "C"]);
    }
}
