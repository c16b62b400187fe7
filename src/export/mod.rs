//! Exporters: the baked scene as glTF 2.0 (`.gltf` + `.bin`, or `.glb`).

use crate::{Result, result::BakeResult, scene::Scene};
use std::path::Path;

/// Options for writing the output.
#[derive(Debug, Clone, Copy)]
pub struct ExportOptions {
    /// Switch every material to `KHR_materials_unlit` (default), so any viewer shows the bake.
    pub unlit: bool,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions { unlit: true }
    }
}

/// Write `scene` with the baked `result` to `path` (`.gltf` or `.glb`, by extension), atomically.
pub fn write(
    path: &Path,
    scene: &Scene,
    result: &BakeResult,
    options: &ExportOptions,
) -> Result<()> {
    let _ = (path, scene, result, options);
    todo!("export::write")
}
