//! Fixture builders shared by the import tests: a tiny glTF writer (one binary buffer, written
//! as an external `.bin`, a `data:` URI or a `.glb`) and small geometry/assertion helpers.
#![allow(dead_code)]

pub mod luminaires;

use glam::DVec3;
use luxbake::import::{ImportOptions, load};
use luxbake::scene::Scene;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

pub const FLOAT: u32 = 5126;
pub const UNSIGNED_SHORT: u32 = 5123;

/// How the binary buffer is stored.
pub enum Bin<'a> {
    External(&'a str),
    DataUri,
}

pub struct Builder {
    pub bin: Vec<u8>,
    pub json: Value,
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

impl Builder {
    pub fn new() -> Self {
        Builder {
            bin: Vec::new(),
            json: json!({
                "asset": {"version": "2.0"},
                "buffers": [],
                "bufferViews": [],
                "accessors": [],
                "meshes": [],
                "nodes": [],
            }),
        }
    }

    fn push(&mut self, key: &str, value: Value) -> usize {
        let array = self.json[key].as_array_mut().unwrap();
        array.push(value);
        array.len() - 1
    }

    /// Append raw bytes as a bufferView; returns its index.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.push(
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}),
        )
    }

    pub fn accessor(&mut self, value: Value) -> usize {
        self.push("accessors", value)
    }

    /// A float accessor of `ty` ("VEC3", "VEC2", ...) holding `data`.
    pub fn floats(&mut self, data: &[f32], ty: &str, components: usize) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({
            "bufferView": view, "componentType": FLOAT,
            "count": data.len() / components, "type": ty
        }))
    }

    /// A VEC3 float accessor with `min` and `max` (required for POSITION).
    pub fn vec3s(&mut self, data: &[[f32; 3]]) -> usize {
        let flat: Vec<f32> = data.iter().flatten().copied().collect();
        let accessor = self.floats(&flat, "VEC3", 3);
        let bound = |f: fn(f32, f32) -> f32| -> Vec<f32> {
            (0..3)
                .map(|c| data.iter().map(|v| v[c]).fold(data[0][c], f))
                .collect()
        };
        self.json["accessors"][accessor]["min"] = json!(bound(f32::min));
        self.json["accessors"][accessor]["max"] = json!(bound(f32::max));
        accessor
    }

    pub fn indices(&mut self, data: &[u16]) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({
            "bufferView": view, "componentType": UNSIGNED_SHORT,
            "count": data.len(), "type": "SCALAR"
        }))
    }

    pub fn mesh(&mut self, primitives: Vec<Value>) -> usize {
        self.push("meshes", json!({ "primitives": primitives }))
    }

    /// A mesh with one primitive of `positions` (and optional indices, mode, material).
    pub fn simple_mesh(
        &mut self,
        positions: &[[f32; 3]],
        indices: Option<&[u16]>,
        mode: Option<u32>,
        material: Option<usize>,
    ) -> usize {
        let position = self.vec3s(positions);
        let mut primitive = json!({"attributes": {"POSITION": position}});
        if let Some(indices) = indices {
            primitive["indices"] = json!(self.indices(indices));
        }
        if let Some(mode) = mode {
            primitive["mode"] = json!(mode);
        }
        if let Some(material) = material {
            primitive["material"] = json!(material);
        }
        self.mesh(vec![primitive])
    }

    pub fn node(&mut self, node: Value) -> usize {
        self.push("nodes", node)
    }

    pub fn material(&mut self, material: Value) -> usize {
        if self.json.get("materials").is_none() {
            self.json["materials"] = json!([]);
        }
        self.push("materials", material)
    }

    pub fn set(&mut self, key: &str, value: Value) {
        self.json[key] = value;
    }

    pub fn finished_json(&self, uri: Option<String>) -> Value {
        let mut json = self.json.clone();
        if !self.bin.is_empty() {
            let mut buffer = json!({"byteLength": self.bin.len()});
            if let Some(uri) = uri {
                buffer["uri"] = json!(uri);
            }
            json["buffers"] = json!([buffer]);
        }
        json
    }

    /// Write `name` (a .gltf) into `dir`, storing the buffer as `bin` says.
    pub fn write_gltf(&self, dir: &Path, name: &str, bin: Bin) -> PathBuf {
        let uri = match bin {
            Bin::External(file) => {
                std::fs::write(dir.join(file), &self.bin).unwrap();
                file.to_owned()
            }
            Bin::DataUri => format!(
                "data:application/octet-stream;base64,{}",
                base64_encode(&self.bin)
            ),
        };
        let path = dir.join(name);
        let json = self.finished_json(Some(uri));
        std::fs::write(&path, serde_json::to_vec_pretty(&json).unwrap()).unwrap();
        path
    }

    /// Write `name` as a binary .glb into `dir`.
    pub fn write_glb(&self, dir: &Path, name: &str) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, self.glb_bytes()).unwrap();
        path
    }

    pub fn glb_bytes(&self) -> Vec<u8> {
        glb_from(&self.finished_json(None), &self.bin)
    }
}

/// A GLB container holding `json` and (if not empty) `bin`.
pub fn glb_from(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(json).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}

/// Standard base64 with padding (tests must not depend on the crate's internals).
pub fn base64_encode(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The unit normal of a world-space triangle from its winding.
pub fn geometric_normal(positions: &[DVec3], t: [u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    (b - a).cross(c - a).normalize()
}

pub fn assert_close(actual: DVec3, expected: DVec3, what: &str) {
    assert!(
        (actual - expected).abs().max_element() < 1e-6,
        "{what}: got {actual}, expected {expected}"
    );
}

pub fn assert_near(actual: f64, expected: f64, what: &str) {
    assert!(
        (actual - expected).abs() < 1e-6 * expected.abs().max(1.0),
        "{what}: got {actual}, expected {expected}"
    );
}

/// A PNG of `w × h` texels from `f(x, y) -> [r, g, b]` (8-bit sRGB).
pub fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> Vec<u8> {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    bytes
}

pub const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

pub fn load_ok(path: &Path) -> Scene {
    load(path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Load expecting an input error; returns (JSON pointer, full message).
pub fn load_err(path: &Path) -> (String, String) {
    match load(path, &ImportOptions::default()) {
        Err(e @ luxbake::Error::Input { .. }) => {
            let shown = e.to_string();
            let luxbake::Error::Input { at, .. } = e else {
                unreachable!()
            };
            (at, shown)
        }
        Err(e) => panic!("unexpected error kind: {e}"),
        Ok(_) => panic!("{} loaded but should have failed", path.display()),
    }
}

/// A one-node scene with a single triangle mesh.
pub fn triangle_builder() -> Builder {
    let mut b = Builder::new();
    let mesh = b.simple_mesh(&TRIANGLE, None, None, None);
    b.node(json!({"mesh": mesh}));
    b.set("scenes", json!([{"nodes": [0]}]));
    b
}
