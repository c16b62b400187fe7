//! The `bake diff` tests' scene, bakes and file surgery: a small room with every kind of
//! primitive (single- and double-sided, two parents deep) and probes, written to `.gltf`/`.glb`;
//! editing one vertex value in a written `.bin`; running `bake diff`; reading attributes and
//! area-weighted node means straight from the files (independently of `luxbake::diff`).

use super::cli::{Run, bake as run_bake};
use super::gltf_read;
use glam::DVec3;
use luxbake::bake::bake;
use luxbake::export::{self, ExportOptions};
use luxbake::fixtures::SceneBuilder;
use luxbake::progress::Silent;
use luxbake::scene::{LocalTransform, Node, Scene};
use luxbake::settings::{ProbeGrid, Quality, Settings};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A 2 × 2 m floor (ρ 0.5, nodes 0) at y = 0 between two 1 m high walls facing it:
/// `wall_grey` (ρ 0.5) at x = 1 facing −x (node 1), `wall_white` (ρ 0.8) at x = −1 facing +x
/// (node 2). Returns the grey and white materials.
pub fn floor_and_walls(b: &mut SceneBuilder) -> (usize, usize) {
    let grey = b.material("grey", 0.5);
    let white = b.material("white", 0.8);
    b.floor("floor", 1.0, 0.0, grey);
    let p = DVec3::new;
    let wall = |x: f64| {
        [
            p(x, 0.0, -1.0),
            p(x, 0.0, 1.0),
            p(x, 1.0, 1.0),
            p(x, 1.0, -1.0),
        ]
    };
    let w = wall(-1.0);
    b.quad("wall_grey", wall(1.0), grey);
    b.quad("wall_white", [w[0], w[3], w[2], w[1]], white);
    (grey, white)
}

/// Move the roots `children` under a new root node `name` (the scene's last node).
pub fn group(scene: &mut Scene, name: &str, children: Vec<usize>) {
    scene.roots.retain(|r| !children.contains(r));
    scene.roots.push(scene.nodes.len());
    scene.nodes.push(Node {
        name: Some(name.into()),
        source_path: format!("/nodes/{}", scene.nodes.len()),
        children,
        local: LocalTransform::default(),
        world_from_local: glam::DMat4::IDENTITY,
        mesh_name: None,
        surfaces: Vec::new(),
        light: None,
        camera: None,
        extras: None,
    });
}

/// [`floor_and_walls`], a double-sided divider (ρ 0.6, front and back primitives) at z = 0.5,
/// all four under a parent node `room`; an isotropic point light of `flux` lm at (0, 1, 0).
pub fn room(flux: f64) -> Scene {
    let mut b = SceneBuilder::new();
    floor_and_walls(&mut b);
    let card = b.material_full("card", DVec3::splat(0.6), None, true);
    let p = DVec3::new;
    b.quad(
        "divider",
        [
            p(-0.5, 0.1, 0.5),
            p(0.5, 0.1, 0.5),
            p(0.5, 0.6, 0.5),
            p(-0.5, 0.6, 0.5),
        ],
        card,
    );
    b.point_light("lamp", p(0.0, 1.0, 0.0), flux);
    let mut scene = b.build();
    group(&mut scene, "room", vec![0, 1, 2, 3]);
    scene
}

pub fn settings(quality: Quality, patch: f64) -> Settings {
    Settings {
        quality,
        patch_size: Some(patch),
        probe_grid: Some(ProbeGrid {
            spacing: 0.5,
            height: 0.5,
        }),
        working_plane: Some(ProbeGrid {
            spacing: 0.5,
            height: 0.3,
        }),
        ..Settings::default()
    }
}

/// Bake `scene` and write it as `dir/name/lit.<ext>`.
pub fn write(dir: &Path, name: &str, ext: &str, scene: &Scene, settings: &Settings) -> PathBuf {
    let r = bake(scene, settings, &Silent).unwrap();
    let sub = dir.join(name);
    std::fs::create_dir_all(&sub).unwrap();
    let path = sub.join(format!("lit.{ext}"));
    export::write(&path, scene, &r, &ExportOptions::default()).unwrap();
    path
}

/// A copy of `lit.gltf` + its `lit.<hash>.bin` into `dir/name/`.
pub fn copy(from: &Path, dir: &Path, name: &str) -> PathBuf {
    let sub = dir.join(name);
    std::fs::create_dir_all(&sub).unwrap();
    let bin = bin_of(from);
    for f in [from.to_path_buf(), bin] {
        std::fs::copy(&f, sub.join(f.file_name().unwrap())).unwrap();
    }
    sub.join("lit.gltf")
}

/// The `.bin` side file of a written `.gltf` (its `buffers[0].uri`, a plain file name).
pub fn bin_of(gltf: &Path) -> PathBuf {
    let json: Value = serde_json::from_slice(&std::fs::read(gltf).unwrap()).unwrap();
    gltf.with_file_name(json["buffers"][0]["uri"].as_str().unwrap())
}

