//! A glTF file opened for reading without making a [`crate::scene::Scene`] of it: parsed and
//! validated, its buffers read (confined to its folder, like every import), its node tree built
//! (names, parents, world transforms, extras), and its triangle primitives readable by attribute
//! name. The reader of finished bakes (`crate::readback`) starts from it, so the `gltf` crate and
//! the checks on what a file may reference stay in this module.
//!
//! Errors name the file and the JSON pointer of the element (`/meshes/0/primitives/1/indices`).

use super::document::{self, Parsed};
use super::nodes::{self, Hierarchy};
use super::{accessor, buffers, mesh};
use crate::import::context::Ctx;
use crate::import::resources::read_uri;
use crate::scene::Node;
use crate::{Error, Result};
use ::gltf::mesh::{Mode, Semantic};
use glam::DVec3;
use serde_json::Value;
use std::path::{Path, PathBuf};

pub struct GltfFile {
    ctx: Ctx,
    doc: ::gltf::Document,
    raw: Value,
    buffers: Vec<Vec<u8>>,
    hierarchy: Hierarchy,
}

/// One primitive of a mesh of the file.
pub struct Primitive<'f> {
    file: &'f GltfFile,
    prim: ::gltf::Primitive<'f>,
    /// Its JSON pointer (`/meshes/0/primitives/1`).
    pub at: String,
}

impl GltfFile {
    /// Open `path` (`.gltf` or `.glb`, checked by the caller).
    pub(crate) fn open(path: &Path) -> Result<Self> {
        let ctx = Ctx::new(path)?;
        let bytes = ctx.read_input()?;
        Self::parse(ctx, &bytes)
    }

    /// A glTF or GLB document held in memory, named `name` in messages (it may reference no
    /// file: a GLB's binary chunk and `data:` URIs only).
    pub fn from_bytes(name: &Path, bytes: &[u8]) -> Result<Self> {
        Self::parse(Ctx::in_memory(name), bytes)
    }

    fn parse(mut ctx: Ctx, bytes: &[u8]) -> Result<Self> {
        let Parsed { doc, raw, bin } = document::parse(&mut ctx, bytes)?;
        let buffers = buffers::load_buffers(&mut ctx, &doc, bin.as_deref())?;
        let hierarchy = nodes::build(&ctx, &doc, &raw)?;
        Ok(GltfFile {
            ctx,
            doc,
            raw,
            buffers,
            hierarchy,
        })
    }

    /// An error at `at` (a JSON pointer) in this file.
    pub(crate) fn err(&self, at: impl Into<String>, message: impl Into<String>) -> Error {
        self.ctx.err(at, message)
    }

    pub(crate) fn path(&self) -> &Path {
        &self.ctx.file
    }

    /// The files read so far besides this one (canonical paths, each once).
    pub(crate) fn resources_read(&self) -> &[PathBuf] {
        &self.ctx.input_files
    }

    /// The bytes a `uri` of the element at `at` refers to (`data:` or a file inside the file's
    /// folder, as every import reads them); `what` names it in messages.
    pub(crate) fn resource(&mut self, uri: &str, at: &str, what: &str) -> Result<Vec<u8>> {
        read_uri(&mut self.ctx, uri, at, what)
    }

    /// The whole JSON document.
    pub(crate) fn json(&self) -> &Value {
        &self.raw
    }

    /// Every node, by glTF index (names, children, transforms and extras; no surfaces).
    pub fn nodes(&self) -> &[Node] {
        &self.hierarchy.nodes
    }

    /// The root nodes of the file's scene.
    pub(crate) fn roots(&self) -> &[usize] {
        &self.hierarchy.roots
    }

    /// The nodes of the file's scene, in index order.
    pub(crate) fn scene_nodes(&self) -> Vec<usize> {
        let mut order = self.hierarchy.reachable.clone();
        order.sort_unstable();
        order
    }

