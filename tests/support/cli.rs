//! Running the `bake` binary, and a minimal valid input scene to break in small ways: a 2 × 2 m
//! floor quad (y = 0, facing +y, material 0: grey 0.5) under a 0.5 × 0.5 m emissive panel
//! (y = 1, facing −y, material 1: `LUXBAKE_material` reflectance 0.5, 500 lm). One buffer: the
//! floor's positions (accessor 0), the panel's (1), then their u16 indices (2, 3).

use serde_json::{Value, json};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

/// What one run of `bake` did.
#[derive(Debug)]
pub struct Run {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    pub fn ok(&self) -> bool {
        self.code == Some(0)
    }
}

/// Run `bake` with `args`.
pub fn bake<I, S>(args: I) -> Run
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let out = Command::new(env!("CARGO_BIN_EXE_bake"))
        .args(args)
        .output()
        .expect("cannot run the bake binary");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Bake `input` to `output` at draft quality with `extra` arguments.
pub fn bake_draft<S: AsRef<OsStr>>(input: &Path, output: &Path, extra: &[S]) -> Run {
    let mut args: Vec<&OsStr> = vec![
        input.as_os_str(),
        "-o".as_ref(),
        output.as_os_str(),
        "--quality".as_ref(),
        "draft".as_ref(),
    ];
    args.extend(extra.iter().map(AsRef::as_ref));
    bake(args)
}

/// Bake `input` to `output` with `--lightmaps` at default quality; the run must succeed.
pub fn bake_lightmapped(input: &Path, output: &Path) {
    let run = bake([
        input.as_os_str(),
        "-o".as_ref(),
        output.as_os_str(),
        "--lightmaps".as_ref(),
    ]);
    assert!(run.ok(), "{run:?}");
}

/// Bake `input` into `out/lit.gltf` at draft quality with `extra` arguments.
pub fn bake_draft_into<S: AsRef<OsStr>>(input: &Path, out: &Path, extra: &[S]) -> Run {
    bake_draft(input, &out.join("lit.gltf"), extra)
}

/// The minimal scene as `in/scene.gltf` (buffer `scene.bin`) and an empty `out/`, in
/// `scratch(name)`: (the scene, `in`, `out`).
pub fn mini_in(name: &str) -> (PathBuf, PathBuf, PathBuf) {
    let (input, out) = super::in_out(name);
    let gltf = Mini::new().write_gltf(&input, "scene.gltf", Some("scene.bin"));
    (gltf, input, out)
}

/// Non-zero exit and one `error:` line on stderr holding every needle.
pub fn assert_error_line(run: &Run, needles: &[&str]) {
    assert!(!run.ok(), "expected a failure, got {run:?}");
    assert!(run.code.is_some(), "killed by a signal: {run:?}");
    assert!(
        run.stderr.starts_with("error: ") && run.stderr.ends_with('\n'),
        "stderr must be one `error:` line:\n{}",
        run.stderr
    );
    assert_eq!(
        run.stderr.lines().count(),
        1,
        "stderr must be ONE line:\n{}",
        run.stderr
    );
    assert!(
        !run.stderr.contains("panicked"),
        "a panic, not an error: {}",
        run.stderr
    );
    for needle in needles {
        assert!(
            run.stderr.contains(needle),
            "expected '{needle}' in: {}",
            run.stderr
        );
    }
}

/// The sorted names of the files in `dir` (hidden ones included), a side file's content hash
/// shown as `#` (`lit.#.bin`, `lit.lightmap0.#.exr`; see [`super::unhashed`]).
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| super::unhashed(&e.unwrap().file_name().to_string_lossy()))
        .collect();
    names.sort();
    names
}

