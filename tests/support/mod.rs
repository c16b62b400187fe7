//! Shared test support: running the `bake` binary on a minimal input scene (`cli`), the `bake
//! diff` tests' room and file surgery (`bakes`), a hand-built scene with its bake result
//! (`fixture`), a minimal reader of the written glTF (`gltf_read`) and the external tools
//! (`tools`: Khronos glTF-Validator, Blender's importer). Each test binary uses what it needs.
#![allow(dead_code)]

pub mod bakes;
pub mod cli;
pub mod fixture;
pub mod gltf_read;
pub mod lightmapped;
pub mod tools;

use std::path::{Path, PathBuf};

/// `name` with a side file's content hash (16 lowercase hex digits between the last two dots)
/// replaced by `#`: `lit.0123456789abcdef.bin` → `lit.#.bin`.
pub fn unhashed(name: &str) -> String {
    let parts: Vec<&str> = name.split('.').collect();
    let hex = |s: &str| s.len() == 16 && s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'));
    match parts.len() {
        n if n >= 3 && hex(parts[n - 2]) => {
            let mut parts = parts;
            parts[n - 2] = "#";
            parts.join(".")
        }
        _ => name.to_string(),
    }
}

/// The one file in `dir` whose [`unhashed`] name is `pattern` (e.g. `lit.#.bin`).
pub fn hashed(dir: &Path, pattern: &str) -> PathBuf {
    let found: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| unhashed(&p.file_name().unwrap().to_string_lossy()) == pattern)
        .collect();
    assert_eq!(found.len(), 1, "{pattern} in {}: {found:?}", dir.display());
    found.into_iter().next().unwrap()
}

/// A fresh, empty directory for one test's files, under cargo's temporary directory for
/// integration tests (emptied again by the next run of the same test).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("luxbake-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A test's folders: `scratch(name)/in/` for the input, `scratch(name)/out/` (empty) for the
/// output.
pub fn in_out(name: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(name);
    let (input, out) = (dir.join("in"), dir.join("out"));
    std::fs::create_dir(&input).unwrap();
    std::fs::create_dir(&out).unwrap();
    (input, out)
}

/// A PNG's width, height and RGB pixels as bytes (row 0 at the top; RGBA loses its alpha), for
/// 8-bit files ([`png_is_8_bit`] says).
pub fn read_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    pixels.truncate(info.buffer_size());
    let pixels = match info.color_type {
        png::ColorType::Rgb => pixels,
        png::ColorType::Rgba => pixels.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect(),
        other => panic!("{}: colour type {other:?}", path.display()),
    };
    (info.width as usize, info.height as usize, pixels)
}

/// Whether the PNG at `path` has 8 bits a channel.
pub fn png_is_8_bit(path: &Path) -> bool {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    reader.info().bit_depth == png::BitDepth::Eight
}
