//! Luminaires and photometric profiles in glTF inputs (`EXT_lights_ies`, `LUXBAKE_luminaire`,
//! `LUXBAKE_material.emission.profile`), through `luxbake::import::load`: where profiles come from
//! (data URI, bufferView, external file, confined to the input folder), the photometric frame of
//! a node, the intensity arithmetic, and every refusal with its exact JSON pointer.
//!
//! Tests that need a successful import are ignored until the photometry parser lands
//! (`src/photometry` is a stub whose `Photometry::parse` always fails); the refusals are all
//! found before any profile is parsed, so they run now.

mod common;

use common::luminaires::*;
use common::*;
use glam::{DMat3, DQuat, DVec3};
use luxbake::photometry::{Opening, OpeningShape};
use luxbake::scene::{EmissionAmount, Scene};
use serde_json::{Value, json};
use std::path::Path;

fn assert_error(path: &Path, pointer: &str, needle: &str) {
    let (at, message) = load_err(path);
    assert_eq!(at, pointer, "{message}");
    assert!(message.contains(&format!("{pointer}: ")), "{message}");
    assert!(
        message.contains(needle),
        "expected '{needle}' in: {message}"
    );
    assert!(message.contains(&path.display().to_string()), "{message}");
}

fn frame_close(a: DMat3, b: DMat3, what: &str) {
    for (x, y) in [
        (a.x_axis, b.x_axis),
        (a.y_axis, b.y_axis),
        (a.z_axis, b.z_axis),
    ] {
        assert_close(x, y, what);
    }
}

#[test]

fn base_scene_loads() {
    let dir = tempfile::tempdir().unwrap();
    let path = base().write_gltf(dir.path(), "base.gltf", Bin::DataUri);
    let s = load_ok(&path);
    assert_eq!(s.profiles.len(), 2);
    assert_eq!(
        s.profiles[0].source_path,
        "/extensions/EXT_lights_ies/lights/0"
    );
    assert_eq!(s.profiles[0].name.as_deref(), Some("down"));
    assert_eq!(s.profiles[0].bytes, IES.as_bytes());
    assert_eq!(
        s.profiles[1].source_path,
        "/extensions/LUXBAKE_luminaire/profiles/0"
    );
    assert_eq!(s.profiles[1].bytes, LDT.as_bytes());
    assert!(s.profiles[1].photometry.flux() > 0.0);

    assert_eq!(s.luminaires.len(), 2);
    let [ies, ldt] = [&s.luminaires[0], &s.luminaires[1]];
    assert_eq!((ies.node, ies.profile), (1, 0));
    assert_eq!(ies.name.as_deref(), Some("Ies"));
    assert_eq!(ies.source_path, "/nodes/1/extensions/EXT_lights_ies");
    assert_eq!(
        Value::Object(ies.extensions.clone()),
        json!({"EXT_lights_ies": {"light": 0}})
    );
    assert_close(ies.position, DVec3::new(0.0, 3.0, 0.0), "position");
    frame_close(ies.world_from_photometric, DMat3::IDENTITY, "frame");
    assert_eq!((ies.multiplier, ies.maintenance_factor), (1.0, 1.0));
    assert_eq!(ies.color, DVec3::ONE);
    assert_eq!(ies.opening, None);
    assert_eq!((ldt.node, ldt.profile), (2, 1));
    assert_eq!(ldt.source_path, "/nodes/2/extensions/LUXBAKE_luminaire");
}

#[test]