/// The path of a file under the repository root.
pub fn repo_file(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// The minimal scene: its JSON (without `buffers`) and its binary buffer.
#[derive(Debug, Clone)]
pub struct Mini {
    pub json: Value,
    pub bin: Vec<u8>,
}

fn vec3_accessor(view: usize, p: &[[f32; 3]]) -> Value {
    let fold = |f: fn(f32, f32) -> f32, init: f32| {
        (0..3)
            .map(|c| p.iter().fold(init, |a, v| f(a, v[c])))
            .collect::<Vec<f32>>()
    };
    json!({"bufferView": view, "componentType": 5126, "count": p.len(), "type": "VEC3",
           "min": fold(f32::min, f32::INFINITY), "max": fold(f32::max, f32::NEG_INFINITY)})
}

impl Mini {
    pub fn new() -> Mini {
        let floor = [
            [-1.0, 0.0, -1.0],
            [-1.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 0.0, -1.0],
        ];
        Mini::with_floor(floor)
    }

    /// The scene with the floor's four corners replaced (e.g. to put a NaN in them).
    pub fn with_floor(floor: [[f32; 3]; 4]) -> Mini {
        let panel = [
            [-0.25, 1.0, -0.25],
            [0.25, 1.0, -0.25],
            [0.25, 1.0, 0.25],
            [-0.25, 1.0, 0.25],
        ];
        let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
        let mut bin = Vec::new();
        for quad in [&floor, &panel] {
            bin.extend(quad.iter().flatten().flat_map(|v| v.to_le_bytes()));
        }
        for _ in 0..2 {
            bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        }
        let view = |offset: usize, length: usize, target: u32| json!({"buffer": 0, "byteOffset": offset, "byteLength": length, "target": target});
        let index = |view: usize| json!({"bufferView": view, "componentType": 5123, "count": 6, "type": "SCALAR"});
        let mesh = |name: &str, material: usize| {
            json!({"name": name, "primitives": [{"attributes": {"POSITION": material},
                   "indices": material + 2, "material": material}]})
        };
        let json = json!({
            "asset": {"version": "2.0"},
            "extensionsUsed": ["LUXBAKE_material"],
            "scene": 0,
            "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"name": "floor", "mesh": 0}, {"name": "panel", "mesh": 1}],
            "meshes": [mesh("floor", 0), mesh("panel", 1)],
            "materials": [
                {"name": "floor", "pbrMetallicRoughness":
                    {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0}},
                {"name": "panel", "extensions": {"LUXBAKE_material":
                    {"reflectance": 0.5, "emission": {"luminousFlux": 500.0}}}}
            ],
            "accessors": [vec3_accessor(0, &floor), vec3_accessor(1, &panel), index(2), index(3)],
            "bufferViews": [view(0, 48, 34962), view(48, 48, 34962),
                            view(96, 12, 34963), view(108, 12, 34963)],
        });
        Mini { json, bin }
    }

    /// The JSON with `buffers[0]` pointing at `uri` (`None`: no URI, as in a `.glb`).
    pub fn document(&self, uri: Option<&str>) -> Value {
        let mut json = self.json.clone();
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(uri) = uri {
            buffer["uri"] = json!(uri);
        }
        json["buffers"] = json!([buffer]);
        json
    }

    /// Write `dir/name` as a `.gltf` whose buffer is the side file `bin_name` (also written), or
    /// a base64 `data:` URI when `bin_name` is `None`.
    pub fn write_gltf(&self, dir: &Path, name: &str, bin_name: Option<&str>) -> PathBuf {
        use base64::Engine;
        let uri = match bin_name {
            Some(b) => {
                std::fs::write(dir.join(b), &self.bin).unwrap();
                b.to_string()
            }
            None => format!(
                "data:application/octet-stream;base64,{}",
                base64::engine::general_purpose::STANDARD.encode(&self.bin)
            ),
        };
        let path = dir.join(name);
        let text = serde_json::to_vec_pretty(&self.document(Some(&uri))).unwrap();
        std::fs::write(&path, text).unwrap();
        path
    }

    /// The scene as `.glb` bytes.
    pub fn glb_bytes(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.document(None)).unwrap();
        json.resize(json.len().next_multiple_of(4), b' ');
        let mut bin = self.bin.clone();
        bin.resize(bin.len().next_multiple_of(4), 0);
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        for word in [0x4654_6C67, 2, total as u32, json.len() as u32, 0x4E4F_534A] {
            out.extend(u32::to_le_bytes(word));
        }
        out.extend(&json);
        out.extend(u32::to_le_bytes(bin.len() as u32));
        out.extend(u32::to_le_bytes(0x004E_4942));
        out.extend(&bin);
        out
    }
}

/// samples/office baked at draft quality with `extra` into `scratch(name)/lit.gltf`.
pub fn office_draft(name: &str, extra: &[&str]) -> PathBuf {
    let lit = super::scratch(name).join("lit.gltf");
    let run = bake_draft(&repo_file("samples/office/office.gltf"), &lit, extra);
    assert!(run.ok(), "{run:?}");
    lit
}