/// Where element `vertex` of a vertex attribute lies in the `.bin` of a written `.gltf`.
pub fn offset(gltf: &Path, node: &str, primitive: usize, attribute: &str, vertex: usize) -> usize {
    let json: Value = serde_json::from_slice(&std::fs::read(gltf).unwrap()).unwrap();
    let n = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"] == node)
        .unwrap();
    let prim = &json["meshes"][n["mesh"].as_u64().unwrap() as usize]["primitives"][primitive];
    let acc = &json["accessors"][prim["attributes"][attribute].as_u64().unwrap() as usize];
    let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    assert!(view.get("byteStride").is_none());
    let size = if acc["type"] == "VEC3" { 12 } else { 4 };
    view["byteOffset"].as_u64().unwrap_or(0) as usize
        + acc["byteOffset"].as_u64().unwrap_or(0) as usize
        + size * vertex
}

/// The index of the node named `name`.
pub fn node_index(gltf: &Path, name: &str) -> usize {
    let json: Value = serde_json::from_slice(&std::fs::read(gltf).unwrap()).unwrap();
    json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n["name"] == name)
        .unwrap()
}

pub fn read_f32(bin: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(bin[at..at + 4].try_into().unwrap())
}

/// Set one vertex's `_ILLUMINANCE` in the `.bin` of `gltf`; returns the old value and the
/// vertex's position.
pub fn edit(
    gltf: &Path,
    node: &str,
    primitive: usize,
    vertex: usize,
    value: f32,
) -> (f32, [f32; 3]) {
    let at = offset(gltf, node, primitive, "_ILLUMINANCE", vertex);
    let p = offset(gltf, node, primitive, "POSITION", vertex);
    let bin_path = bin_of(gltf);
    let mut bin = std::fs::read(&bin_path).unwrap();
    let old = read_f32(&bin, at);
    let position = [0, 4, 8].map(|k| read_f32(&bin, p + k));
    bin[at..at + 4].copy_from_slice(&value.to_le_bytes());
    std::fs::write(&bin_path, bin).unwrap();
    (old, position)
}

pub fn diff(a: &Path, b: &Path, options: &[&str]) -> Run {
    let mut args: Vec<String> = vec![
        "diff".into(),
        a.display().to_string(),
        b.display().to_string(),
    ];
    args.extend(options.iter().map(|s| s.to_string()));
    run_bake(args)
}

pub fn diff_json(a: &Path, b: &Path, options: &[&str]) -> (Run, Value) {
    let mut o = options.to_vec();
    o.push("--json");
    let run = diff(a, b, &o);
    let json = serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}\n{}", run.stdout, run.stderr));
    (run, json)
}

pub fn quantity<'a>(d: &'a Value, key: &str) -> &'a Value {
    d["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["quantity"] == key)
        .unwrap_or_else(|| panic!("no quantity {key}"))
}

pub fn last_line(s: &str) -> &str {
    s.lines().last().unwrap_or("")
}

pub const QUANTITIES: [&str; 5] = [
    "illuminance",
    "illuminanceDirect",
    "luminance",
    "probeFaces",
    "workingPlane",
];

pub fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// Every baked primitive's `attribute` values, in the file's mesh and primitive order.
pub fn attribute(path: &Path, attribute: &str) -> Vec<Vec<f64>> {
    let file = gltf_read::read(path);
    let mut out = Vec::new();
    for mesh in file.json["meshes"].as_array().unwrap() {
        for p in mesh["primitives"].as_array().unwrap() {
            if let Some(acc) = p["attributes"][attribute].as_u64() {
                let v = file.floats(acc as usize);
                out.push(v.iter().map(|x| f64::from(x[0])).collect());
            }
        }
    }
    out
}

/// 1 % of the nearest-rank 99th percentile of |_ILLUMINANCE| over all vertices.
pub fn default_floor(path: &Path) -> f64 {
    let mut all: Vec<f64> = attribute(path, "_ILLUMINANCE")
        .into_iter()
        .flatten()
        .map(f64::abs)
        .collect();
    all.sort_by(f64::total_cmp);
    0.01 * all[(0.99 * all.len() as f64).ceil() as usize - 1]
}

/// Max, mean and nearest-rank p95.
pub fn max_mean_p95(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    let p95 = v[(0.95 * v.len() as f64).ceil() as usize - 1];
    [v[v.len() - 1], v.iter().sum::<f64>() / v.len() as f64, p95]
}

/// The area-weighted mean of `_ILLUMINANCE` over the baked primitives of the node `name`
/// (identity transforms: positions are world positions).
pub fn node_mean(path: &Path, name: &str) -> f64 {
    let file = gltf_read::read(path);
    let json = &file.json;
    let node = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"] == name)
        .unwrap();
    let (mut area, mut sum) = (0.0, 0.0);
    for p in json["meshes"][node["mesh"].as_u64().unwrap() as usize]["primitives"]
        .as_array()
        .unwrap()
    {
        let get = |k: &str| p["attributes"][k].as_u64().unwrap() as usize;
        let e = file.floats(get("_ILLUMINANCE"));
        let x: Vec<DVec3> = file
            .floats(get("POSITION"))
            .iter()
            .map(|v| DVec3::new(v[0].into(), v[1].into(), v[2].into()))
            .collect();
        for t in file
            .indices(p["indices"].as_u64().unwrap() as usize)
            .chunks(3)
        {
            let [i, j, k] = [t[0], t[1], t[2]].map(|v| v as usize);
            let w = (x[j] - x[i]).cross(x[k] - x[i]).length() / 2.0;
            area += w;
            sum += w / 3.0 * (f64::from(e[i][0]) + f64::from(e[j][0]) + f64::from(e[k][0]));
        }
    }
    sum / area
}
