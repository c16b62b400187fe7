//! Packing a [`Document`] into file bytes: `.gltf` JSON (+ the `.bin` side buffer) or `.glb`.
//!
//! Input: the document and, for `.gltf`, the side buffer's URI. Output: the bytes of each file.
//! Invariants: `buffers` has one entry when there is binary data and is absent otherwise; `.gltf`
//! JSON is pretty-printed with a final newline; a GLB is header + JSON chunk (space-padded to 4
//! bytes) + BIN chunk (zero-padded, only with binary data), all lengths little-endian u32.

use super::document::Document;
use crate::{Error, Result};
use serde_json::{Value, json};
use std::path::Path;

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const GLB_VERSION: u32 = 2;
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"

/// The `.gltf` file's bytes; the buffer (if any) points at `bin_uri`.
pub(crate) fn gltf(doc: &Document, bin_uri: &str) -> Vec<u8> {
    let mut root = doc.root.clone();
    if !doc.bin.is_empty() {
        root.insert(
            "buffers".into(),
            json!([{ "byteLength": doc.bin.len(), "uri": bin_uri }]),
        );
    }
    let mut bytes =
        serde_json::to_vec_pretty(&Value::Object(root)).expect("JSON values always serialise");
    bytes.push(b'\n');
    bytes
}

/// The `.glb` file's bytes; `path` names the file in errors.
pub(crate) fn glb(doc: &Document, path: &Path) -> Result<Vec<u8>> {
    let mut root = doc.root.clone();
    if !doc.bin.is_empty() {
        root.insert("buffers".into(), json!([{ "byteLength": doc.bin.len() }]));
    }
    let mut json = serde_json::to_vec(&Value::Object(root)).expect("JSON values always serialise");
    json.resize(json.len().next_multiple_of(4), b' ');
    let mut bin = doc.bin.clone();
    bin.resize(bin.len().next_multiple_of(4), 0);

    let mut total = 12 + 8 + json.len();
    if !bin.is_empty() {
        total += 8 + bin.len();
    }
    let too_big = || Error::output(path, "output exceeds the 4 GiB limit of a GLB file");
    let total32 = u32::try_from(total).map_err(|_| too_big())?;

    let mut out = Vec::with_capacity(total);
    for word in [GLB_MAGIC, GLB_VERSION, total32] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    for (kind, data) in [(CHUNK_JSON, &json), (CHUNK_BIN, &bin)] {
        if data.is_empty() {
            continue;
        }
        let len = u32::try_from(data.len()).map_err(|_| too_big())?;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(data);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::Map;

    #[test]
    fn glb_layout() {
        let mut root = Map::new();
        root.insert("asset".into(), json!({"version": "2.0"}));
        let doc = Document {
            root,
            bin: vec![1, 2, 3, 4],
        };
        let glb = glb(&doc, Path::new("x.glb")).unwrap();
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(glb.len() % 4, 0);
        let total = u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize;
        assert_eq!(total, glb.len());
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        assert_eq!(&glb[16..20], b"JSON");
        assert_eq!(&glb[20 + json_len + 4..20 + json_len + 8], b"BIN\0");
        assert_eq!(&glb[glb.len() - 4..], &[1, 2, 3, 4]);
    }
}
