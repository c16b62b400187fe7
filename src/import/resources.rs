//! Reading the resources an input file refers to: glTF URIs (`data:` URIs, relative references)
//! and OBJ/MTL file names, confined to the input file's folder.
//!
//! Inputs: a reference string and the JSON pointer (or locator) of the element holding it.
//! Outputs: the bytes; files read are recorded in
//! the [`Ctx`].
//! Invariants: no file outside `Ctx::dir` is ever opened — references with a scheme other than
//! `data:` (including `file:`), absolute paths, `..` steps that climb above the folder and
//! symlinks whose target lies outside it are all refused with an error naming the element.

use super::context::Ctx;
use crate::Result;
use base64::Engine;
use std::path::{Component, Path, PathBuf};

/// Read a glTF `uri` (of a buffer or image at `at`). `what` names the resource in messages.
pub(crate) fn read_uri(ctx: &mut Ctx, uri: &str, at: &str, what: &str) -> Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        return decode_data_uri(rest).map_err(|m| ctx.err(at, format!("{what}: {m}")));
    }
    if let Some(scheme) = scheme_of(uri) {
        return Err(ctx.err(
            at,
            format!(
                "{what} URI '{uri}' uses the scheme '{scheme}:'; only relative file references \
                 and data: URIs are allowed"
            ),
        ));
    }
    let decoded = percent_encoding::percent_decode_str(uri)
        .decode_utf8()
        .map_err(|_| {
            ctx.err(
                at,
                format!("{what} URI '{uri}' is not valid UTF-8 when decoded"),
            )
        })?;
    read_confined(ctx, Path::new(decoded.as_ref()), at, what)
}

/// Read the file `reference` (relative to `Ctx::dir`), refusing anything outside that folder.
pub(crate) fn read_confined(
    ctx: &mut Ctx,
    reference: &Path,
    at: &str,
    what: &str,
) -> Result<Vec<u8>> {
    let path = confine(ctx, reference, at, what)?;
    let bytes = super::files::read(&path)
        .map_err(|e| ctx.err(at, format!("cannot read {what} {}: {e}", path.display())))?;
    ctx.record(path);
    Ok(bytes)
}

/// `dir.join(reference)` with `.` and `..` resolved lexically; `None` if `reference` is absolute.
fn lexical_join(dir: &Path, reference: &Path) -> Option<PathBuf> {
    let mut path = dir.to_path_buf();
    for component in reference.components() {
        match component {
            Component::Normal(name) => path.push(name),
            Component::CurDir => {}
            Component::ParentDir => {
                path.pop();
            }
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(path)
}

/// True when `reference` is relative and, with its `..` steps resolved, stays inside `dir`.
pub(crate) fn lexically_inside(dir: &Path, reference: &Path) -> bool {
    lexical_join(dir, reference).is_some_and(|p| p.starts_with(dir) && p != dir)
}

/// Resolve `reference` against `Ctx::dir` to a canonical path inside it.
pub(crate) fn confine(ctx: &Ctx, reference: &Path, at: &str, what: &str) -> Result<PathBuf> {
    let shown = reference.display();
    let dir = ctx.folder(at, what)?;
    let Some(lexical) = lexical_join(dir, reference) else {
        return Err(ctx.err(
            at,
            format!(
                "{what} '{shown}' is an absolute path; use a path relative to the input \
                 file's folder"
            ),
        ));
    };
    if !lexical.starts_with(dir) {
        return Err(ctx.err(
            at,
            format!(
                "{what} '{shown}' lies outside the folder of the input file; resources must be \
                 inside {}",
                dir.display()
            ),
        ));
    }
    if lexical == dir {
        return Err(ctx.err(at, format!("{what} '{shown}' does not name a file")));
    }
    let joined = dir.join(reference);
    let canonical = joined.canonicalize().map_err(|e| {
        ctx.err(
            at,
            format!("{what} file {} cannot be opened: {e}", joined.display()),
        )
    })?;
    if !canonical.starts_with(dir) {
        return Err(ctx.err(
            at,
            format!(
                "{what} '{shown}' resolves to {}, outside the folder of the input file (through \
                 a symbolic link); resources must be inside {}",
                canonical.display(),
                dir.display()
            ),
        ));
    }
    if !canonical.is_file() {
        return Err(ctx.err(at, format!("{what} {} is not a file", canonical.display())));
    }
    Ok(canonical)
}

/// The URI scheme (RFC 3986: ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":"), if any.
/// A single letter before ':' is taken as a Windows drive letter, which is a scheme too for us.
fn scheme_of(uri: &str) -> Option<&str> {
    let colon = uri.find(':')?;
    let scheme = &uri[..colon];
    let mut chars = scheme.chars();
    let first = chars.next()?;
    (first.is_ascii_alphabetic()
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.')))
    .then_some(scheme)
}

/// Decode the part of a `data:` URI after `data:`: `[<mediatype>][;base64],<data>`. The media
/// type is not used: images are recognised by their bytes.
fn decode_data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let (header, data) = rest
        .split_once(',')
        .ok_or("malformed data: URI (no ',' before the data)")?;
    if header.ends_with(";base64") {
        base64::engine::general_purpose::STANDARD_PAD_INDIFFERENT
            .decode(data.trim_end())
            .map_err(|e| format!("invalid base64 in data: URI: {e}"))
    } else {
        Ok(percent_encoding::percent_decode_str(data).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schemes() {
        assert_eq!(scheme_of("http://x/y.bin"), Some("http"));
        assert_eq!(scheme_of("file:///etc/passwd"), Some("file"));
        assert_eq!(scheme_of("C:/x.bin"), Some("C"));
        assert_eq!(scheme_of("a b:c.bin"), None);
        assert_eq!(scheme_of("dir/x:y.bin"), None);
        assert_eq!(scheme_of("x.bin"), None);
    }

    #[test]
    fn data_uris() {
        let r = decode_data_uri("application/octet-stream;base64,AAEC").unwrap();
        assert_eq!(r, vec![0, 1, 2]);
        let r = decode_data_uri(",a%20b").unwrap();
        assert_eq!(r, b"a b");
        assert!(decode_data_uri("image/png;base64").is_err());
    }
}
