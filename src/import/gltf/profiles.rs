//! Photometric profiles: the root lists `EXT_lights_ies.lights[]` and
//! `LUXBAKE_luminaire.profiles[]` → [`Profile`]s (schema of ours in
//! `schemas/LUXBAKE_luminaire.schema.json`).
//!
//! Inputs: the raw JSON, the validated document and the loaded buffers. Outputs: first
//! [`Sources`] (each profile's bytes and format, read but not parsed), then, once every index
//! into them has been checked, the parsed [`Profile`]s. The scene's profiles are the
//! `EXT_lights_ies` lights in order, followed by the `LUXBAKE_luminaire` profiles in order.
//! Rules: each entry gives exactly one of `uri` (a relative file reference, confined to the
//! input folder like buffers and images, or a `data:` URI) and `bufferView` (which needs a
//! `mimeType`). The format is the `mimeType` (`application/x-ies-lm-63`, or for
//! `LUXBAKE_luminaire` also `application/x-eulumdat`); without one, `EXT_lights_ies` is IES and a
//! `LUXBAKE_luminaire` URI is recognised by its media type (`data:`) or file extension
//! (`.ies`, `.ldt`). Every profile is parsed, used or not.
//! Invariants: any problem is an error at the entry's JSON pointer
//! (`/extensions/EXT_lights_ies/lights/N`, or a member below it such as `.../mimeType`); a parse
//! failure names the entry, the file and the line.

use super::buffers::view_bytes;
use super::document::{EXT_LIGHTS_IES, LUXBAKE_LUMINAIRE};
use super::luxbake_ext::only_keys;
use crate::Result;
use crate::import::{context::Ctx, resources::read_uri};
use crate::photometry::{Format, Photometry};
use crate::scene::Profile;
use serde_json::Value;
use std::path::Path;

/// How many profiles each root list holds; maps list indices to scene profile indices.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Counts {
    /// `EXT_lights_ies.lights` (scene profiles `0..ies`).
    pub ies: usize,
    /// `LUXBAKE_luminaire.profiles` (scene profiles `ies..ies + luxbake`).
    pub luxbake: usize,
}

impl Counts {
    /// The scene profile of `EXT_lights_ies.lights[light]`.
    pub(crate) fn ies_light(&self, light: usize) -> Option<usize> {
        (light < self.ies).then_some(light)
    }

    /// The scene profile of `LUXBAKE_luminaire.profiles[profile]`.
    pub(crate) fn luxbake_profile(&self, profile: usize) -> Option<usize> {
        (profile < self.luxbake).then_some(self.ies + profile)
    }
}

/// A profile read but not yet parsed.
pub(super) struct Source {
    pointer: String,
    pub name: Option<String>,
    /// What the file is called in messages: the URI, `data: URI` or `/bufferViews/K`.
    label: String,
    bytes: Vec<u8>,
    format: Format,
}

/// Every profile of the file, read but not yet parsed.
pub(super) struct Sources {
    pub counts: Counts,
    pub sources: Vec<Source>,
}

/// Which root list an entry comes from.
#[derive(Clone, Copy, PartialEq, Eq)]
enum List {
    Ies,
    Luxbake,
}

/// Read the bytes of every profile of both root lists.
pub(super) fn read(
    ctx: &mut Ctx,
    doc: &::gltf::Document,
    raw: &Value,
    buffers: &[Vec<u8>],
) -> Result<Sources> {
    let mut sources = Vec::new();
    let mut counts = Counts::default();
    for (list, ext, key) in [
        (List::Ies, EXT_LIGHTS_IES, "lights"),
        (List::Luxbake, LUXBAKE_LUMINAIRE, "profiles"),
    ] {
        let entries = root_list(ctx, raw, list, ext, key)?;
        for (i, entry) in entries.iter().enumerate() {
            let at = format!("/extensions/{ext}/{key}/{i}");
            sources.push(read_one(ctx, doc, buffers, entry, &at, list)?);
        }
        match list {
            List::Ies => counts.ies = entries.len(),
            List::Luxbake => counts.luxbake = entries.len(),
        }
    }
    Ok(Sources { counts, sources })
}

