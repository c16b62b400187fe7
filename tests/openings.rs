//! The luminaires' luminous openings drawn for viewers (issue 57, `bake::openings`,
//! `export/openings.rs`): samples/office's fittings show lit in any glTF viewer, the drawing is
//! never part of the light, and a re-bake of the output does not see it.

mod support;

use serde_json::Value;
use support::{cli, gltf_read};

/// Every photometric luminaire of the office gets a display-only node; the fittings' faces that
/// look down into the room (+Y up), and each opening's brightest face, show at least 0.95 of
/// white in COLOR_0 (brighter than the exposure's white), and `_LUMINANCE` is each face's
/// luminance (cd/m², > 0).
#[test]
fn the_office_fittings_are_drawn_lit_and_a_rebake_does_not_see_them() {
    let lit = cli::office_draft("openings-office", &[]);
    let dir = lit.parent().unwrap().to_path_buf();
    let file = gltf_read::read(&lit);
    let nodes = file.json["nodes"].as_array().unwrap();
    let luminaires = (nodes.iter())
        .filter(|n| n["extensions"]["LUXBAKE_luminaire"].is_object())
        .count();
    let shown: Vec<&Value> = (nodes.iter())
        .filter(|n| n["extras"]["luxbake"]["displayOnly"] == Value::Bool(true))
        .collect();
    assert_eq!((luminaires, shown.len()), (7, 7));
    for node in shown {
        let name = node["name"].as_str().unwrap();
        assert!(name.ends_with(" opening"), "{name}");
        let mesh = &file.json["meshes"][node["mesh"].as_u64().unwrap() as usize];
        let p = &mesh["primitives"][0];
        let a = &p["attributes"];
        assert!(a["_ILLUMINANCE"].is_null(), "{name}: no baked values");
        let material = &file.json["materials"][p["material"].as_u64().unwrap() as usize];
        assert!(material["extensions"]["KHR_materials_unlit"].is_object());
        assert_eq!(
            material["pbrMetallicRoughness"]["baseColorFactor"],
            serde_json::json!([1.0, 1.0, 1.0, 1.0])
        );
        let read = |key: &str| file.floats(a[key].as_u64().unwrap() as usize);
        let (normals, colors, luminance) = (read("NORMAL"), read("COLOR_0"), read("_LUMINANCE"));
        // The six fittings hang level (their nadir down); the spotlight is aimed: its
        // brightest face is checked.
        let fitting = name.starts_with("luminaire_");
        let brightest = luminance.iter().map(|l| l[0]).fold(0.0, f32::max);
        let mut checked = 0;
        for ((n, c), l) in normals.iter().zip(&colors).zip(&luminance) {
            assert!(l[0] > 0.0, "{name}: a face drawn shows light");
            if (fitting && n[1] < -0.7) || l[0] == brightest {
                checked += 1;
                assert!(
                    c.iter().all(|&x| x >= 0.95),
                    "{name}: COLOR_0 {c:?} at L {}",
                    l[0]
                );
            }
        }
        assert!(checked >= 3, "{name}: a face was checked");
    }

    // Baked anew, the output holds the same surfaces: the openings were not read as geometry
    // (they lie 1 mm under each fitting's diffuser and would shade it). (The light itself
    // differs a little: a re-bake meshes the output's patches anew.)
    let again = dir.join("again.gltf");
    let run = cli::bake_draft(&lit, &again, &[] as &[&str]);
    assert!(run.ok(), "{run:?}");
    let surfaces = |path: &std::path::Path| {
        gltf_read::read(path).json["scenes"][0]["extras"]["luxbake"]["counts"]["surfaces"].clone()
    };
    assert_eq!(surfaces(&lit), surfaces(&again));
    assert_eq!(surfaces(&lit), serde_json::json!(29));
}