fn frame_follows_the_node_without_its_scale() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = base();
    // The luminaire's node: −Z along `down`, +X along `c0` (in the parent's space), scaled.
    let down = DVec3::new(0.3, -1.0, 0.4).normalize();
    let c0 = DVec3::Y.cross(down).normalize();
    let local = DQuat::from_mat3(&DMat3::from_cols(c0, (-down).cross(c0), -down));
    let child = b.node(json!({
        "name": "Aimed",
        "translation": [0.5, -0.25, 0.0],
        "rotation": local.to_array(),
        "scale": [2.0, 0.5, 3.0],
        "extensions": {"LUXBAKE_luminaire": {"profile": 0}},
    }));
    let parent_rotation = DQuat::from_rotation_y(0.7);
    root(
        &mut b,
        json!({"name": "Track", "translation": [1, 2, 3], "rotation": parent_rotation.to_array(),
            "scale": [2, 2, 2], "children": [child]}),
    );
    let path = b.write_gltf(dir.path(), "aimed.gltf", Bin::DataUri);
    let s = load_ok(&path);
    let l = s.luminaires.iter().find(|l| l.node == child).unwrap();
    let f = l.world_from_photometric;
    assert_close(f * DVec3::NEG_Z, parent_rotation * down, "nadir");
    assert_close(f * DVec3::X, parent_rotation * c0, "C0");
    assert_close(
        f * DVec3::Y,
        parent_rotation * (-down).cross(c0),
        "C90 (node +Y)",
    );
    assert_near(f.determinant(), 1.0, "right-handed, unscaled");
    assert_close(
        l.position,
        DVec3::new(1.0, 2.0, 3.0) + parent_rotation * DVec3::new(1.0, -0.5, 0.0),
        "position",
    );
    // Node scale does not change the intensity.
    assert_eq!(l.multiplier, 1.0);
    // Luminaires follow node index order.
    let nodes: Vec<usize> = s.luminaires.iter().map(|l| l.node).collect();
    assert_eq!(nodes, [1, 2, child]);
}

#[test]

fn mirrored_node_keeps_a_right_handed_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = base();
    b.json["nodes"][1]["scale"] = json!([1, -1, 1]);
    let path = b.write_gltf(dir.path(), "mirror.gltf", Bin::DataUri);
    let s = load_ok(&path);
    frame_close(
        s.luminaires[0].world_from_photometric,
        DMat3::IDENTITY,
        "the distribution is not mirrored",
    );
}

#[test]

fn multiplier_colour_maintenance_and_opening() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = base();
    b.json["nodes"][1]["extensions"] = json!({
        "EXT_lights_ies": {"light": 0, "multiplier": 2.5, "color": [1.0, 0.8, 0.5]},
        "LUXBAKE_luminaire": {"maintenanceFactor": 0.8,
            "opening": {"length": 1.2, "width": 0.3, "height": 0.05}},
    });
    b.json["nodes"][2]["extensions"]["LUXBAKE_luminaire"] =
        json!({"profile": 0, "multiplier": 4, "color": [0.2, 0.4, 1.0]});
    let path = b.write_gltf(dir.path(), "arith.gltf", Bin::DataUri);
    let s = load_ok(&path);

    let y = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let l = &s.luminaires[0];
    let raw = [1.0, 0.8, 0.5];
    assert_near(l.multiplier, 2.5 * y(raw) * 0.8, "EXT multiplier × Y × MF");
    assert_eq!(l.maintenance_factor, 0.8);
    assert_close(l.color, DVec3::from_array(raw) / y(raw), "colour at Y = 1");
    assert_eq!(
        l.opening,
        Some(Opening {
            length: 1.2,
            width: 0.3,
            height: 0.05,
            shape: OpeningShape::Rectangular
        })
    );
    assert_eq!(l.profile, 0);
    assert_eq!(l.source_path, "/nodes/1/extensions/EXT_lights_ies");
    assert_eq!(l.extensions.len(), 2);

    let l = &s.luminaires[1];
    let raw = [0.2, 0.4, 1.0];
    assert_near(l.multiplier, 4.0 * y(raw), "LUXBAKE multiplier × Y");
    assert_close(l.color, DVec3::from_array(raw) / y(raw), "colour at Y = 1");
    assert_eq!(l.maintenance_factor, 1.0);
}