/// Parse every profile read by [`read`], in scene order.
pub(super) fn parse(ctx: &Ctx, sources: Sources) -> Result<Vec<Profile>> {
    sources
        .sources
        .into_iter()
        .map(|s| {
            let kind = match s.format {
                Format::Ies => "IES LM-63",
                Format::Eulumdat => "EULUMDAT",
            };
            let photometry = Photometry::parse(&s.bytes, s.format)
                .map_err(|e| ctx.err(&s.pointer, format!("{kind} profile ({}): {e}", s.label)))?;
            Ok(Profile {
                name: s.name,
                source_path: s.pointer,
                bytes: s.bytes,
                photometry,
            })
        })
        .collect()
}

/// The entries of `/extensions/{ext}/{key}` (none when the extension is absent).
fn root_list<'r>(
    ctx: &Ctx,
    raw: &'r Value,
    list: List,
    ext: &str,
    key: &str,
) -> Result<&'r [Value]> {
    let at = format!("/extensions/{ext}");
    let Some(value) = raw.pointer(&at) else {
        return Ok(&[]);
    };
    let object = value
        .as_object()
        .ok_or_else(|| ctx.err(&at, "the extension must be a JSON object"))?;
    if list == List::Luxbake {
        only_keys(object, &[key, "extensions", "extras"], "the extension")
            .map_err(|m| ctx.err(&at, m))?;
    }
    match object.get(key) {
        Some(Value::Array(entries)) => Ok(entries),
        Some(_) => Err(ctx.err(format!("{at}/{key}"), format!("{key} must be an array"))),
        None => Err(ctx.err(&at, format!("the extension has no '{key}' array"))),
    }
}

fn read_one(
    ctx: &mut Ctx,
    doc: &::gltf::Document,
    buffers: &[Vec<u8>],
    entry: &Value,
    at: &str,
    list: List,
) -> Result<Source> {
    let object = entry
        .as_object()
        .ok_or_else(|| ctx.err(at, "a profile must be a JSON object"))?;
    if list == List::Luxbake {
        only_keys(
            object,
            &[
                "uri",
                "bufferView",
                "mimeType",
                "name",
                "extensions",
                "extras",
            ],
            "the profile",
        )
        .map_err(|m| ctx.err(at, m))?;
    }
    let name = match object.get("name") {
        None => None,
        Some(Value::String(s)) => Some(s.clone()),
        Some(_) => return Err(ctx.err(format!("{at}/name"), "name must be a string")),
    };
    let declared = match object.get("mimeType") {
        None => None,
        Some(Value::String(m)) => {
            Some(mime_format(m, list).map_err(|msg| ctx.err(format!("{at}/mimeType"), msg))?)
        }
        Some(_) => return Err(ctx.err(format!("{at}/mimeType"), "mimeType must be a string")),
    };
    let (bytes, label, format) = match (object.get("uri"), object.get("bufferView")) {
        (Some(uri), None) => {
            let uri = uri
                .as_str()
                .ok_or_else(|| ctx.err(format!("{at}/uri"), "uri must be a string"))?;
            let format = match (declared, list) {
                (Some(f), _) => f,
                (None, List::Ies) => Format::Ies,
                (None, List::Luxbake) => format_of_uri(uri).ok_or_else(|| {
                    ctx.err(
                        at,
                        format!(
                            "cannot tell the format of '{}': give a mimeType \
                             (application/x-ies-lm-63 or application/x-eulumdat) or name the \
                             file *.ies or *.ldt",
                            shorten(uri)
                        ),
                    )
                })?,
            };
            let bytes = read_uri(ctx, uri, at, "profile")?;
            let label = if uri.starts_with("data:") {
                "data: URI".to_owned()
            } else {
                uri.to_owned()
            };
            (bytes, label, format)
        }
        (None, Some(view)) => {
            let view_at = format!("{at}/bufferView");
            let index = view
                .as_u64()
                .ok_or_else(|| ctx.err(&view_at, "bufferView must be an index (an integer ≥ 0)"))?;
            let view = usize::try_from(index)
                .ok()
                .and_then(|k| doc.views().nth(k))
                .ok_or_else(|| {
                    ctx.err(
                        &view_at,
                        format!(
                            "refers to /bufferViews/{index}, which does not exist (the file has \
                             {} bufferViews)",
                            doc.views().len()
                        ),
                    )
                })?;
            let bytes = view_bytes(buffers, &view)
                .map_err(|m| ctx.err(&view_at, m))?
                .to_vec();
            let format = declared.ok_or_else(|| {
                ctx.err(
                    at,
                    "a profile stored in a bufferView needs a mimeType (application/x-ies-lm-63 \
                     or application/x-eulumdat)",
                )
            })?;
            (bytes, format!("/bufferViews/{index}"), format)
        }
        _ => {
            return Err(ctx.err(at, "a profile must give exactly one of uri and bufferView"));
        }
    };
    Ok(Source {
        pointer: at.to_owned(),
        name,
        label,
        bytes,
        format,
    })
}

