//! Importers: glTF 2.0 (`.gltf`, `.glb`) and OBJ+MTL into the format-neutral [`Scene`].
//! All file-format crates (`gltf`, `tobj`, image decoders) are used only below this module.

use crate::{Result, scene::Scene};
use std::path::Path;

/// Which input axis is "up" in an OBJ file (glTF is always +Y up).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UpAxis {
    #[default]
    Y,
    Z,
}

/// Options for importing.
#[derive(Debug, Clone, Copy, Default)]
pub struct ImportOptions {
    /// Up axis of OBJ files (ignored for glTF).
    pub obj_up: UpAxis,
}

/// Read a scene from `path`, choosing the importer by extension (`.gltf`, `.glb`, `.obj`).
pub fn load(path: &Path, options: &ImportOptions) -> Result<Scene> {
    let _ = (path, options);
    todo!("import::load")
}
