//! The fuzz targets: one function per reader, fed arbitrary bytes. Each returns whether the input
//! was accepted (parsed without error); any panic, hang or huge allocation is a bug. The fuzzer
//! binaries (`fuzz/fuzz_targets/`, nightly) and the stable replay test (`tests/fuzz_replay.rs`,
//! which includes this file) call the same functions.
//!
//! Readers that only take a path get their bytes written into a per-thread scratch folder: the
//! input is split at [`SEP`]; the first part is the main file (`in.gltf`, `in.glb`, `in.obj`),
//! each further part is `NAME\nBYTES`, written as a file beside it (a `.bin` buffer, an `.mtl`,
//! an IES profile), so the fuzzer can also mutate the files a scene references.

use luxbake::import::{self, GltfFile, ImportOptions, UpAxis};
use luxbake::photometry::{Format, Photometry};
use luxbake::readback::{self, BakedOutput};
use luxbake::report::{self, Targets};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Separates the main file from the side files in a scene input.
pub const SEP: &[u8] = b"\n%%LUXFUZZ%%\n";

/// A baked output (a small Cornell box bake) the targets file is checked against.
const BAKED: &[u8] = include_bytes!("../data/cornell-baked.glb");

thread_local! {
    static SCRATCH: tempfile::TempDir = tempfile::tempdir().expect("a scratch folder");
}

fn split<'a>(data: &'a [u8], sep: &[u8]) -> Vec<&'a [u8]> {
    let mut parts = Vec::new();
    let mut rest = data;
    while let Some(i) = rest.windows(sep.len()).position(|w| w == sep) {
        parts.push(&rest[..i]);
        rest = &rest[i + sep.len()..];
    }
    parts.push(rest);
    parts
}

/// A side file's name: plain, short and inside the scratch folder.
fn side_name(name: &[u8]) -> Option<&str> {
    let name = std::str::from_utf8(name).ok()?;
    let plain = name
        .bytes()
        .all(|b| b.is_ascii_alphanumeric() || b == b'.' || b == b'_' || b == b'-');
    (plain && !name.is_empty() && name.len() <= 64 && !name.starts_with('.') && name != "in")
        .then_some(name)
}

/// Write `data` into an emptied scratch folder as `in.EXT` plus its side files; call `f` on the
/// main file's path.
fn with_files<T>(data: &[u8], ext: &str, f: impl FnOnce(&Path) -> T) -> T {
    SCRATCH.with(|dir| {
        let dir = dir.path();
        for entry in std::fs::read_dir(dir).expect("scratch folder readable") {
            let path = entry.expect("scratch entry").path();
            if path.is_dir() {
                std::fs::remove_dir_all(&path).expect("scratch cleared");
            } else {
                std::fs::remove_file(&path).expect("scratch cleared");
            }
        }
        let parts = split(data, SEP);
        let main: PathBuf = dir.join(format!("in.{ext}"));
        std::fs::write(&main, parts[0]).expect("scratch written");
        for part in &parts[1..] {
            let (name, bytes) = match part.iter().position(|&b| b == b'\n') {
                Some(i) => (&part[..i], &part[i + 1..]),
                None => (*part, &[][..]),
            };
            if let Some(name) = side_name(name) {
                std::fs::write(dir.join(name), bytes).expect("scratch written");
            }
        }
        f(&main)
    })
}

fn import_scene(data: &[u8], ext: &str, up: UpAxis) -> bool {
    with_files(data, ext, |path| {
        import::load(path, &ImportOptions { obj_up: up }).is_ok()
    })
}

/// A `.gltf` (JSON) scene and the files it references.
pub fn gltf(data: &[u8]) -> bool {
    import_scene(data, "gltf", UpAxis::Y)
}

/// A `.glb` scene (container, JSON chunk, BIN chunk) and the files it references; also opened as
/// a document held in memory (what `bake report`/`diff` start from).
pub fn glb(data: &[u8]) -> bool {
    let main = split(data, SEP)[0];
    let in_memory = GltfFile::from_bytes(Path::new("in.glb"), main).is_ok();
    import_scene(data, "glb", UpAxis::Y) || in_memory
}

