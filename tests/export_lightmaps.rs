//! The lightmap files of the exporter on a hand-built bake with two atlases of known values
//! (`support/lightmapped.rs`): the files and their names, the EXR read back with the `exr` crate
//! (exact values, row 0 at the top, header texts), determinism, atomicity and the input guard.
//! The glTF side: `export_lightmaps_gltf.rs`; the Khronos validator and Blender:
//! `export_lightmaps_tools.rs`.

mod support;

use exr::prelude::*;
use luxbake::{Error, export, export::ExportOptions};
use serde_json::{Value, json};
use std::path::Path;
use support::{gltf_read, lightmapped, scratch};

fn write(path: &Path, options: &ExportOptions) {
    let (scene, result) = lightmapped::scene();
    export::write(path, &scene, &result, options).unwrap();
}

fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| support::unhashed(&e.unwrap().file_name().into_string().unwrap()))
        .collect();
    names.sort();
    names
}

#[test]
fn files_are_named_after_the_output() {
    let dir = scratch("lm-names");
    write(&dir.join("lit.gltf"), &ExportOptions::default());
    assert_eq!(
        names(&dir),
        [
            "lit.#.bin",
            "lit.gltf",
            "lit.lightmap0.#.exr",
            "lit.lightmap1.#.exr"
        ]
    );
    let dir = scratch("lm-names-glb");
    write(&dir.join("room lit.glb"), &ExportOptions::default());
    assert_eq!(
        names(&dir),
        [
            "room lit.glb",
            "room lit.lightmap0.#.exr",
            "room lit.lightmap1.#.exr"
        ]
    );
    let j = gltf_read::read(&dir.join("room lit.glb")).json;
    let ext = &j["materials"][2]["extensions"]["LUXBAKE_lightmap"];
    let exr = support::hashed(&dir, "room lit.lightmap0.#.exr");
    let name = exr.file_name().unwrap().to_str().unwrap();
    assert_eq!(ext["uri"], name.replace(' ', "%20"));
    // The name's hash is the file's content's (FNV-1a 64).
    let hash = luxbake::export::content_hash(&std::fs::read(&exr).unwrap());
    assert!(name.ends_with(&format!(".{hash:016x}.exr")), "{name}");
}

/// Every channel of every texel as written, row 0 first, and the header texts.
#[test]
fn exr_holds_the_atlas_exactly_row_0_at_the_top() {
    let dir = scratch("lm-exr");
    write(&dir.join("lit.gltf"), &ExportOptions::default());
    for k in 0..2 {
        let atlas = lightmapped::atlas(k);
        let image = read_all_flat_layers_from_file(support::hashed(
            &dir,
            &format!("lit.lightmap{k}.#.exr"),
        ))
        .unwrap_or_else(|e| panic!("atlas {k}: {e}"));
        let layer = &image.layer_data[0];
        assert_eq!(image.layer_data.len(), 1);
        let (w, h) = lightmapped::SIZES[k];
        assert_eq!(layer.size, Vec2(w as usize, h as usize));
        let channel = |name: &str| -> Vec<f32> {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name == *name)
                .unwrap_or_else(|| panic!("no channel {name}"));
            match &c.sample_data {
                FlatSamples::F32(v) => v.clone(),
                other => panic!("{name} is not 32-bit float: {other:?}"),
            }
        };
        let names: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        let sorted = [
            "B",
            "G",
            "R",
            "footprint",
            "illuminance",
            "illuminanceDirect",
        ];
        assert_eq!(names, sorted);
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            let want: Vec<f32> = atlas.luminance.iter().map(|v| v[c]).collect();
            assert_eq!(channel(name), want, "atlas {k} {name}");
        }
        assert_eq!(channel("illuminance"), atlas.illuminance);
        assert_eq!(channel("illuminanceDirect"), atlas.illuminance_direct);
        assert_eq!(channel("footprint"), atlas.area);
        // Scan line 0 is row 0 (the top): its first texel has G = 10·0 + 0.25.
        assert_eq!(channel("G")[0], 0.25);
        assert_eq!(
            channel("G")[(w * (h - 1)) as usize],
            10.0 * (h - 1) as f32 + 0.25
        );

        let header = &layer.attributes;
        assert_eq!(header.white_luminance, Some(1.0));
        let text = |name: &str| match header.other.get(&Text::from(name)) {
            Some(AttributeValue::Text(t)) => t.to_string(),
            other => panic!("{name}: {other:?}"),
        };
        assert_eq!(text("luxbake.atlas"), k.to_string());
        assert_eq!(
            text("luxbake.tool"),
            format!("luxbake {}", env!("CARGO_PKG_VERSION"))
        );
        assert_eq!(text("luxbake.texelSize"), "0.25 m");
        let units: Value = serde_json::from_str(&text("luxbake.units")).unwrap();
        assert_eq!(
            units,
            json!({"R": "cd/m2", "G": "cd/m2", "B": "cd/m2", "illuminance": "lx",
                   "illuminanceDirect": "lx", "footprint": "m2"})
        );
        let settings: Value = serde_json::from_str(&text("luxbake.settings")).unwrap();
        assert_eq!(settings["quality"], "default");
        let exposure: Value = serde_json::from_str(&text("luxbake.exposure")).unwrap();
        assert_eq!(exposure["whiteIlluminanceLx"], 400.0);
    }
}