    /// The scene's extras.
    pub(crate) fn scene_extras(&self) -> Option<&Value> {
        self.hierarchy.extras.as_ref()
    }

    /// Every material's name, by index.
    pub(crate) fn material_names(&self) -> Vec<Option<String>> {
        self.doc
            .materials()
            .map(|m| m.name().map(str::to_owned))
            .collect()
    }

    /// The primitives of node `i`'s mesh (none without a mesh).
    pub fn primitives(&self, i: usize) -> Vec<Primitive<'_>> {
        let Some(mesh) = self.doc.nodes().nth(i).and_then(|n| n.mesh()) else {
            return Vec::new();
        };
        mesh.primitives()
            .map(|prim| Primitive {
                file: self,
                at: format!("/meshes/{}/primitives/{}", mesh.index(), prim.index()),
                prim,
            })
            .collect()
    }
}

impl Primitive<'_> {
    /// Made of triangles (a list, strip or fan).
    pub(crate) fn is_triangles(&self) -> bool {
        matches!(
            self.prim.mode(),
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        )
    }

    /// The accessor of an attribute named as in the file (`POSITION`, `TEXCOORD_1`, `COLOR_0`,
    /// `_ILLUMINANCE`).
    fn attribute(&self, name: &str) -> Option<::gltf::Accessor<'_>> {
        let semantic = match name {
            "POSITION" => Semantic::Positions,
            _ if name.starts_with("TEXCOORD_") => Semantic::TexCoords(name[9..].parse().ok()?),
            _ if name.starts_with("COLOR_") => Semantic::Colors(name[6..].parse().ok()?),
            custom => Semantic::Extras(custom.strip_prefix('_')?.into()),
        };
        self.prim.get(&semantic)
    }

    pub(crate) fn has(&self, name: &str) -> bool {
        self.attribute(name).is_some()
    }

    /// The vertex count (of `POSITION`).
    pub(crate) fn vertex_count(&self) -> Result<usize> {
        self.attribute("POSITION")
            .map(|a| a.count())
            .ok_or_else(|| {
                self.file.err(
                    format!("{}/attributes", self.at),
                    "primitive has no POSITION",
                )
            })
    }

    /// Attribute `name` as `components` numbers per vertex (an error when it is missing or does
    /// not have one element per vertex).
    pub fn read(&self, name: &str, components: usize) -> Result<Vec<f64>> {
        let at = format!("{}/attributes/{name}", self.at);
        let count = self.vertex_count()?;
        let a = self
            .attribute(name)
            .ok_or_else(|| self.file.err(&at, "missing"))?;
        if a.count() != count {
            return Err(self
                .file
                .err(&at, format!("{} values for {count} vertices", a.count())));
        }
        accessor::read(&self.file.ctx, &self.file.buffers, &a, components, &at)
    }

    /// `POSITION` (m, in the node's local space).
    pub fn positions(&self) -> Result<Vec<DVec3>> {
        let raw = self.read("POSITION", 3)?;
        Ok(raw
            .chunks_exact(3)
            .map(|q| DVec3::new(q[0], q[1], q[2]))
            .collect())
    }

    /// The triangles as the file winds them (indices checked against the vertex count).
    pub fn triangles(&self) -> Result<Vec<[u32; 3]>> {
        let count = self.vertex_count()?;
        let indices: Vec<u32> = match self.prim.indices() {
            Some(a) => {
                let at = format!("{}/indices", self.at);
                let v = accessor::read_indices(&self.file.ctx, &self.file.buffers, &a, &at)?;
                if v.iter().any(|&i| i as usize >= count) {
                    return Err(self
                        .file
                        .err(at, format!("an index is ≥ the {count} vertices")));
                }
                v
            }
            None => (0..count as u32).collect(),
        };
        Ok(mesh::assemble(self.prim.mode(), &indices))
    }

    /// Its material's index.
    pub(crate) fn material(&self) -> Option<usize> {
        self.prim.material().index()
    }
}