#[test]

fn profiles_from_files_buffer_views_and_glb() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("ies")).unwrap();
    std::fs::write(dir.path().join("ies/down light.ies"), IES).unwrap();
    std::fs::write(dir.path().join("panel.LDT"), LDT).unwrap();
    std::fs::write(dir.path().join("panel.txt"), LDT).unwrap();
    let mut b = base();
    let ies_view = b.view(IES.as_bytes());
    let ldt_view = b.view(LDT.as_bytes());
    b.json["extensions"] = json!({
        "EXT_lights_ies": {"lights": [
            {"uri": "ies/down%20light.ies"},
            {"bufferView": ies_view, "mimeType": "application/x-ies-lm-63"},
        ]},
        "LUXBAKE_luminaire": {"profiles": [
            {"uri": "panel.LDT"},
            {"uri": "panel.txt", "mimeType": "application/x-eulumdat"},
            {"bufferView": ldt_view, "mimeType": "application/x-eulumdat", "name": "in bin"},
            {"uri": data_uri("application/x-ies-lm-63", IES)},
        ]},
    });
    b.json["nodes"][1]["extensions"]["EXT_lights_ies"]["light"] = json!(1);
    b.json["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["profile"] = json!(3);
    for path in [
        b.write_gltf(dir.path(), "files.gltf", Bin::External("files.bin")),
        b.write_glb(dir.path(), "files.glb"),
    ] {
        let s = load_ok(&path);
        let bytes: Vec<&[u8]> = s.profiles.iter().map(|p| p.bytes.as_slice()).collect();
        let (i, l) = (IES.as_bytes(), LDT.as_bytes());
        assert_eq!(bytes, [i, i, l, l, l, i]);
        assert_eq!(s.profiles[4].name.as_deref(), Some("in bin"));
        assert_eq!(
            s.profiles[5].source_path,
            "/extensions/LUXBAKE_luminaire/profiles/3"
        );
        assert_eq!(s.luminaires[0].profile, 1);
        assert_eq!(s.luminaires[1].profile, 2 + 3);
        for file in ["ies/down light.ies", "panel.LDT", "panel.txt"] {
            let canonical = dir.path().join(file).canonicalize().unwrap();
            assert!(s.input_files.contains(&canonical), "{file} not recorded");
        }
    }
}

#[test]

fn emission_profile_on_a_material() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = base();
    b.json["extensions"]["LUXBAKE_luminaire"]["profiles"]
        .as_array_mut()
        .unwrap()
        .push(json!({"uri": ies_uri()}));
    b.material(
        json!({"extensions": {"LUXBAKE_material": {"reflectance": 0.5,
        "emission": {"luminousFlux": 1200, "profile": 1}}}}),
    );
    b.material(
        json!({"extras": {"luxbake": {"original": {"LUXBAKE_material":
        {"emission": {"luminance": 50, "profile": 0}}}}},
        "pbrMetallicRoughness": {"metallicFactor": 0, "baseColorFactor": [0.5, 0.5, 0.5, 1]}}),
    );
    let path = b.write_gltf(dir.path(), "emit.gltf", Bin::DataUri);
    let s = load_ok(&path);
    // Scene profiles: EXT light 0, then LUXBAKE profiles 0 and 1.
    let e = s.materials[0].emission.unwrap();
    assert_eq!(e.profile, Some(2));
    assert_eq!(e.amount, EmissionAmount::LuminousFlux(1200.0));
    // An unlit luxbake output keeps the extension in extras; the profile is read from there too.
    assert_eq!(s.materials[1].emission.unwrap().profile, Some(1));
}

#[test]

fn nodes_outside_the_scene_place_no_luminaire() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = base();
    b.node(json!({"extensions": {"EXT_lights_ies": {"light": 0}}}));
    let path = b.write_gltf(dir.path(), "orphan.gltf", Bin::DataUri);
    let s: Scene = load_ok(&path);
    assert_eq!(s.luminaires.len(), 2);
}

