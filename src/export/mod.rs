//! Exporters: the baked scene as glTF 2.0 (`.gltf` + `.bin`, or `.glb`); [`write_scene`] writes
//! an unbaked scene (one built in code) the same way, as an input.
//!
//! Input: the [`Scene`], its [`BakeResult`] and [`ExportOptions`]. Output: the file(s) at the
//! requested path: `<stem>.<hash>.bin` beside a `.gltf`, and with lightmaps one EXR file per
//! atlas beside it (`<stem>.lightmap<k>.<hash>.exr`; `<hash>`: 16 hex digits of the file's
//! bytes). Invariants: the output is byte-deterministic (same inputs, same bytes and names);
//! every check runs before anything is written ([`check_run`]: unknown extension, missing or
//! unwritable folder, a directory, an output that would replace an input or another output);
//! every file is staged in one [`atomic::Batch`], then renamed: the side files first (new names,
//! so the old set's files are untouched), the `.gltf`/`.glb` last: that rename is the commit
//! point, so a kill at any instant leaves the old set or the new one; the old set's side files
//! are removed after it ([`Staged::commit`]). Layout of the output (one concern per module):
//! [`target`] (paths, checks and cleanup), [`document`] (the root JSON) built from
//! [`mesh`] (+ [`geometry`], [`buffer`]), [`material`], [`nodes`], [`luminaires`] (profiles and
//! luminaire extensions), [`probes`] (probe nodes and their results, + [`glyphs`]),
//! [`lightmaps`] (display textures, + [`display`]; EXR files, [`exr`]; material variants,
//! [`lightmap_material`]) and [`extras`], packed by [`container`] and written by [`atomic`].

pub mod atomic;
mod buffer;
mod container;
pub mod display;
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
mod openings;
mod probes;
pub mod summary;
mod target;

pub use exr::{ViewImage, ascii_json, encode_view};
pub use glyphs::scale as glyph_scale;
pub use target::content_hash;

use crate::{Error, Result, result::BakeResult, scene::Scene};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
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

/// The files `scene` was read from (its source file and every file the import read).
fn scene_inputs(scene: &Scene) -> Vec<&Path> {
    let source = Some(scene.source_file.as_path()).filter(|p| !p.as_os_str().is_empty());
    scene
        .input_files
        .iter()
        .map(PathBuf::as_path)
        .chain(source)
        .collect()
}

/// Check, before any work, that `path` is a writable output for `scene`: a `.gltf` or `.glb`
/// name in an existing folder that would not replace any file the import read (nor would any
/// side file it may get). `extra` are other files the caller will write (e.g. a summary);
/// they are checked the same way and may not coincide with the output files.
pub fn check(path: &Path, scene: &Scene, extra: &[&Path]) -> Result<()> {
    check_run(path, scene, &[], extra)
}

/// [`check`] with `inputs`: files the run reads besides the scene's (targets, a probe CSV).
pub fn check_run(path: &Path, scene: &Scene, inputs: &[&Path], extra: &[&Path]) -> Result<()> {
    let target = Target::for_path(path)?;
    let mut all = scene_inputs(scene);
    all.extend_from_slice(inputs);
    target::check_paths(&all, Some(&target), extra)
}

/// Check outputs that are not a scene (e.g. a polar curve's SVG) against the run's `inputs`
/// and each other, as [`check`] does.
pub fn check_files(inputs: &[&Path], outputs: &[&Path]) -> Result<()> {
    target::check_paths(inputs, None, outputs)
}

/// Write `scene` with the baked `result` to `path` (`.gltf` or `.glb`, by extension), atomically.
pub fn write(
    path: &Path,
    scene: &Scene,
    result: &BakeResult,
    options: &ExportOptions,
) -> Result<()> {
    let mut batch = atomic::Batch::default();
    let prepared = Prepared::staged(path, scene, result, options, &mut batch)?;
    prepared.stage(scene, &mut batch)?.commit(batch, &[])
}

/// An output built and checked but not yet written: it can be read back first (the bake's
/// report is made from the very bytes it writes).
pub struct Prepared<'p> {
    path: &'p Path,
    target: Target,
    doc: document::Document,
    result: &'p BakeResult,
    /// The lightmaps' EXR file names, when staged.
    staged: Vec<String>,
}

impl<'p> Prepared<'p> {
    /// The output in memory only, to be read back: nothing is staged and the lightmaps' URIs
    /// are `<stem>.lightmap<k>.exr` without a hash.
    pub(crate) fn new(
        path: &'p Path,
        scene: &Scene,
        result: &'p BakeResult,
        options: &ExportOptions,
    ) -> Result<Self> {
        let target = Target::for_path(path)?;
        let atlases = result.lightmaps.as_ref().map_or(0, |l| l.atlases.len());
        let uris: Vec<String> = (0..atlases)
            .map(|k| target.unstaged_lightmap_uri(k))
            .collect();
        Ok(Prepared {
            path,
            doc: document::build(scene, result, options, &uris)?,
            target,
            result,
            staged: Vec::new(),
        })
    }

