//! Exporters: the baked scene as glTF 2.0 (`.gltf` + `.bin`, or `.glb`); [`write_scene`] writes
//! an unbaked scene (one built in code) the same way, as an input.
//!
//! Input: the [`Scene`], its [`BakeResult`] and [`ExportOptions`]. Output: the file(s) at the
//! requested path, and with lightmaps one EXR file per atlas beside it
//! (`<stem>.lightmap<k>.exr`). Invariants: the output is byte-deterministic (same inputs, same
//! bytes); it is written atomically (every file staged first, then renamed: the EXR files, the
//! `.bin`, the `.gltf`/`.glb` last), and nothing is written when any check fails (unknown
//! extension, missing directory, an output that would replace an input file, inconsistent bake
//! results). Layout of the output (one concern per module):
//! [`target`] (paths and the input-overwrite guard), [`document`] (the root JSON) built from
//! [`mesh`] (+ [`geometry`], [`buffer`]), [`material`], [`nodes`], [`luminaires`] (profiles and
//! luminaire extensions), [`probes`] (probe nodes and their results, + [`glyphs`]),
//! [`lightmaps`] (display textures, + [`display`]; EXR files, [`exr`]; material variants,
//! [`lightmap_material`]) and [`extras`], packed by [`container`] and written by [`atomic`].

pub mod atomic;
mod buffer;
mod container;
mod display;
mod document;
mod exr;
mod extras;
pub(crate) mod geometry;
mod glyphs;
mod lightmap_material;
mod lightmaps;
mod luminaires;
mod material;
mod mesh;
mod nodes;
mod probes;
pub mod summary;
mod target;

pub use glyphs::scale as glyph_scale;

use crate::{Error, Result, result::BakeResult, scene::Scene};
use std::path::Path;
use target::{Format, Target};

/// Options for writing the output.
#[derive(Debug, Clone, Copy)]
pub struct ExportOptions {
    /// Switch every material to `KHR_materials_unlit` (default), so any viewer shows the bake.
    pub unlit: bool,
    /// Add a glyph mesh per probe at this scale s (m; see [`glyph_scale`]); `None`: no glyphs.
    pub probe_glyphs: Option<f64>,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            unlit: true,
            probe_glyphs: None,
        }
    }
}

/// Check, before any work, that `path` is a writable output for `scene`: a `.gltf` or `.glb`
/// name in an existing folder that would not replace any file the import read (nor would any
/// lightmap EXR file it may get). `extra` are other files the caller will write (e.g. a
/// summary); they are checked the same way and may not coincide with the output files.
pub fn check(path: &Path, scene: &Scene, extra: &[&Path]) -> Result<()> {
    let target = Target::for_path(path)?;
    target.check_with(scene, true, None, extra)
}

/// Write `scene` with the baked `result` to `path` (`.gltf` or `.glb`, by extension), atomically.
pub fn write(
    path: &Path,
    scene: &Scene,
    result: &BakeResult,
    options: &ExportOptions,
) -> Result<()> {
    Prepared::new(path, scene, result, options)?.write(scene)
}

/// An output built and checked but not yet written: it can be read back first (the bake's
/// report is made from the very bytes it writes).
pub struct Prepared<'p> {
    path: &'p Path,
    target: Target,
    doc: document::Document,
    result: &'p BakeResult,
}

impl<'p> Prepared<'p> {
    pub fn new(
        path: &'p Path,
        scene: &Scene,
        result: &'p BakeResult,
        options: &ExportOptions,
    ) -> Result<Self> {
        let target = Target::for_path(path)?;
        let atlases = result.lightmaps.as_ref().map_or(0, |l| l.atlases.len());
        let uris: Vec<String> = (0..atlases).map(|k| target.lightmap(k).1).collect();
        Ok(Prepared {
            path,
            doc: document::build(scene, result, options, &uris)?,
            target,
            result,
        })
    }

    /// The atlases the EXR files will be written from (`None` without lightmaps).
    pub fn lightmaps(&self) -> Option<&crate::result::Lightmaps> {
        self.result.lightmaps.as_ref()
    }

    /// The output as one `.glb` file's bytes (the same document whatever the output's format).
    pub fn glb(&self) -> Result<Vec<u8>> {
        container::glb(&self.doc, self.path)
    }

    /// Write the output files (the EXR files are encoded here, one at a time).
    pub fn write(self, scene: &Scene) -> Result<()> {
        write_doc(self.path, self.target, scene, &self.doc, Some(self.result))
    }
}

/// Write `scene` unbaked, as an input for a bake (e.g. a scene built in code): POSITION, NORMAL
/// and TEXCOORD_n only (no COLOR_0, no `_ILLUMINANCE*`), the materials as given (PBR, with their
/// `LUXBAKE_material`, not unlit), lights, profiles and luminaires, and the scene's extras without
/// a run summary. The importer reads it back as the same scene.
pub fn write_scene(path: &Path, scene: &Scene) -> Result<()> {
    let target = Target::for_path(path)?;
    let result = BakeResult::unbaked(scene);
    let options = ExportOptions {
        unlit: false,
        probe_glyphs: None,
    };
    let doc = document::build_input(scene, &result, &options)?;
    write_doc(path, target, scene, &doc, None)
}

/// Stage every file (the lightmaps of `baked`, if any, first), then rename them all.
fn write_doc(
    path: &Path,
    target: Target,
    scene: &Scene,
    doc: &document::Document,
    baked: Option<&BakeResult>,
) -> Result<()> {
    let has_binary = !doc.bin.is_empty();
    let lightmaps = baked.and_then(|b| b.lightmaps.as_ref().map(|l| (l, &b.summary)));
    let atlases = lightmaps.map_or(0, |(l, _)| l.atlases.len());
    target.check_not_input(scene, has_binary, atlases)?;
    let mut batch = atomic::Batch::default();
    if let Some((l, summary)) = lightmaps {
        for (k, atlas) in l.atlases.iter().enumerate() {
            let file = target.lightmap(k).0;
            let header = lightmaps::exr_header(k, l, summary);
            let bytes = exr::encode(atlas, &header).map_err(|m| Error::output(&file, m))?;
            batch.stage(&file, &bytes)?;
        }
    }
    match target.format {
        Format::Glb => batch.stage(&target.main, &container::glb(doc, path)?)?,
        Format::Gltf => {
            if has_binary {
                batch.stage(&target.bin, &doc.bin)?;
            }
            batch.stage(&target.main, &container::gltf(doc, &target.bin_uri))?;
        }
    }
    batch.commit()
}