/// An `.obj` scene with its `.mtl` (and textures) as side files, read +Z up when the first byte
/// is odd (so both axis conversions are fuzzed).
pub fn obj(data: &[u8]) -> bool {
    let up = if data.first().is_some_and(|b| b % 2 == 1) {
        UpAxis::Z
    } else {
        UpAxis::Y
    };
    import_scene(data, "obj", up)
}

/// Accessors: a GLB whose one primitive reads `POSITION`, `TEXCOORD_0` and indices from the fuzz
/// bytes with component types, normalisation, counts, offsets, strides, sparse substitution and
/// mode chosen by the first 16 bytes (the rest is the binary chunk).
pub fn accessors(data: &[u8]) -> bool {
    let mut head = [0u8; 16];
    let n = data.len().min(16);
    head[..n].copy_from_slice(&data[..n]);
    let bin = &data[n..];
    let glb = accessor_glb(&head, bin);
    let mut accepted = false;
    if let Ok(file) = GltfFile::from_bytes(Path::new("accessors.glb"), &glb) {
        for i in 0..file.nodes().len() {
            for p in file.primitives(i) {
                accepted |= p.positions().is_ok();
                accepted |= p.triangles().is_ok();
                accepted |= p.read("TEXCOORD_0", 2).is_ok();
                accepted |= p.read("_ILLUMINANCE", 1).is_ok();
            }
        }
    }
    // The scene importer reads the same accessors into surfaces (normals, winding, transforms).
    accepted | import_scene(&glb, "glb", UpAxis::Y)
}

const COMPONENT_TYPES: [u32; 6] = [5120, 5121, 5122, 5123, 5125, 5126];
const TYPES: [&str; 4] = ["VEC3", "VEC2", "SCALAR", "VEC4"];
const INDEX_TYPES: [u32; 4] = [5125, 5121, 5123, 5126];