/// The format a `mimeType` names; `EXT_lights_ies` allows only IES LM-63.
fn mime_format(mime: &str, list: List) -> Result<Format, String> {
    let format = mime
        .contains('/')
        .then(|| Format::from_mime_or_extension(mime))
        .flatten();
    match (format, list) {
        (Some(f @ Format::Ies), _) | (Some(f @ Format::Eulumdat), List::Luxbake) => Ok(f),
        (Some(Format::Eulumdat), List::Ies) => Err(format!(
            "mimeType '{mime}': EXT_lights_ies carries IES LM-63 files only \
             (application/x-ies-lm-63); put EULUMDAT files in {LUXBAKE_LUMINAIRE}.profiles"
        )),
        (None, List::Ies) => Err(format!(
            "unknown mimeType '{mime}' (EXT_lights_ies allows application/x-ies-lm-63)"
        )),
        (None, List::Luxbake) => Err(format!(
            "unknown mimeType '{mime}' (allowed: application/x-ies-lm-63, \
             application/x-eulumdat)"
        )),
    }
}

/// The format of a URI without mimeType: a `data:` URI's media type, else the file extension.
fn format_of_uri(uri: &str) -> Option<Format> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let media_type = rest.split([',', ';']).next().unwrap_or("");
        return mime_format(media_type.trim(), List::Luxbake).ok();
    }
    let path = uri.split(['?', '#']).next().unwrap_or(uri);
    let extension = Path::new(path).extension()?.to_str()?;
    Format::from_mime_or_extension(extension)
}

/// A URI for a message: data URIs are cut after their header.
fn shorten(uri: &str) -> String {
    match uri.strip_prefix("data:") {
        Some(rest) => format!("data:{},…", rest.split(',').next().unwrap_or("")),
        None => uri.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_from_mime_types_and_uris() {
        assert!(mime_format("application/x-ies-lm-63", List::Ies).is_ok());
        assert!(mime_format("application/x-eulumdat", List::Ies).is_err());
        assert_eq!(
            mime_format("application/x-eulumdat", List::Luxbake),
            Ok(Format::Eulumdat)
        );
        assert!(mime_format("ies", List::Luxbake).is_err());
        assert!(mime_format("text/plain", List::Luxbake).is_err());
        assert_eq!(format_of_uri("a/b.IES"), Some(Format::Ies));
        assert_eq!(format_of_uri("b.ldt"), Some(Format::Eulumdat));
        assert_eq!(format_of_uri("b.txt"), None);
        assert_eq!(
            format_of_uri("data:application/x-eulumdat;base64,AAAA"),
            Some(Format::Eulumdat)
        );
        assert_eq!(format_of_uri("data:,abc"), None);
        assert_eq!(
            shorten("data:text/plain;base64,QUJD"),
            "data:text/plain;base64,…"
        );
    }

    #[test]
    fn counts_map_list_indices() {
        let c = Counts { ies: 2, luxbake: 3 };
        assert_eq!(c.ies_light(1), Some(1));
        assert_eq!(c.ies_light(2), None);
        assert_eq!(c.luxbake_profile(0), Some(2));
        assert_eq!(c.luxbake_profile(3), None);
    }
}