#[test]
fn required_extensions_are_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    b.json["extensionsUsed"] = json!(["EXT_lights_ies", "LUXBAKE_luminaire"]);
    b.json["extensionsRequired"] = json!(["EXT_lights_ies", "LUXBAKE_luminaire"]);
    let path = b.write_gltf(dir.path(), "required.gltf", Bin::DataUri);
    let s = load_ok(&path);
    assert!(s.profiles.is_empty() && s.luminaires.is_empty());
}

#[test]
fn parse_errors_name_the_profile_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = "IESNA:LM-63-2002\nTILT=NONE\n1 1000 one 3 1 1 2 0 0 0\n";
    std::fs::write(dir.path().join("bad.ies"), bad).unwrap();
    let mut b = base();
    b.json["extensions"]["EXT_lights_ies"]["lights"][0] = json!({"uri": "bad.ies"});
    let path = b.write_gltf(dir.path(), "bad.gltf", Bin::DataUri);
    assert_error(
        &path,
        "/extensions/EXT_lights_ies/lights/0",
        "IES LM-63 profile (bad.ies): line ",
    );

    let mut b = base();
    let view = b.view(bad.as_bytes());
    b.json["extensions"]["LUXBAKE_luminaire"]["profiles"][0] =
        json!({"bufferView": view, "mimeType": "application/x-eulumdat"});
    let path = b.write_gltf(dir.path(), "bad_view.gltf", Bin::DataUri);
    // With the real parser the good IES profile parses and the bad EULUMDAT one fails; the stub
    // fails on the first profile.
    let (at, message) = load_err(&path);
    assert!(
        at == "/extensions/LUXBAKE_luminaire/profiles/0"
            && message.contains("EULUMDAT profile (/bufferViews/")
            || at == "/extensions/EXT_lights_ies/lights/0" && message.contains("not implemented"),
        "{at}: {message}"
    );
}

#[test]
fn profile_uris_stay_in_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("a/b");
    std::fs::create_dir_all(&inner).unwrap();
    std::fs::write(dir.path().join("a/x.ies"), IES).unwrap();
    let at = "/extensions/EXT_lights_ies/lights/0";
    for (uri, needle) in [
        ("../x.ies", "outside the folder"),
        ("/etc/passwd", "absolute path"),
        ("file:///etc/passwd", "scheme 'file:'"),
        ("https://example.com/x.ies", "scheme 'https:'"),
        ("missing.ies", "cannot be opened"),
    ] {
        let mut b = base();
        b.json["extensions"]["EXT_lights_ies"]["lights"][0] = json!({"uri": uri});
        let path = b.write_gltf(&inner, "up.gltf", Bin::DataUri);
        assert_error(&path, at, needle);
    }
    // The same for LUXBAKE_luminaire.
    let mut b = base();
    b.json["extensions"]["LUXBAKE_luminaire"]["profiles"][0] = json!({"uri": "../x.ies"});
    let path = b.write_gltf(&inner, "up2.gltf", Bin::DataUri);
    assert_error(
        &path,
        "/extensions/LUXBAKE_luminaire/profiles/0",
        "outside the folder",
    );
}