fn accessor_glb(h: &[u8; 16], bin: &[u8]) -> Vec<u8> {
    let view = |offset: u8, length: u8, stride: u8| {
        let mut v = format!(
            r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}"#,
            length as usize * 4
        );
        if stride != 0 {
            v += &format!(r#","byteStride":{stride}"#);
        }
        v + "}"
    };
    let sparse = |flags: u8, count: u8, at: u8| {
        if flags & 1 == 0 {
            return String::new();
        }
        format!(
            r#","sparse":{{"count":{count},"indices":{{"bufferView":2,"byteOffset":{at},"componentType":{}}},"values":{{"bufferView":2,"byteOffset":{}}}}}"#,
            INDEX_TYPES[(flags as usize >> 1) % 3],
            (flags >> 3) as usize * 4
        )
    };
    let accessor = |kind: u8, count: u8, offset: u8, view: Option<u8>, extra: String| {
        let view = view
            .map(|v| format!(r#""bufferView":{v},"#))
            .unwrap_or_default();
        format!(
            r#"{{{view}"byteOffset":{offset},"componentType":{},"normalized":{},"count":{count},"type":"{}"{extra}}}"#,
            COMPONENT_TYPES[kind as usize % 6],
            kind & 0x08 != 0,
            TYPES[(kind as usize >> 4) % 4],
        )
    };
    // h[0] kind, h[1] count, h[2] offset, h[3..6] view 0, h[6] sparse flags, h[7] sparse count,
    // h[8] index kind, h[9] index count, h[10] index offset, h[11] mode, h[12..14] view 1,
    // h[14] texcoord kind, h[15] which accessors lack a bufferView.
    let position_view = (h[15] & 1 == 0).then_some(0);
    let accessors = [
        accessor(h[0], h[1], h[2], position_view, sparse(h[6], h[7], h[10])),
        format!(
            r#"{{"bufferView":1,"byteOffset":{},"componentType":{},"count":{},"type":"SCALAR"}}"#,
            h[10],
            INDEX_TYPES[h[8] as usize % 4],
            h[9]
        ),
        accessor(h[14], h[1], h[2] / 2, Some(0), String::new()),
        accessor(h[14] ^ 0x20, h[1], h[12], Some(1), String::new()),
    ];
    let mut attributes = r#""POSITION":0"#.to_string();
    if h[15] & 2 != 0 {
        attributes += r#","TEXCOORD_0":2"#;
    }
    if h[15] & 4 != 0 {
        attributes += r#","_ILLUMINANCE":3"#;
    }
    let indices = if h[15] & 8 == 0 {
        r#","indices":1"#
    } else {
        ""
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":{}}}],"bufferViews":[{},{},{}],"accessors":[{}],"meshes":[{{"primitives":[{{"attributes":{{{attributes}}}{indices},"mode":{}}}]}}],"nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#,
        bin.len(),
        view(h[3], h[4], h[5]),
        view(h[12], h[13], 0),
        view(h[7], h[13] ^ h[9], 0),
        accessors.join(","),
        h[11] % 8,
    );
    glb_bytes(json.as_bytes(), bin)
}

/// A GLB container of `json` and `bin` (each chunk padded to 4 bytes, as the spec says).
fn glb_bytes(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| n.div_ceil(4) * 4;
    let (j, b) = (pad(json.len()), pad(bin.len()));
    let total = 12 + 8 + j + 8 + b;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(20 + j, b' ');
    out.extend_from_slice(&(b as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}

fn photometry(data: &[u8], format: Format) -> bool {
    let Ok(p) = Photometry::parse(data, format) else {
        return false;
    };
    // What `bake luminaire` and the importer's luminaires ask of a parsed file.
    let _ = (
        p.flux(),
        p.opening(),
        p.light_output_ratio(),
        p.max_intensity(),
    );
    for (h, v) in [
        (0.0, 0.0),
        (45.0, 30.0),
        (90.0, 90.0),
        (180.0, 135.0),
        (270.0, 180.0),
    ] {
        let _ = p.intensity_at(h, v);
    }
    let _ = p.summary().to_string();
    let _ = p.polar_svg();
    true
}

/// An IES LM-63 file, then what `bake luminaire` computes of it.
pub fn ies(data: &[u8]) -> bool {
    photometry(data, Format::Ies)
}

/// An EULUMDAT file, then what `bake luminaire` computes of it.
pub fn ldt(data: &[u8]) -> bool {
    photometry(data, Format::Eulumdat)
}

/// A probe CSV file (`--probes FILE.csv`).
pub fn probes_csv(data: &[u8]) -> bool {
    std::str::from_utf8(data).is_ok_and(|text| luxbake::probes::csv::parse(text).is_ok())
}

fn baked_cornell() -> &'static BakedOutput {
    static B: OnceLock<BakedOutput> = OnceLock::new();
    B.get_or_init(|| readback::from_glb(Path::new("cornell-baked.glb"), BAKED).expect("a bake"))
}

/// A targets JSON file (`bake report --targets`), checked against a small bake.
pub fn targets_json(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let Ok(targets) = Targets::parse(Path::new("targets.json"), text) else {
        return false;
    };
    let options = report::Options {
        by: report::By::Both,
        targets: Some(targets),
        border: 0.0,
    };
    report::build(baked_cornell(), &options).is_ok()
}

/// A lightmap's OpenEXR file.
pub fn exr(data: &[u8]) -> bool {
    import::exr::decode(data, &readback::LIGHTMAP_CHANNELS).is_ok()
}

/// A baked output as GLB bytes (`bake report`/`diff` read it), then its report in every format.
pub fn baked(data: &[u8]) -> bool {
    let Ok(output) = readback::from_glb(Path::new("baked.glb"), data) else {
        return false;
    };
    if let Ok(r) = report::build(&output, &report::Options::default()) {
        for f in [
            report::Format::Table,
            report::Format::Markdown,
            report::Format::Csv,
            report::Format::Json,
        ] {
            let _ = r.render(f);
        }
    }
    true
}