#[test]
fn output_is_byte_identical_on_a_second_write() {
    let (a, b) = (scratch("lm-same-a"), scratch("lm-same-b"));
    for name in ["lit.gltf", "lit.glb"] {
        write(&a.join(name), &ExportOptions::default());
        write(&b.join(name), &ExportOptions::default());
    }
    let exact = |d: &Path| -> Vec<String> {
        let mut n: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        n.sort();
        n
    };
    assert_eq!(exact(&a), exact(&b));
    for name in exact(&a) {
        let same = std::fs::read(a.join(&name)).unwrap() == std::fs::read(b.join(&name)).unwrap();
        assert!(same, "{name} differs");
    }
}

fn assert_output_error(r: luxbake::Result<()>) {
    assert!(matches!(r, Err(Error::Output { .. })), "{r:?}");
}

#[test]
fn failed_writes_leave_nothing_behind() {
    let dir = scratch("lm-atomic");
    let (scene, mut result) = lightmapped::scene();
    let opts = ExportOptions::default();
    // The .gltf cannot replace a directory: the EXR files and the .bin renamed before it go.
    std::fs::create_dir(dir.join("lit.gltf")).unwrap();
    assert_output_error(export::write(&dir.join("lit.gltf"), &scene, &result, &opts));
    assert_eq!(names(&dir), ["lit.gltf"]);
    // An atlas that cannot be encoded (its second file): nothing is written, no temporary left.
    result.lightmaps.as_mut().unwrap().atlases[1].area.pop();
    assert_output_error(export::write(&dir.join("b.glb"), &scene, &result, &opts));
    assert_eq!(names(&dir), ["lit.gltf"]);
}

#[test]
fn refuses_when_a_lightmap_would_replace_an_input() {
    let dir = scratch("lm-refuse");
    let (mut scene, result) = lightmapped::scene();
    let input = dir.join("lit.lightmap1.0123456789abcdef.exr");
    std::fs::write(&input, b"input").unwrap();
    scene.input_files = vec![input.canonicalize().unwrap()];
    let out = dir.join("lit.glb");
    // Before the bake (how many atlases is not known yet) and when writing.
    assert_output_error(export::check(&out, &scene, &[]));
    assert_output_error(export::write(
        &out,
        &scene,
        &result,
        &ExportOptions::default(),
    ));
    assert!(export::check(&dir.join("other.glb"), &scene, &[]).is_ok());
    // An extra output (a summary) may not take a lightmap's name either.
    scene.input_files.clear();
    let summary = dir.join("lit.lightmap7.0123456789abcdef.exr");
    assert_output_error(export::check(&out, &scene, &[summary.as_path()]));
    assert_eq!(std::fs::read(&input).unwrap(), b"input");
    assert_eq!(names(&dir), ["lit.lightmap1.#.exr"]);
}
