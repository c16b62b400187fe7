//! glTF textures and samplers → [`Texture`]s and [`Sampler`]s (same indices as the file).
//!
//! Inputs: the validated document and its raw JSON. Outputs: textures pointing at images and
//! samplers; sampler fields keep the raw glTF numbers, `None` when the file leaves them unset.
//! Invariant: every index is valid (the document was validated).

use super::raw;
use crate::scene::{Sampler, Texture};
use serde_json::Value;

pub(super) fn textures(doc: &::gltf::Document) -> Vec<Texture> {
    doc.textures()
        .map(|t| Texture {
            name: t.name().map(str::to_owned),
            image: t.source().index(),
            sampler: t.sampler().index(),
        })
        .collect()
}

pub(super) fn samplers(doc: &::gltf::Document, raw: &Value) -> Vec<Sampler> {
    (0..doc.samplers().len())
        .map(|i| {
            let field =
                |name: &str| raw::number(raw, &format!("/samplers/{i}/{name}")).map(|v| v as u32);
            Sampler {
                mag_filter: field("magFilter"),
                min_filter: field("minFilter"),
                wrap_s: field("wrapS"),
                wrap_t: field("wrapT"),
            }
        })
        .collect()
}
