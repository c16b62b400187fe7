//! A minimal reader of the glTF the exporter wrote (`.gltf` + side buffer, or `.glb`), enough to
//! check its JSON and decode its float and index accessors. Panics on anything unexpected.

use serde_json::Value;
use std::path::Path;

/// A written glTF: its JSON and its single buffer.
#[derive(Debug, Clone)]
pub struct Gltf {
    pub json: Value,
    pub bin: Vec<u8>,
}

fn u32_at(bytes: &[u8], at: usize) -> usize {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize
}

/// Read `path` (by extension).
pub fn read(path: &Path) -> Gltf {
    let bytes = std::fs::read(path).unwrap();
    if path.extension().is_some_and(|e| e == "glb") {
        assert_eq!(&bytes[0..4], b"glTF");
        assert_eq!(u32_at(&bytes, 8), bytes.len());
        let json_len = u32_at(&bytes, 12);
        assert_eq!(&bytes[16..20], b"JSON");
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let bin_at = 20 + json_len;
        let bin = if bin_at < bytes.len() {
            assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
            bytes[bin_at + 8..bin_at + 8 + u32_at(&bytes, bin_at)].to_vec()
        } else {
            Vec::new()
        };
        Gltf { json, bin }
    } else {
        let json: Value = serde_json::from_slice(&bytes).unwrap();
        let bin = match json["buffers"][0]["uri"].as_str() {
            Some(uri) => std::fs::read(path.with_file_name(uri)).unwrap(),
            None => Vec::new(),
        };
        Gltf { json, bin }
    }
}

impl Gltf {
    fn view_bytes(&self, accessor: usize) -> (&Value, &[u8]) {
        let acc = &self.json["accessors"][accessor];
        let view = &self.json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        assert!(
            view.get("byteStride").is_none(),
            "byteStride must be omitted"
        );
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        assert_eq!(offset % 4, 0, "bufferView not 4-byte aligned");
        let len = view["byteLength"].as_u64().unwrap() as usize;
        (acc, &self.bin[offset..offset + len])
    }

    /// A float accessor's elements (each with 1–4 components).
    pub fn floats(&self, accessor: usize) -> Vec<Vec<f32>> {
        let (acc, bytes) = self.view_bytes(accessor);
        assert_eq!(acc["componentType"], 5126);
        let n = match acc["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            t => panic!("unexpected accessor type {t}"),
        };
        let count = acc["count"].as_u64().unwrap() as usize;
        let values: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        values[..count * n].chunks(n).map(<[f32]>::to_vec).collect()
    }

    /// An index accessor's values (u16 or u32).
    pub fn indices(&self, accessor: usize) -> Vec<u32> {
        let (acc, bytes) = self.view_bytes(accessor);
        let count = acc["count"].as_u64().unwrap() as usize;
        match acc["componentType"].as_u64().unwrap() {
            5123 => bytes
                .chunks_exact(2)
                .take(count)
                .map(|c| u16::from_le_bytes(c.try_into().unwrap()) as u32)
                .collect(),
            5125 => bytes
                .chunks_exact(4)
                .take(count)
                .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
                .collect(),
            t => panic!("unexpected index component type {t}"),
        }
    }
}
