//! Where the output goes: the container format chosen by the extension, the side buffer's path,
//! the lightmaps' EXR files (`<stem>.lightmap<k>.exr` beside the output, `.gltf` or `.glb`), and
//! the guard that refuses to overwrite any file the scene was read from.
//!
//! Input: the requested output path and the [`Scene`]'s `source_file` / `input_files`.
//! Output: a [`Target`]. Invariants: the format is decided by the extension alone
//! (case-insensitive `.gltf` / `.glb`, anything else is [`Error::Output`]); every check here runs
//! before anything is written.

use crate::{Error, Result, scene::Scene};
use std::path::{Path, PathBuf};

/// The container format of the output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.gltf` JSON with a `<stem>.bin` side buffer.
    Gltf,
    /// `.glb`: one binary file.
    Glb,
}

/// The resolved output files.
#[derive(Debug, Clone)]
pub struct Target {
    pub format: Format,
    /// The `.gltf` / `.glb` file.
    pub main: PathBuf,
    /// `<stem>.bin` beside a `.gltf` (unused for `.glb`).
    pub bin: PathBuf,
    /// The side buffer's relative URI as written in `buffers[0].uri` (percent-encoded file name).
    pub bin_uri: String,
    /// The output's file stem (`lit` for `lit.gltf`).
    stem: String,
}

impl Target {
    /// Decide the format and the side-file name for `path`.
    pub fn for_path(path: &Path) -> Result<Target> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let format = match ext.as_deref() {
            Some("gltf") => Format::Gltf,
            Some("glb") => Format::Glb,
            _ => {
                return Err(Error::output(
                    path,
                    "unsupported output extension: use .gltf (with a .bin side file) or .glb",
                ));
            }
        };
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .filter(|s| !s.is_empty())
            .ok_or_else(|| Error::output(path, "the output file name must be valid UTF-8"))?;
        let bin_name = format!("{stem}.bin");
        Ok(Target {
            format,
            main: path.to_path_buf(),
            bin: path.with_file_name(&bin_name),
            bin_uri: percent_encode(&bin_name),
            stem: stem.to_string(),
        })
    }

    /// Atlas `k`'s EXR file beside the output, and its relative URI (percent-encoded name).
    pub fn lightmap(&self, k: usize) -> (PathBuf, String) {
        let name = format!("{}.lightmap{k}.exr", self.stem);
        (self.main.with_file_name(&name), percent_encode(&name))
    }

    /// Whether `name` is the name some atlas's EXR file would have.
    fn is_lightmap_name(&self, name: &std::ffi::OsStr) -> bool {
        let Some(rest) = name
            .to_str()
            .and_then(|n| n.strip_prefix(self.stem.as_str()))
            .and_then(|n| n.strip_prefix(".lightmap"))
            .and_then(|n| n.strip_suffix(".exr"))
        else {
            return false;
        };
        !rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit())
    }

    /// The files that will be written when the output has `has_binary` data and `lightmaps`
    /// atlases, in the order they are renamed into place (the main file last).
    pub fn files(&self, has_binary: bool, lightmaps: usize) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = (0..lightmaps).map(|k| self.lightmap(k).0).collect();
        if self.format == Format::Gltf && has_binary {
            files.push(self.bin.clone());
        }
        files.push(self.main.clone());
        files
    }

    /// Refuse (before writing anything) when an output file would replace one of the scene's
    /// input files, or when the output directory does not exist.
    pub fn check_not_input(&self, scene: &Scene, has_binary: bool, lightmaps: usize) -> Result<()> {
        self.check_with(scene, has_binary, Some(lightmaps), &[])
    }

    /// Like [`Target::check_not_input`], also for `extra` files the caller will write (a summary):
    /// none may be an input, a glTF output, or each other, and their folders must exist. With
    /// `lightmaps` unknown (`None`: checked before the bake), no input or extra file may have
    /// the name of any atlas's EXR file.
    pub fn check_with(
        &self,
        scene: &Scene,
        has_binary: bool,
        lightmaps: Option<usize>,
        extra: &[&Path],
    ) -> Result<()> {
        let mut inputs: Vec<PathBuf> = scene.input_files.iter().map(|p| canonical(p)).collect();
        if !scene.source_file.as_os_str().is_empty() {
            inputs.push(canonical(&scene.source_file));
        }
        if lightmaps.is_none() {
            let dir = resolve_output(&self.main)?;
            let dir = dir.parent().unwrap_or(&dir);
            let clash = inputs.iter().cloned().chain(
                extra
                    .iter()
                    .map(|p| resolve_output(p))
                    .collect::<Result<Vec<_>>>()?,
            );
            for file in clash {
                if file.parent() == Some(dir)
                    && file.file_name().is_some_and(|n| self.is_lightmap_name(n))
                {
                    return Err(Error::output(
                        &file,
                        "a lightmap of the output would be written to this file (an input, or \
                         another output); choose another output name",
                    ));
                }
            }
        }
        // The main file first, so a clash is reported on the name the user typed.
        let mut files = self.files(has_binary, lightmaps.unwrap_or(0));
        files.reverse();
        files.extend(extra.iter().map(|p| p.to_path_buf()));
        let mut written: Vec<PathBuf> = Vec::new();
        for file in &files {
            let resolved = resolve_output(file)?;
            if inputs.contains(&resolved) {
                return Err(Error::output(
                    file,
                    "refusing to overwrite an input file of the scene; choose another output name",
                ));
            }
            if written.contains(&resolved) {
                return Err(Error::output(
                    file,
                    "two outputs would be written to the same file; choose another name",
                ));
            }
            written.push(resolved);
        }
        Ok(())
    }
}

