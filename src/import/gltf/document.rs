//! Parsing a `.gltf`/`.glb` file into a validated `gltf::Document` plus its raw JSON.
//!
//! Input: the file's bytes. Output: [`Parsed`] — the typed, validated document (all indices valid,
//! all enums known), the raw JSON (for values kept verbatim and numbers read at full f64
//! precision) and the GLB binary chunk.
//! Invariants: `extensionsRequired` may only name extensions luxbake handles (anything else is
//! refused, naming it); `LUXBAKE_material`, `LUXBAKE_luminaire` (ours) and `EXT_lights_ies` are
//! accepted even though the `gltf` crate would reject them. Validation errors of the `gltf` crate (paths like `meshes[0].primitives[0]`) are
//! reported as JSON pointers (`/meshes/0/primitives/0`).

use crate::Result;
use crate::import::{context::Ctx, glb};
use serde_json::Value;

/// Extensions we can honour when a file requires them.
const HANDLED_REQUIRED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_unlit",
    KHR_MESH_QUANTIZATION,
    LUXBAKE_MATERIAL,
    EXT_LIGHTS_IES,
    LUXBAKE_LUMINAIRE,
];

/// Our own material extension, unknown to the `gltf` crate.
pub(super) const LUXBAKE_MATERIAL: &str = "LUXBAKE_material";
/// The vendor extension for IES luminaires, unknown to the `gltf` crate.
pub(super) const EXT_LIGHTS_IES: &str = "EXT_lights_ies";
/// Our own luminaire extension, unknown to the `gltf` crate.
pub(super) const LUXBAKE_LUMINAIRE: &str = "LUXBAKE_luminaire";
/// Quantized vertex data: integer accessors, which `accessor` converts as the spec says.
const KHR_MESH_QUANTIZATION: &str = "KHR_mesh_quantization";
/// Extensions luxbake reads itself; the `gltf` crate must not see them as required.
const READ_HERE: &[&str] = &[
    LUXBAKE_MATERIAL,
    EXT_LIGHTS_IES,
    LUXBAKE_LUMINAIRE,
    KHR_MESH_QUANTIZATION,
];

pub(super) struct Parsed {
    pub doc: ::gltf::Document,
    pub raw: Value,
    pub bin: Option<Vec<u8>>,
}

pub(super) fn parse(ctx: &mut Ctx, bytes: &[u8]) -> Result<Parsed> {
    let (json, bin) = if glb::is_glb(bytes) {
        let g = glb::parse(bytes).map_err(|m| ctx.err("", m))?;
        (g.json, g.bin.map(<[u8]>::to_vec))
    } else {
        (bytes, None)
    };
    // glTF forbids a byte-order mark before the JSON; some editors write one: read past it.
    let json = match json.strip_prefix(b"\xEF\xBB\xBF") {
        Some(rest) => {
            ctx.warn("the glTF JSON starts with a UTF-8 byte-order mark (glTF allows none); read past it");
            rest
        }
        None => json,
    };
    let raw: Value =
        serde_json::from_slice(json).map_err(|e| ctx.err("", format!("not valid JSON: {e}")))?;
    if !raw.is_object() {
        return Err(ctx.err("", "the glTF JSON must be an object"));
    }
    check_version(ctx, &raw)?;
    check_required_extensions(ctx, &raw)?;
    let invalid = |e: serde_json::Error| ctx.err("", format!("not valid glTF 2.0 JSON: {e}"));
    let mut root = match scenes_without_nodes(&raw) {
        // A scene's `nodes` is optional in glTF 2.0 (Blender writes none for an empty scene);
        // the `gltf` crate requires it: given as empty.
        true => {
            let mut patched = raw.clone();
            for scene in patched["scenes"].as_array_mut().into_iter().flatten() {
                if let Some(o) = scene.as_object_mut() {
                    o.entry("nodes").or_insert_with(|| Value::Array(Vec::new()));
                }
            }
            serde_json::from_value::<::gltf::json::Root>(patched).map_err(invalid)?
        }
        false => ::gltf::json::Root::from_slice(json).map_err(invalid)?,
    };
    root.extensions_required
        .retain(|e| !READ_HERE.contains(&e.as_str()));
    check_position_accessors(ctx, &root)?;
    let doc = match ::gltf::Document::from_json(root.clone()) {
        Ok(doc) => doc,
        Err(::gltf::Error::Validation(errors)) => {
            let (tolerated, fatal): (Vec<_>, Vec<_>) = errors.into_iter().partition(tolerated);
            if !fatal.is_empty() {
                return Err(validation_error(ctx, &fatal));
            }
            for (path, _) in &tolerated {
                let (pointer, _) = json_pointer(path.as_str());
                ctx.warn_once(
                    "POSITION min/max",
                    format!(
                        "{pointer}: missing (the spec requires min and max on POSITION \
                         accessors); ignored"
                    ),
                );
            }
            ::gltf::Document::from_json_without_validation(root)
        }
        Err(other) => return Err(ctx.err("", format!("invalid glTF: {other}"))),
    };
    Ok(Parsed { doc, raw, bin })
}

