//! Importers: glTF 2.0 (`.gltf`, `.glb`) and OBJ+MTL into the format-neutral [`Scene`].
//! All file-format crates (`gltf`, `tobj`, image decoders, base64; `exr` for reading) are used only
//! below this module.
//!
//! Input: a path and [`ImportOptions`]. Output: a [`Scene`] meeting the invariants documented in
//! `crate::scene`, or an [`crate::Error::Input`] naming the file and the element (a JSON pointer
//! for glTF). Every file read is listed, canonicalised, in `Scene::input_files`; no file outside
//! the input file's folder is ever read. [`GltfFile`] opens a glTF with the same parser and the
//! same confinement without making a scene of it: `crate::readback` reads finished bakes through it,
//! and their lightmap EXR files through [`exr`] (the `exr` crate's only reader).

mod checks;
mod context;
pub mod exr;
pub mod files;
mod geometry;
mod glb;
mod gltf;
mod images;
mod material_values;
mod obj;
mod obj_mtl;
mod resources;

pub use checks::{MAX_COORDINATE, MAX_PHOTOMETRIC};
pub(crate) use glb::{is_glb, parse as parse_glb};
pub use gltf::file::{GltfFile, Primitive as GltfPrimitive};
pub use images::decode_rgb8;

use crate::{Error, Result, scene::Scene};
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

/// Read a scene from `path`, choosing the importer by extension (`.gltf`, `.glb`, `.obj`; case
/// does not matter).
pub fn load(path: &Path, options: &ImportOptions) -> Result<Scene> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let mut scene = match extension.as_deref() {
        Some("gltf" | "glb") => {
            let mut ctx = context::Ctx::new(path)?;
            let bytes = ctx.read_input()?;
            gltf::load(&mut ctx, &bytes)
        }
        Some("obj") => {
            let mut ctx = context::Ctx::new(path)?;
            let bytes = ctx.read_input()?;
            obj::load(&mut ctx, &bytes, options.obj_up)
        }
        _ => Err(Error::input(
            path,
            "",
            "unsupported file type: luxbake reads .gltf, .glb and .obj files",
        )),
    }?;
    checks::finish(&mut scene)?;
    Ok(scene)
}