/// The canonical path of an input, or the path itself when it cannot be resolved.
fn canonical(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| path.to_path_buf())
}

/// The canonical path an output file will have: the file itself when it exists (following
/// symlinks), otherwise its canonicalised parent joined with its name.
fn resolve_output(path: &Path) -> Result<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Ok(p);
    }
    let name = path
        .file_name()
        .ok_or_else(|| Error::output(path, "not a file name"))?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let dir = parent.canonicalize().map_err(|e| {
        Error::output(
            path,
            format!("output directory {} is not usable: {e}", parent.display()),
        )
    })?;
    Ok(dir.join(name))
}

/// Percent-encode a file name for a relative URI (RFC 3986 unreserved characters kept).
fn percent_encode(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'.' | b'_' | b'~') {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_by_extension() {
        let t = Target::for_path(Path::new("out/room lit.GLTF")).unwrap();
        assert_eq!(t.format, Format::Gltf);
        assert_eq!(t.bin, Path::new("out/room lit.bin"));
        assert_eq!(t.bin_uri, "room%20lit.bin");
        assert_eq!(
            Target::for_path(Path::new("a.glb")).unwrap().format,
            Format::Glb
        );
        for bad in ["a.obj", "a", "a.gltf.tmp"] {
            assert!(matches!(
                Target::for_path(Path::new(bad)),
                Err(Error::Output { .. })
            ));
        }
    }

    #[test]
    fn missing_directory_is_refused() {
        let t = Target::for_path(Path::new("/nonexistent-luxbake-dir/x.glb")).unwrap();
        assert!(t.check_not_input(&Scene::default(), true, 0).is_err());
    }

    #[test]
    fn lightmap_names() {
        let t = Target::for_path(Path::new("out/room lit.glb")).unwrap();
        let (path, uri) = t.lightmap(12);
        assert_eq!(path, Path::new("out/room lit.lightmap12.exr"));
        assert_eq!(uri, "room%20lit.lightmap12.exr");
        for (name, is) in [
            ("room lit.lightmap0.exr", true),
            ("room lit.lightmap.exr", false),
            ("room lit.lightmap1a.exr", false),
            ("room.lightmap0.exr", false),
        ] {
            assert_eq!(t.is_lightmap_name(name.as_ref()), is, "{name}");
        }
    }
}