/// Every refusal, each at its exact JSON pointer. All are found before any profile is parsed.
#[test]
fn refusals_name_the_element() {
    type Edit = fn(&mut Value);
    let ies = "/extensions/EXT_lights_ies/lights/0";
    let lux = "/extensions/LUXBAKE_luminaire/profiles/0";
    let n1 = "/nodes/1/extensions/EXT_lights_ies";
    let n2 = "/nodes/2/extensions/LUXBAKE_luminaire";
    let cases: Vec<(String, &str, Edit)> = vec![
        // Root lists and profile entries.
        ("/extensions/EXT_lights_ies".into(), "JSON object", |j| {
            j["extensions"]["EXT_lights_ies"] = json!([]);
        }),
        ("/extensions/EXT_lights_ies".into(), "'lights'", |j| {
            j["extensions"]["EXT_lights_ies"] = json!({});
        }),
        (
            "/extensions/LUXBAKE_luminaire/profiles".into(),
            "array",
            |j| {
                j["extensions"]["LUXBAKE_luminaire"]["profiles"] = json!({});
            },
        ),
        (
            "/extensions/LUXBAKE_luminaire".into(),
            "unknown member 'lights'",
            |j| {
                j["extensions"]["LUXBAKE_luminaire"]["lights"] = json!([]);
            },
        ),
        (ies.into(), "JSON object", |j| {
            j["extensions"]["EXT_lights_ies"]["lights"][0] = json!("x.ies");
        }),
        (ies.into(), "exactly one of uri and bufferView", |j| {
            j["extensions"]["EXT_lights_ies"]["lights"][0]["bufferView"] = json!(0);
        }),
        (lux.into(), "exactly one of uri and bufferView", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0] = json!({"name": "none"});
        }),
        (
            format!("{ies}/mimeType"),
            "unknown mimeType 'text/plain'",
            |j| {
                j["extensions"]["EXT_lights_ies"]["lights"][0]["mimeType"] = json!("text/plain");
            },
        ),
        (format!("{ies}/mimeType"), "IES LM-63 files only", |j| {
            j["extensions"]["EXT_lights_ies"]["lights"][0]["mimeType"] =
                json!("application/x-eulumdat");
        }),
        (
            format!("{lux}/mimeType"),
            "unknown mimeType 'image/png'",
            |j| {
                j["extensions"]["LUXBAKE_luminaire"]["profiles"][0]["mimeType"] =
                    json!("image/png");
            },
        ),
        (format!("{lux}/mimeType"), "must be a string", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0]["mimeType"] = json!(1);
        }),
        (lux.into(), "cannot tell the format of 'panel.txt'", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0] = json!({"uri": "panel.txt"});
        }),
        (
            lux.into(),
            "cannot tell the format of 'data:text/plain;base64,…'",
            |j| {
                j["extensions"]["LUXBAKE_luminaire"]["profiles"][0] =
                    json!({"uri": "data:text/plain;base64,QUJD"});
            },
        ),
        (lux.into(), "needs a mimeType", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0] = json!({"bufferView": 0});
        }),
        (
            format!("{lux}/bufferView"),
            "/bufferViews/9, which does not exist",
            |j| {
                j["extensions"]["LUXBAKE_luminaire"]["profiles"][0] =
                    json!({"bufferView": 9, "mimeType": "application/x-eulumdat"});
            },
        ),
        (format!("{lux}/bufferView"), "an index", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0] =
                json!({"bufferView": -1, "mimeType": "application/x-eulumdat"});
        }),
        (lux.into(), "unknown member 'url'", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0]["url"] = json!("x.ldt");
        }),
        (format!("{lux}/name"), "string", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0]["name"] = json!(7);
        }),
        (lux.into(), "invalid base64", |j| {
            j["extensions"]["LUXBAKE_luminaire"]["profiles"][0]["uri"] =
                json!("data:application/x-eulumdat;base64,@@@");
        }),
        // Node extensions.
        (
            format!("{n1}/light"),
            "/extensions/EXT_lights_ies/lights/1, which does not exist",
            |j| {
                j["nodes"][1]["extensions"]["EXT_lights_ies"]["light"] = json!(1);
            },
        ),
        (format!("{n1}/light"), "an index", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"]["light"] = json!("0");
        }),
        (n1.into(), "no 'light'", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"] = json!({"multiplier": 2});
        }),
        (n1.into(), "JSON object", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"] = json!(0);
        }),
        (
            format!("{n1}/multiplier"),
            "multiplier -1 must be finite and ≥ 0",
            |j| {
                j["nodes"][1]["extensions"]["EXT_lights_ies"]["multiplier"] = json!(-1);
            },
        ),
        (format!("{n1}/color"), "every channel in [0, 1]", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"]["color"] = json!([1.2, 1, 1]);
        }),
        (format!("{n1}/color"), "positive luminance", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"]["color"] = json!([0, 0, 0]);
        }),
        (format!("{n1}/color"), "array of 3 numbers", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"]["color"] = json!([1, 1]);
        }),
        ("/nodes/1".into(), "two profiles", |j| {
            j["nodes"][1]["extensions"]["LUXBAKE_luminaire"] = json!({"profile": 0});
        }),
        ("/nodes/1".into(), "no luminance", |j| {
            j["nodes"][1]["extensions"]["EXT_lights_ies"]["color"] = json!([1, 0, 0]);
            j["nodes"][1]["extensions"]["LUXBAKE_luminaire"] = json!({"color": [0, 1, 1]});
        }),
        ("/nodes/1".into(), "collapses", |j| {
            j["nodes"][1]["scale"] = json!([1, 1, 0]);
        }),
        (
            format!("{n2}/profile"),
            "/extensions/LUXBAKE_luminaire/profiles/1, which does not",
            |j| {
                j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["profile"] = json!(1);
            },
        ),
        (n2.into(), "has no profile", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"] = json!({"multiplier": 2});
        }),
        (n2.into(), "unknown member 'light'", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["light"] = json!(0);
        }),
        (format!("{n2}/multiplier"), "multiplier", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["multiplier"] = json!(-0.5);
        }),
        (format!("{n2}/maintenanceFactor"), "(0, 1]", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["maintenanceFactor"] = json!(0);
        }),
        (format!("{n2}/maintenanceFactor"), "(0, 1]", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["maintenanceFactor"] = json!(1.25);
        }),
        (format!("{n2}/opening/height"), "height -0.1 m", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["opening"] =
                json!({"length": 1, "width": 1, "height": -0.1});
        }),
        (format!("{n2}/opening"), "'width' is missing", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["opening"] =
                json!({"length": 1, "height": 0});
        }),
        (format!("{n2}/opening"), "unknown member 'diameter'", |j| {
            j["nodes"][2]["extensions"]["LUXBAKE_luminaire"]["opening"] =
                json!({"length": 1, "width": 1, "height": 0, "diameter": 1});
        }),
        // Materials.
        (
            "/materials/0/extensions/LUXBAKE_material/emission/profile".into(),
            "/extensions/LUXBAKE_luminaire/profiles/1, which does not exist",
            |j| {
                j["materials"] = json!([{"extensions": {"LUXBAKE_material":
                    {"reflectance": 0.5, "emission": {"luminance": 10, "profile": 1}}}}]);
            },
        ),
        (
            "/materials/0/extras/luxbake/original/LUXBAKE_material/emission/profile".into(),
            "which does not exist",
            |j| {
                j["materials"] = json!([{"extras": {"luxbake": {"original": {"LUXBAKE_material":
                    {"reflectance": 0.5, "emission": {"luminance": 0, "profile": 4}}}}}}]);
            },
        ),
        (
            "/materials/0/extensions/LUXBAKE_material".into(),
            "emission.profile must be an index",
            |j| {
                j["materials"] = json!([{"extensions": {"LUXBAKE_material":
                {"reflectance": 0.5, "emission": {"luminance": 10, "profile": "a"}}}}]);
            },
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("panel.txt"), LDT).unwrap();
    for (k, (pointer, needle, edit)) in cases.into_iter().enumerate() {
        let mut b = base();
        edit(&mut b.json);
        let path = b.write_gltf(dir.path(), &format!("case{k}.gltf"), Bin::DataUri);
        assert_error(&path, &pointer, needle);
    }
}