/// Some scene object has no `nodes` member.
fn scenes_without_nodes(raw: &Value) -> bool {
    (raw.get("scenes")
        .and_then(Value::as_array)
        .into_iter()
        .flatten())
    .any(|s| s.is_object() && s.get("nodes").is_none())
}

/// Every primitive's `POSITION` names an existing accessor: the `gltf` crate's validation indexes
/// the accessors with it unchecked (a panic, not an error, on an index out of range).
fn check_position_accessors(ctx: &Ctx, root: &::gltf::json::Root) -> Result<()> {
    let count = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position =
                ::gltf::json::validation::Checked::Valid(::gltf::json::mesh::Semantic::Positions);
            if let Some(index) = prim.attributes.get(&position)
                && index.value() >= count
            {
                return Err(ctx.err(
                    format!("/meshes/{m}/primitives/{p}/attributes/POSITION"),
                    format!(
                        "accessor {} does not exist (the file has {count})",
                        index.value()
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn check_version(ctx: &Ctx, raw: &Value) -> Result<()> {
    let version = raw.pointer("/asset/version").and_then(Value::as_str);
    match version {
        Some(v) if v.split('.').next() == Some("2") => Ok(()),
        Some(v) => Err(ctx.err(
            "/asset/version",
            format!("glTF version {v} is not supported (only 2.x)"),
        )),
        None => Err(ctx.err("/asset", "missing asset.version: not a glTF 2.0 file")),
    }
}

fn check_required_extensions(ctx: &Ctx, raw: &Value) -> Result<()> {
    let Some(required) = raw.get("extensionsRequired").and_then(Value::as_array) else {
        return Ok(());
    };
    for (i, ext) in required.iter().enumerate() {
        let name = ext.as_str().unwrap_or("");
        if HANDLED_REQUIRED.contains(&name) {
            continue;
        }
        let why = match name {
            "KHR_draco_mesh_compression" => "its meshes are Draco-compressed",
            "EXT_meshopt_compression" => "its buffers are meshopt-compressed",
            "KHR_texture_basisu" | "EXT_texture_webp" | "EXT_texture_avif" => {
                "its textures use an image format luxbake does not decode"
            }
            _ => "luxbake does not implement this extension",
        };
        return Err(ctx.err(
            format!("/extensionsRequired/{i}"),
            format!(
                "the file requires extension '{name}', which luxbake cannot read ({why}); \
                 export the file again without it"
            ),
        ));
    }
    Ok(())
}

/// Validation findings we accept: POSITION accessors without `min`/`max` (common in the wild and
/// harmless here, as bounds are recomputed).
fn tolerated(finding: &(::gltf::json::Path, ::gltf::json::validation::Error)) -> bool {
    let path = finding.0.as_str();
    matches!(finding.1, ::gltf::json::validation::Error::Missing)
        && (path.ends_with("[\"POSITION\"].min") || path.ends_with("[\"POSITION\"].max"))
}

fn validation_error(
    ctx: &Ctx,
    errors: &[(::gltf::json::Path, ::gltf::json::validation::Error)],
) -> crate::Error {
    let described: Vec<(String, String)> = errors
        .iter()
        .map(|(path, error)| {
            let (pointer, value) = json_pointer(path.as_str());
            use ::gltf::json::validation::Error as V;
            let error = match error {
                V::IndexOutOfBounds => "the index refers to an element that does not exist",
                V::Invalid => "invalid value",
                V::Missing => "a required member is missing",
                V::Oversize => "a size or offset exceeds the system limits",
                V::Unsupported => "unsupported extension",
            };
            let what = match value {
                Some(v) => format!("{error} ('{v}')"),
                None => error.to_owned(),
            };
            (pointer, what)
        })
        .collect();
    let at = described[0].0.clone();
    let mut message = format!("invalid glTF: {}", described[0].1);
    if described.len() > 1 {
        let others: Vec<String> = described[1..]
            .iter()
            .take(5)
            .map(|(p, w)| format!("{p}: {w}"))
            .collect();
        message += &format!("; also {}", others.join("; "));
        if described.len() > 6 {
            message += &format!(" and {} more", described.len() - 6);
        }
    }
    ctx.err(at, message)
}

/// Convert a `gltf_json::Path` (`meshes[0].attributes["POSITION"] = "x"`) to a JSON pointer
/// (`/meshes/0/attributes/POSITION`) and the value it may name.
pub(super) fn json_pointer(path: &str) -> (String, Option<String>) {
    let (path, value) = match path.split_once(" = ") {
        Some((p, v)) => (p, Some(v.trim_matches('"').to_owned())),
        None => (path, None),
    };
    let mut out = String::new();
    let mut segment = String::new();
    let mut in_brackets = false;
    let flush = |out: &mut String, segment: &mut String| {
        if !segment.is_empty() {
            out.push('/');
            let s = extension_name(segment.trim_matches('"'));
            out.push_str(&s.replace('~', "~0").replace('/', "~1"));
            segment.clear();
        }
    };
    for c in path.chars() {
        match c {
            '[' if !in_brackets => {
                flush(&mut out, &mut segment);
                in_brackets = true;
            }
            ']' if in_brackets => {
                flush(&mut out, &mut segment);
                in_brackets = false;
            }
            '.' if !in_brackets => flush(&mut out, &mut segment),
            _ => segment.push(c),
        }
    }
    flush(&mut out, &mut segment);
    (out, value)
}

/// The `gltf` crate names extension fields in camel case (`khrLightsPunctual`); JSON pointers
/// need the real names (`KHR_lights_punctual`).
fn extension_name(segment: &str) -> String {
    match segment.strip_prefix("khr") {
        Some(rest) if rest.starts_with(|c: char| c.is_ascii_uppercase()) => {
            let mut name = String::from("KHR");
            for c in rest.chars() {
                if c.is_ascii_uppercase() {
                    name.push('_');
                    name.push(c.to_ascii_lowercase());
                } else {
                    name.push(c);
                }
            }
            name
        }
        _ => segment.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::json_pointer;

    #[test]
    fn paths_become_pointers() {
        assert_eq!(
            json_pointer("meshes[0].primitives[0].attributes[\"POSITION\"]").0,
            "/meshes/0/primitives/0/attributes/POSITION"
        );
        assert_eq!(
            json_pointer("extensionsRequired[1] = \"KHR_x\""),
            ("/extensionsRequired/1".to_owned(), Some("KHR_x".to_owned()))
        );
        assert_eq!(json_pointer("asset").0, "/asset");
        assert_eq!(
            json_pointer("extensions.khrLightsPunctual.lights[1].spot").0,
            "/extensions/KHR_lights_punctual/lights/1/spot"
        );
    }
}
