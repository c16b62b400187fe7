//! Where the output goes and what a run may write: the container format chosen by the
//! extension; the side files' names (`<stem>.<hash>.bin` beside a `.gltf`, the lightmaps'
//! `<stem>.lightmap<k>.<hash>.exr` beside a `.gltf` or `.glb`, `<hash>` 16 hex digits of the
//! file's content); the checks run before any work on every output path of a run; and the
//! cleanup after a commit.
//!
//! Input: the requested output path, the run's input files and its other outputs. Output: a
//! [`Target`]. Invariants: the format is decided by the extension alone (case-insensitive
//! `.gltf` / `.glb`, anything else is [`Error::Output`]); [`check_paths`] runs before anything
//! is written; a side file's name is a function of its bytes, so staging the new set never
//! touches a file of the old set (same name, same bytes) and the `.gltf`/`.glb` rename is the
//! commit point of the set; cleanup removes only side-file names of this output's stem that no
//! `<stem>.gltf`/`<stem>.glb` in the folder references, and never an input of the run.

use super::atomic;
use crate::{Error, Result};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The container format of the output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.gltf` JSON with a `<stem>.<hash>.bin` side buffer.
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
    /// The output's file stem (`lit` for `lit.gltf`).
    stem: String,
}

/// A side file's name pattern.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    /// `<stem>.<hash>.bin`, `<stem>.lightmap<k>.<hash>.exr`.
    Hashed,
    /// The names before content hashes: `<stem>.bin`, `<stem>.lightmap<k>.exr`.
    Legacy,
}

impl Target {
    /// Decide the format for `path`.
    pub(crate) fn for_path(path: &Path) -> Result<Target> {
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
        Ok(Target {
            format,
            main: path.to_path_buf(),
            stem: stem.to_string(),
        })
    }

    /// The side buffer holding `bytes` beside a `.gltf`, and its relative URI.
    pub(crate) fn bin(&self, bytes: &[u8]) -> (PathBuf, String) {
        self.side(format!("{}.{:016x}.bin", self.stem, content_hash(bytes)))
    }

    /// Atlas `k`'s EXR file holding `bytes`, and its relative URI.
    pub(crate) fn lightmap(&self, k: usize, bytes: &[u8]) -> (PathBuf, String) {
        let hash = content_hash(bytes);
        self.side(format!("{}.lightmap{k}.{hash:016x}.exr", self.stem))
    }

    /// Atlas `k`'s URI in an output only read back, never written (no hash).
    pub(crate) fn unstaged_lightmap_uri(&self, k: usize) -> String {
        percent_encode(&format!("{}.lightmap{k}.exr", self.stem))
    }

    fn side(&self, name: String) -> (PathBuf, String) {
        (self.main.with_file_name(&name), percent_encode(&name))
    }

    /// Which side-file pattern of this output `name` matches, if any.
    fn side_kind(&self, name: &str) -> Option<Side> {
        let rest = name.strip_prefix(self.stem.as_str())?.strip_prefix('.')?;
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        let hex =
            |s: &str| s.len() == 16 && s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'));
        if rest == "bin" {
            return Some(Side::Legacy);
        }
        if let Some(h) = rest.strip_suffix(".bin") {
            return hex(h).then_some(Side::Hashed);
        }
        let atlas = rest.strip_prefix("lightmap")?.strip_suffix(".exr")?;
        match atlas.split_once('.') {
            None => digits(atlas).then_some(Side::Legacy),
            Some((k, h)) => (digits(k) && hex(h)).then_some(Side::Hashed),
        }
    }

    /// The side files of this output that `main` (this output's file or a sibling with the same
    /// stem) references: relative URIs in its folder matching a side-file pattern.
    fn references(&self, main: &Path) -> BTreeSet<String> {
        let Ok(bytes) = std::fs::read(main) else {
            return BTreeSet::new();
        };
        let Some(json) = json_of(&bytes) else {
            return BTreeSet::new();
        };
        let mut uris = Vec::new();
        collect_uris(&json, &mut uris);
        uris.iter()
            .filter_map(|u| percent_encoding::percent_decode_str(u).decode_utf8().ok())
            .map(|u| u.into_owned())
            .filter(|u| !u.contains(['/', '\\']) && self.side_kind(u).is_some())
            .collect()
    }

    /// What the output file references now: read before the commit, it is the old set's side
    /// files, to be removed after it.
    pub(crate) fn old_references(&self) -> BTreeSet<String> {
        self.references(&self.main)
    }

    /// After the commit: remove the side files of the old set (`old`) that the new set (`new`)
    /// does not reference, the hashed side files no `<stem>.gltf`/`.glb` here references (left
    /// by a killed run) and the temporaries of killed runs; never a file in `keep` (inputs).
    pub(crate) fn clean(&self, old: &BTreeSet<String>, new: &BTreeSet<String>, keep: &[PathBuf]) {
        let dir = atomic::folder(&self.main);
        let Ok(entries) = std::fs::read_dir(&dir) else {
            return;
        };
        let names: BTreeSet<String> = entries
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .collect();
        let main_name = self.main.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let mut referenced = new.clone();
        for name in &names {
            let sibling = Path::new(name);
            let same_stem = sibling.file_stem().and_then(|s| s.to_str()) == Some(&self.stem);
            let ext = sibling
                .extension()
                .and_then(|e| e.to_str())
                .map(str::to_ascii_lowercase);
            if name != main_name && same_stem && matches!(ext.as_deref(), Some("gltf" | "glb")) {
                referenced.extend(self.references(&dir.join(name)));
            }
        }
        let keep: Vec<PathBuf> = keep.iter().map(|p| canonical(p)).collect();
        for name in &names {
            let gone = match self.side_kind(name) {
                Some(Side::Hashed) => true,
                Some(Side::Legacy) => old.contains(name),
                None => false,
            };
            let path = dir.join(name);
            if gone && !referenced.contains(name) && !keep.contains(&canonical(&path)) {
                atomic::remove_leftover(&path);
            }
        }
        atomic::remove_stale_temporaries(&dir);
    }
}

/// The JSON of a `.gltf` file or of a `.glb`'s first chunk.
fn json_of(bytes: &[u8]) -> Option<serde_json::Value> {
    let chunk = if crate::import::is_glb(bytes) {
        crate::import::parse_glb(bytes).ok()?.json
    } else {
        bytes
    };
    serde_json::from_slice(chunk).ok()
}

/// Every string value of a `uri` key, at any depth.
fn collect_uris<'a>(value: &'a serde_json::Value, out: &mut Vec<&'a str>) {
    match value {
        serde_json::Value::Object(map) => {
            for (key, v) in map {
                match v.as_str() {
                    Some(s) if key == "uri" => out.push(s),
                    _ => collect_uris(v, out),
                }
            }
        }
        serde_json::Value::Array(items) => items.iter().for_each(|v| collect_uris(v, out)),
        _ => {}
    }
}

/// 64-bit FNV-1a of `bytes`: a stable content hash for side-file names (not a security hash;
/// the names only need to differ when the bytes do).
pub fn content_hash(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A file's identity: its canonical path and, when it exists, its (device, inode), so hard
/// links to one file are seen as one.
#[derive(Debug, Clone)]
struct FileId {
    path: PathBuf,
    inode: Option<(u64, u64)>,
}

impl FileId {
    fn same(&self, other: &FileId) -> bool {
        self.path == other.path || (self.inode.is_some() && self.inode == other.inode)
    }
}

fn inode(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// Check every output path of a run before any work: `gltf` (the scene output, if any, with its
/// side files) and `others`, against the `inputs` and each other. Each must name a file (not a
/// directory, not a device) in an existing folder where files can be created, must not be an
/// input or another output (same canonical path, or the same file through a hard link), and no
/// input or other output in the glTF's folder may have one of its side-file names.
pub(crate) fn check_paths(inputs: &[&Path], gltf: Option<&Target>, others: &[&Path]) -> Result<()> {
    let inputs: Vec<FileId> = inputs
        .iter()
        .filter(|p| !p.as_os_str().is_empty())
        .map(|p| FileId {
            path: canonical(p),
            inode: inode(p),
        })
        .collect();
    let mut outputs: Vec<(&Path, FileId)> = Vec::new();
    let mut folders: Vec<PathBuf> = Vec::new();
    for path in gltf
        .map(|t| t.main.as_path())
        .into_iter()
        .chain(others.iter().copied())
    {
        let id = output_id(path)?;
        if inputs.iter().any(|i| i.same(&id)) {
            return Err(Error::output(
                path,
                "refusing to overwrite an input file of this run; choose another output name",
            ));
        }
        if let Some((first, _)) = outputs.iter().find(|(_, o)| o.same(&id)) {
            return Err(Error::output(
                path,
                format!(
                    "two outputs would be written to the same file (also {}); choose another name",
                    first.display()
                ),
            ));
        }
        let dir = id.path.parent().map(Path::to_path_buf).unwrap_or_default();
        if !folders.contains(&dir) {
            atomic::check_writable(&dir).map_err(|e| {
                Error::output(
                    path,
                    format!("cannot write in folder {}: {e}", dir.display()),
                )
            })?;
            folders.push(dir);
        }
        outputs.push((path, id));
    }
    let Some(target) = gltf else {
        return Ok(());
    };
    let dir = outputs[0].1.path.parent().map(Path::to_path_buf);
    // Named as given for an output, canonical for an input.
    let clash = (inputs.iter().map(|i| (i.path.as_path(), i)))
        .chain(outputs.iter().skip(1).map(|(p, id)| (*p, id)));
    for (given, file) in clash {
        let name = file.path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if file.path.parent().map(Path::to_path_buf) == dir
            && target.side_kind(name) == Some(Side::Hashed)
        {
            return Err(Error::output(
                given,
                format!(
                    "this file (an input, or another output) has the name of a side file of \
                     {} ({stem}.<hash>.bin, {stem}.lightmap<k>.<hash>.exr), which a bake \
                     writes and removes; choose another output name",
                    target.main.display(),
                    stem = target.stem
                ),
            ));
        }
    }
    Ok(())
}

/// An output path's identity after the checks that need no comparison: a file name, in an
/// existing folder, not a directory or other non-regular file.
fn output_id(path: &Path) -> Result<FileId> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::output(path, "not a file name; name the file to write"))?;
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(Error::output(
                path,
                "is a directory; name a file to write (e.g. inside it)",
            ));
        }
        if !meta.is_file() {
            return Err(Error::output(
                path,
                "is not a regular file (a device, pipe or socket); name a file to write",
            ));
        }
        return Ok(FileId {
            path: canonical(path),
            inode: inode(path),
        });
    }
    let parent = atomic::folder(path);
    let dir = parent.canonicalize().map_err(|e| {
        Error::output(
            path,
            format!(
                "output folder {} is not usable: {e}; create it first",
                parent.display()
            ),
        )
    })?;
    if !dir.is_dir() {
        return Err(Error::output(
            path,
            format!("{} is not a folder", parent.display()),
        ));
    }
    Ok(FileId {
        path: dir.join(name),
        inode: None,
    })
}

/// The canonical path of a file, or the path itself when it cannot be resolved.
fn canonical(path: &Path) -> PathBuf {
    path.canonicalize().unwrap_or_else(|_| path.to_path_buf())
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
        let (bin, uri) = t.bin(b"");
        assert_eq!(bin, Path::new("out/room lit.cbf29ce484222325.bin"));
        assert_eq!(uri, "room%20lit.cbf29ce484222325.bin");
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
        assert!(check_paths(&[], Some(&t), &[]).is_err());
    }

    #[test]
    fn content_hash_is_fnv1a() {
        // Published FNV-1a 64 test vectors.
        assert_eq!(content_hash(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(content_hash(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(content_hash(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn side_file_names() {
        let t = Target::for_path(Path::new("out/room lit.glb")).unwrap();
        let (path, uri) = t.lightmap(12, b"a");
        assert_eq!(
            path,
            Path::new("out/room lit.lightmap12.af63dc4c8601ec8c.exr")
        );
        assert_eq!(uri, "room%20lit.lightmap12.af63dc4c8601ec8c.exr");
        for (name, kind) in [
            (
                "room lit.lightmap0.0123456789abcdef.exr",
                Some(Side::Hashed),
            ),
            ("room lit.0123456789abcdef.bin", Some(Side::Hashed)),
            ("room lit.lightmap0.exr", Some(Side::Legacy)),
            ("room lit.bin", Some(Side::Legacy)),
            ("room lit.lightmap.exr", None),
            ("room lit.lightmap1a.exr", None),
            ("room lit.0123456789ABCDEF.bin", None),
            ("room lit.v2.0123456789abcdef.bin", None),
            ("room lit.lightmap0.0123456789abcde.exr", None),
            ("room.lightmap0.exr", None),
            ("room lit.gltf", None),
        ] {
            assert_eq!(t.side_kind(name), kind, "{name}");
        }
    }
}