    /// The output to be written: checks `path` against the scene's files, then encodes and
    /// stages the lightmaps' EXR files in `batch` (one at a time; their names carry a hash of
    /// their bytes) and builds the document that references them.
    pub fn staged(
        path: &'p Path,
        scene: &Scene,
        result: &'p BakeResult,
        options: &ExportOptions,
        batch: &mut atomic::Batch,
    ) -> Result<Self> {
        let target = Target::for_path(path)?;
        target::check_paths(&scene_inputs(scene), Some(&target), &[])?;
        let mut uris = Vec::new();
        let mut staged = Vec::new();
        if let Some(l) = &result.lightmaps {
            for (k, atlas) in l.atlases.iter().enumerate() {
                let header = lightmaps::exr_header(k, l, &result.summary);
                let bytes = exr::encode(atlas, &header)
                    .map_err(|m| Error::output(target.lightmap(k, b"").0, m))?;
                let (file, uri) = target.lightmap(k, &bytes);
                batch.stage(&file, &bytes)?;
                staged.push(name_of(&file));
                uris.push(uri);
            }
        }
        Ok(Prepared {
            path,
            doc: document::build(scene, result, options, &uris)?,
            target,
            result,
            staged,
        })
    }

    /// The atlases the EXR files will be written from (`None` without lightmaps).
    pub(crate) fn lightmaps(&self) -> Option<&crate::result::Lightmaps> {
        self.result.lightmaps.as_ref()
    }

    /// The output as one `.glb` file's bytes (the same document whatever the output's format).
    pub(crate) fn glb(&self) -> Result<Vec<u8>> {
        container::glb(&self.doc, self.path)
    }

    /// Stage the `.bin` and the `.gltf`/`.glb` (after the lightmaps, so it is renamed last of
    /// the set); other files staged in `batch` after it are renamed after it.
    pub fn stage(self, scene: &Scene, batch: &mut atomic::Batch) -> Result<Staged> {
        let mut new: BTreeSet<String> = self.staged.into_iter().collect();
        stage_doc(self.path, &self.target, &self.doc, batch, &mut new)?;
        Ok(Staged {
            old: self.target.old_references(),
            target: self.target,
            new,
            keep: scene_inputs(scene)
                .iter()
                .map(|p| p.to_path_buf())
                .collect(),
        })
    }
}

/// A glTF set staged in a [`atomic::Batch`], to be committed with it.
#[derive(Debug)]
pub struct Staged {
    target: Target,
    /// Side files the output referenced before this run, and references now.
    old: BTreeSet<String>,
    new: BTreeSet<String>,
    /// Files never removed by the cleanup (the inputs).
    keep: Vec<PathBuf>,
}

impl Staged {
    /// Rename everything staged in `batch` (the glTF set's commit point is its main file's
    /// rename), then remove the old set's side files the new one does not use, side files and
    /// temporaries that killed runs left beside it, and temporaries of killed runs in the
    /// folders of `others` (the other outputs).
    pub fn commit(self, batch: atomic::Batch, others: &[&Path]) -> Result<()> {
        batch.commit()?;
        self.target.clean(&self.old, &self.new, &self.keep);
        for other in others {
            atomic::remove_stale_temporaries(&atomic::folder(other));
        }
        Ok(())
    }
}

fn name_of(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Write `scene` unbaked, as an input for a bake (e.g. a scene built in code): POSITION, NORMAL
/// and TEXCOORD_n only (no COLOR_0, no `_ILLUMINANCE*`), the materials as given (PBR, with their
/// `LUXBAKE_material`, not unlit), lights, profiles and luminaires, and the scene's extras without
/// a run summary. The importer reads it back as the same scene.
pub fn write_scene(path: &Path, scene: &Scene) -> Result<()> {
    let target = Target::for_path(path)?;
    target::check_paths(&scene_inputs(scene), Some(&target), &[])?;
    let result = BakeResult::unbaked(scene);
    let options = ExportOptions {
        unlit: false,
        probe_glyphs: None,
    };
    let doc = document::build_input(scene, &result, &options)?;
    let mut batch = atomic::Batch::default();
    let mut new = BTreeSet::new();
    stage_doc(path, &target, &doc, &mut batch, &mut new)?;
    let staged = Staged {
        old: target.old_references(),
        target,
        new,
        keep: scene_inputs(scene)
            .iter()
            .map(|p| p.to_path_buf())
            .collect(),
    };
    staged.commit(batch, &[])
}

/// Stage the `.bin` (a `.gltf` with binary data) and the main file; `names` gets the side
/// file's name.
fn stage_doc(
    path: &Path,
    target: &Target,
    doc: &document::Document,
    batch: &mut atomic::Batch,
    names: &mut BTreeSet<String>,
) -> Result<()> {
    match target.format {
        Format::Glb => batch.stage(&target.main, &container::glb(doc, path)?),
        Format::Gltf => {
            let (bin, uri) = target.bin(&doc.bin);
            if !doc.bin.is_empty() {
                batch.stage(&bin, &doc.bin)?;
                names.insert(name_of(&bin));
            }
            batch.stage(&target.main, &container::gltf(doc, &uri))
        }
    }
}
