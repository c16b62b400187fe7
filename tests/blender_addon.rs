//! The LuxBake Blender add-on (`blender/luxbake/`) round trip, in PyPI `bpy` 5.0.1: a room built
//! in Blender by script (`blender/tests/room_roundtrip.py`: walls, a desk, an IES luminaire on an
//! Empty, a EULUMDAT profile on a spot light, an emitting panel, point and spot lights, two probe
//! Empties, a working plane) is exported by the add-on, baked by this `bake` through the
//! add-on's operator, and imported back by the add-on.
//!
//! Asserted: the export passes the Khronos glTF-Validator with 0 errors and 0 warnings and holds
//! what the panels set (`LUXBAKE_material`, `EXT_lights_ies` with the profile copied beside it,
//! the luminaire node turned so the Empty's −Z is the nadir, a profiled light's nadir its −Z,
//! the point light in cd at 683 lm/W, a photometric value as given, probe extras, the working
//! plane passed to bake); the imported `_ILLUMINANCE`/`_LUMINANCE` of every mesh equal the
//! bake's vertex values exactly (both are the same f32); every probe's readable properties
//! equal the bake's faces; glyphs are in their own collection; materials show the bake through
//! an emission shader and the display group; the operator reports a missing `bake`, bake's own
//! error line and a missing profile file (the export fails). Further tests below: the office
//! rebuilt in Blender against the sample, a render against `bake view --display`, the zip.

mod support;

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;
use support::{gltf_read, scratch, tools};

fn repo(relative: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// JSON values equal with numbers compared as f64 (Blender writes 500.0 as `500`).
fn same(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(x, y)| same(x, y))
        }
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| same(v, w)))
        }
        _ => a == b,
    }
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The blender object name of an imported node: Blender appends `.001` when the name is taken
/// (the room's own objects are still in the file).
fn node_name(blender: &str) -> &str {
    match blender.rsplit_once('.') {
        Some((base, n)) if n.len() == 3 && n.bytes().all(|b| b.is_ascii_digit()) => base,
        _ => blender,
    }
}

/// Every baked attribute of every mesh node of a bake, primitives concatenated in order.
fn baked_attributes(lit: &gltf_read::Gltf) -> BTreeMap<String, BTreeMap<String, Vec<f32>>> {
    let json = &lit.json;
    let mut out = BTreeMap::new();
    for node in json["nodes"].as_array().unwrap() {
        let Some(mesh) = node["mesh"].as_u64() else {
            continue;
        };
        let mut attrs: BTreeMap<String, Vec<f32>> = BTreeMap::new();
        for prim in json["meshes"][mesh as usize]["primitives"]
            .as_array()
            .unwrap()
        {
            for name in ["_ILLUMINANCE", "_LUMINANCE"] {
                if let Some(a) = prim["attributes"][name].as_u64() {
                    let values = lit.floats(a as usize).into_iter().map(|v| v[0]);
                    attrs.entry(name.to_string()).or_default().extend(values);
                }
            }
        }
        if !attrs.is_empty() {
            out.insert(node["name"].as_str().unwrap().to_string(), attrs);
        }
    }
    out
}

#[test]
fn room_built_in_blender_exports_bakes_and_imports_back() {
    if !tools::have_blender() || !tools::have_validator() {
        return;
    }
    let dir = scratch("blender-addon");
    let profile = repo("samples/office/profiles/miral_58w.ies");
    let report = tools::blender_run(
        &repo("blender/tests/room_roundtrip.py"),
        &[
            "--bake".as_ref(),
            env!("CARGO_BIN_EXE_bake").as_ref(),
            "--out".as_ref(),
            dir.as_os_str(),
            "--profile".as_ref(),
            profile.as_os_str(),
        ],
    );
    assert_eq!(
        report["operator"],
        serde_json::json!(["FINISHED"]),
        "{}",
        report["status"]
    );

    // The operator's errors: no bake binary, and bake's own error line.
    let missing = &report["errors"]["missing_bake"];
    assert!(missing[0].is_null(), "{missing}");
    assert!(
        missing[1].as_str().unwrap().contains("no-such-bake"),
        "{missing}"
    );
    let bad = &report["errors"]["bad_option"];
    assert!(bad[0].is_null(), "{bad}");
    assert!(bad[2].as_str().unwrap().starts_with("error:"), "{bad}");
    assert!(bad[2].as_str().unwrap().contains("--exposure"), "{bad}");

    let no_profile = &report["errors"]["missing_profile"];
    assert!(no_profile[0].is_null(), "{no_profile}");
    let message = no_profile[2].as_str().unwrap();
    assert!(!message.contains('\n'), "one line: {message}");
    assert!(
        message.contains("object downlight") && message.contains("missing.ies: no such file"),
        "{no_profile}"
    );

    // The export: valid, and what the panels set.
    let exported = dir.join("scene.gltf");
    let validation = tools::validate(&exported);
    println!(
        "validator on the add-on's export: {} errors, {} warnings, {} infos",
        validation.errors, validation.warnings, validation.infos
    );
    assert_eq!(
        (validation.errors, validation.warnings),
        (0, 0),
        "{}",
        validation.listing()
    );
    let scene = gltf_read::read(&exported).json;
    // Blender's exporter requires KHR_lights_punctual itself; the add-on's extensions never are.
    let required = scene["extensionsRequired"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    assert!(
        required.iter().all(|e| e == "KHR_lights_punctual"),
        "{required:?}"
    );
    let material = |name: &str| {
        scene["materials"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == name)
            .unwrap_or_else(|| panic!("no material {name}"))
            .clone()
    };
    for (name, want) in [
        ("floor", serde_json::json!({"reflectance": 0.3})),
        (
            "ceiling",
            serde_json::json!({"reflectance": [0.7, 0.7, 0.65]}),
        ),
        (
            "panel",
            serde_json::json!({"reflectance": 0.5,
                               "emission": {"luminance": 500.0, "color": [1.0, 0.9, 0.8]}}),
        ),
    ] {
        let got = &material(name)["extensions"]["LUXBAKE_material"];
        assert!(same(got, &want), "{name}: {got} vs {want}");
    }
    assert!(
        material("desk").get("extensions").is_none(),
        "desk: reflectance from its base colour"
    );
    assert_eq!(
        material("desk")["pbrMetallicRoughness"]["metallicFactor"],
        0
    );

    let node = |name: &str| {
        scene["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|n| n["name"] == name)
            .unwrap_or_else(|| panic!("no node {name}"))
            .clone()
    };
    let luminaire = node("downlight.luminaire");
    let want = serde_json::json!({
        "EXT_lights_ies": {"light": 0, "multiplier": 1.0, "color": [1.0, 1.0, 1.0]},
        "LUXBAKE_luminaire": {"maintenanceFactor": 0.8}});
    assert!(
        same(&luminaire["extensions"], &want),
        "{}",
        luminaire["extensions"]
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    for (got, want) in luminaire["rotation"]
        .as_array()
        .unwrap()
        .iter()
        .zip([-h, 0.0, 0.0, h])
    {
        assert!((num(got) - want).abs() < 1e-12, "{}", luminaire["rotation"]);
    }
    let lights = &scene["extensions"]["EXT_lights_ies"]["lights"];
    assert_eq!(lights[0]["uri"], "miral_58w.ies");
    assert_eq!(
        std::fs::read(dir.join("miral_58w.ies")).unwrap(),
        std::fs::read(&profile).unwrap(),
        "profile copied beside the glTF"
    );
    let punctual = scene["extensions"]["KHR_lights_punctual"]["lights"]
        .as_array()
        .unwrap();
    let light = |name: &str| {
        let found = punctual.iter().find(|l| l["name"] == name);
        found.unwrap_or_else(|| panic!("no light {name}: {punctual:?}"))
    };
    let cd = 10.0 * 683.0 / (4.0 * std::f64::consts::PI);
    assert!(
        (num(&light("bulb")["intensity"]) - cd).abs() < 1e-9 * cd,
        "{}",
        light("bulb")
    );
    assert_eq!(
        num(&light("spot")["intensity"]),
        200.0,
        "photometric value written as is"
    );
    assert_eq!(
        punctual.len(),
        2,
        "the profiled light is a luminaire, not a punctual light"
    );
    // A EULUMDAT profile on a Light: on the light's own node (its −Z already the light's).
    let washer = node("washer");
    assert!(
        washer["extensions"].get("KHR_lights_punctual").is_none(),
        "{washer}"
    );
    let want = serde_json::json!({"LUXBAKE_luminaire": {"profile": 0, "multiplier": 1.0, "color": [1.0, 1.0, 1.0]}});
    assert!(
        same(&washer["extensions"], &want),
        "{}",
        washer["extensions"]
    );
    let turn = |q: &Value, v: [f64; 3]| {
        let q: Vec<f64> = q.as_array().unwrap().iter().map(num).collect();
        let (u, w) = ([q[0], q[1], q[2]], q[3]);
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let t = cross(u, v).map(|c| 2.0 * c);
        let ut = cross(u, t);
        [0, 1, 2].map(|i| v[i] + w * t[i] + ut[i])
    };
    let nadir = turn(&washer["rotation"], [0.0, 0.0, -1.0]);
    let c0 = turn(&washer["rotation"], [1.0, 0.0, 0.0]);
    for (got, want) in nadir.iter().chain(&c0).zip([1.0, 0.0, 0.0, 0.0, 1.0, 0.0]) {
        assert!(
            (got - want).abs() < 1e-6,
            "nadir {nadir:?} (+x, east), C0 {c0:?} (+y, up)"
        );
    }
    let profiles = &scene["extensions"]["LUXBAKE_luminaire"]["profiles"];
    assert_eq!(profiles[0]["uri"], "cns70_50w.ldt");
    assert!(dir.join("cns70_50w.ldt").is_file());
    assert_eq!(node("probe_desk")["extras"]["probe"], true);
    assert_eq!(node("probe_corner")["extras"]["probe"], true);

    // The bake: the working plane from the scene's settings, the luminaire and the light found.
    let lit = gltf_read::read(&dir.join("scene-lit.gltf"));
    let summary = &lit.json["scenes"][0]["extras"]["luxbake"];
    assert_eq!(num(&summary["settings"]["workingPlane"]["spacing"]), 0.5);
    assert!((num(&summary["settings"]["workingPlane"]["height"]) - 0.8).abs() < 1e-6);
    assert_eq!(summary["settings"]["quality"], "draft");
    let sources: Vec<&str> = summary["sources"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["kind"].as_str().unwrap())
        .collect();
    assert_eq!(
        sources,
        ["point", "spot", "luminaire", "luminaire"],
        "{}",
        summary["sources"]
    );

    // Imported vertex values equal the bake's.
    let baked = baked_attributes(&lit);
    let meshes = report["meshes"].as_array().unwrap();
    let mut compared = 0usize;
    let mut worst = 0.0f64;
    for (name, attrs) in &baked {
        if name.ends_with("_glyph") {
            continue;
        }
        let mesh = meshes
            .iter()
            .find(|m| node_name(m["name"].as_str().unwrap()) == name)
            .unwrap_or_else(|| panic!("no imported mesh for node {name}"));
        for (attr, want) in attrs {
            let got = mesh["attributes"][attr]
                .as_array()
                .unwrap_or_else(|| panic!("{name}: no {attr}"));
            assert_eq!(got.len(), want.len(), "{name} {attr}");
            for (g, w) in got.iter().zip(want) {
                let d = (num(g) - f64::from(*w)).abs();
                worst = worst.max(d);
                compared += 1;
            }
        }
    }
    println!("imported vs baked vertex values: {compared} compared, max |difference| {worst:e}");
    assert!(compared > 1000, "{compared}");
    assert_eq!(worst, 0.0, "imported values differ from the bake's");

    // Probes: every probe of the bake has readable properties equal to its faces.
    let probes = report["probes"].as_array().unwrap();
    let mut probe_nodes = 0;
    let mut glyph_nodes = Vec::new();
    for n in lit.json["nodes"].as_array().unwrap() {
        let result = &n["extras"]["luxbake"];
        if result.get("glyph").is_some() {
            glyph_nodes.push(n["name"].as_str().unwrap().to_string());
        }
        let Some(faces) = result["faces"].as_object() else {
            continue;
        };
        probe_nodes += 1;
        let name = n["name"].as_str().unwrap();
        let probe = probes
            .iter()
            .find(|p| node_name(p["name"].as_str().unwrap()) == name)
            .unwrap_or_else(|| panic!("probe {name} has no properties in Blender"));
        for (face, value) in faces {
            assert_eq!(
                num(&probe["properties"][format!("E{face}_lx")]),
                num(value),
                "{name} {face}"
            );
        }
        let direct = &result["facesDirect"]["+y"];
        assert_eq!(
            num(&probe["properties"]["direct+y_lx"]),
            num(direct),
            "{name}"
        );
        let scalar = &result["metrics"]["scalar"];
        assert_eq!(
            num(&probe["properties"]["scalar_lx"]),
            num(scalar),
            "{name}"
        );
    }
    assert_eq!(probes.len(), probe_nodes);
    assert!(
        probe_nodes > 40,
        "{probe_nodes}: two node probes and the working plane"
    );
    for name in ["probe_desk", "probe_corner"] {
        assert!(
            probes
                .iter()
                .any(|p| node_name(p["name"].as_str().unwrap()) == name),
            "{name}"
        );
    }
    let mut glyphs: Vec<String> = report["glyphs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| node_name(g.as_str().unwrap()).to_string())
        .collect();
    glyphs.sort();
    glyph_nodes.sort();
    assert_eq!(
        glyphs, glyph_nodes,
        "glyphs in the collection 'LuxBake probe glyphs'"
    );

    // Display: emission through the display group; glyphs plain; Standard view; the switch.
    let materials = report["materials"].as_object().unwrap();
    for name in ["floor.001", "wall.001", "panel.001"] {
        let m = &materials[name];
        assert_eq!(m["surface"], "EMISSION", "{name}");
        let nodes: Vec<&str> = m["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap())
            .collect();
        assert!(
            nodes.contains(&"GROUP") && nodes.contains(&"VERTEX_COLOR"),
            "{name}: {nodes:?}"
        );
    }
    let glyph_material = materials
        .iter()
        .find(|(k, _)| k.starts_with("luxbake glyph"))
        .expect("a glyph material");
    assert!(
        !glyph_material.1["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|n| n == "GROUP")
    );
    assert_eq!(report["scene"]["view_transform"], "Standard");
    // The bake lives in a scene of its own, shown after the bake; the authoring scene is left
    // as it was (14 objects built, Blender's default view transform), and baking from the
    // bake's scene is refused.
    assert_eq!(report["shown"], "scene-lit");
    assert_eq!(
        report["authoring"],
        serde_json::json!({"objects": 14, "view_transform": "AgX", "bake_objects_here": 0})
    );
    assert!(
        report["from_bake_scene"][0].is_null(),
        "{}",
        report["from_bake_scene"]
    );
    assert!(
        report["from_bake_scene"][2]
            .as_str()
            .unwrap()
            .contains("holds a bake")
    );
    // Every panel drew (into a stand-in layout: no window here) with properties that exist.
    let panels = &report["panels"];
    assert!(
        num(&panels["props"]) > 500.0 && num(&panels["ramps"]) >= 2.0,
        "{panels}"
    );

    // Baked again with lightmaps: the export leaves the first bake out, and lightmapped
    // materials show the display texture on TEXCOORD_1 through the display group.
    assert_eq!(
        report["lightmapped"][0],
        serde_json::json!(["FINISHED"]),
        "{}",
        report["lightmapped"]
    );
    let second: Vec<&str> = report["second_export_nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    let first: Vec<&str> = {
        let mut v: Vec<&str> = scene["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n["name"].as_str().unwrap())
            .collect();
        v.sort();
        v
    };
    assert_eq!(second, first, "the second export holds the scene alone");
    let lightmapped = report["lightmap_materials"].as_object().unwrap();
    assert!(lightmapped.len() >= 5, "{lightmapped:?}");
    for (name, m) in lightmapped {
        let nodes: Vec<&str> = m["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap())
            .collect();
        for t in ["EMISSION", "GROUP", "TEX_IMAGE", "UVMAP"] {
            assert!(nodes.contains(&t), "{name}: {nodes:?}");
        }
        assert_eq!(m["uv_map"], "UVMap.001", "{name}: TEXCOORD_1");
        assert_eq!(
            m["has_illuminance"], true,
            "{name}: vertex values for false colour"
        );
    }
    assert_eq!(report["false_colour"]["false_colour"], 1.0);
    assert_eq!(
        report["false_colour"]["range"],
        serde_json::json!([0.0, 500.0])
    );
}

/// `bake diff --mode means --json` of two bakes: (exit code, report).
fn diff_means(a: &Path, b: &Path) -> (Option<i32>, Value) {
    let run = support::cli::bake([
        "diff".as_ref(),
        a.as_os_str(),
        b.as_os_str(),
        "--mode".as_ref(),
        "means".as_ref(),
        "--rtol".as_ref(),
        "0.005".as_ref(),
        "--json".as_ref(),
    ]);
    (
        run.code,
        serde_json::from_str(&run.stdout).expect("diff --json"),
    )
}

fn bake_ok(input: &Path, output: &Path, extra: &[&str]) {
    let mut args = vec![
        input.as_os_str(),
        "-o".as_ref(),
        output.as_os_str(),
        "-q".as_ref(),
    ];
    args.extend(extra.iter().map(|a| std::ffi::OsStr::new(*a)));
    let run = support::cli::bake(args);
    assert!(run.ok(), "bake {}: {}", input.display(), run.stderr);
}

/// samples/office rebuilt in Blender by `blender/examples/office.py` (from make_office.py's
/// numbers, through the add-on's panels and export) bakes as `samples/office/office.gltf` does
/// (default quality): `bake diff --mode means` passes at 0.5 % on every node's and material's
/// means (exit 0), and with the working plane its points agree within 0.5 % too. Individual
/// probe faces other than the working plane's `+y` may differ a little more (asserted < 1 %):
/// the adaptive mesh differs slightly (the ceiling gets 985 vertices instead of 987) — the files
/// hold the same meshes but differ in node order (Blender writes children first), f32 rounding
/// of some transforms and signed zeros, and the bake's meshing depends on the node order.
#[test]
fn office_rebuilt_in_blender_bakes_like_the_sample() {
    if !tools::have_blender() || !tools::have_validator() {
        return;
    }
    let dir = scratch("blender-addon-office");
    let report = tools::blender_run(
        &repo("blender/examples/office.py"),
        &[dir.join("blender").as_os_str()],
    );
    let rebuilt = Path::new(report["gltf"].as_str().unwrap()).to_path_buf();
    let validation = tools::validate(&rebuilt);
    assert_eq!(
        (validation.errors, validation.warnings),
        (0, 0),
        "{}",
        validation.listing()
    );

    let sample = repo("samples/office/office.gltf");
    // Same materials for viewers too: the base colours are the reflectances, as in the sample.
    let (ours, theirs) = (
        gltf_read::read(&rebuilt).json,
        gltf_read::read(&sample).json,
    );
    for m in theirs["materials"].as_array().unwrap() {
        let name = m["name"].as_str().unwrap();
        let mine = ours["materials"]
            .as_array()
            .unwrap()
            .iter()
            .find(|x| x["name"] == name);
        let mine = mine.unwrap_or_else(|| panic!("no material {name} in the rebuilt office"));
        for key in ["baseColorFactor"] {
            let (x, y) = (
                &mine["pbrMetallicRoughness"][key],
                &m["pbrMetallicRoughness"][key],
            );
            for (p, q) in x.as_array().unwrap().iter().zip(y.as_array().unwrap()) {
                assert!((num(p) - num(q)).abs() < 1e-6, "{name} {key}: {x} vs {y}");
            }
        }
        let (x, y) = (
            &mine["extensions"]["LUXBAKE_material"]["reflectance"],
            &m["extensions"]["LUXBAKE_material"]["reflectance"],
        );
        assert!((num(x) - num(y)).abs() < 1e-6, "{name}: {x} vs {y}");
    }
    let (a, b) = (dir.join("rebuilt-lit.gltf"), dir.join("sample-lit.gltf"));
    bake_ok(&rebuilt, &a, &[]);
    bake_ok(&sample, &b, &[]);
    let (code, means) = diff_means(&a, &b);
    let rel = |d: &Value, q: usize| num(&d["quantities"][q]["overall"]["rel"]["max"]);
    println!(
        "office rebuilt in Blender vs samples/office: node and material means within {:.3} % (E), {:.3} % (E direct), {:.3} % (L), {} values",
        100.0 * rel(&means, 0),
        100.0 * rel(&means, 1),
        100.0 * rel(&means, 2),
        means["values"]
    );
    assert_eq!(code, Some(0), "{}", means["worstFailure"]);
    assert!(num(&means["values"]) >= 90.0, "{}", means["values"]);

    let (wa, wb) = (dir.join("rebuilt-wp.gltf"), dir.join("sample-wp.gltf"));
    bake_ok(&rebuilt, &wa, &["--working-plane", "0.8"]);
    bake_ok(&sample, &wb, &["--working-plane", "0.8"]);
    let (_, with_plane) = diff_means(&wa, &wb);
    let plane = &with_plane["quantities"][4]["overall"];
    let faces = &with_plane["quantities"][3]["overall"];
    println!(
        "with the working plane: {} points within {:.3} %; all probe faces: max {:.3} %, mean {:.4} %, {} of {} above 0.5 %",
        plane["values"],
        100.0 * num(&plane["rel"]["max"]),
        100.0 * num(&faces["rel"]["max"]),
        100.0 * num(&faces["rel"]["mean"]),
        faces["failed"],
        faces["values"]
    );
    for q in 0..3 {
        assert!(
            rel(&with_plane, q) < 0.005,
            "{}",
            with_plane["quantities"][q]["overall"]
        );
    }
    assert!(
        num(&plane["values"]) > 600.0 && num(&plane["rel"]["max"]) < 0.005,
        "{plane}"
    );
    // Single faces differ more than means: the two files' node order moves a few of the
    // adaptive mesh's splits at the luminaires' cut-off on the walls (h/4 there), and the
    // faces beside them read the wall's patches (measured: max 1.36 %, mean 0.03 %).
    assert!(
        num(&faces["rel"]["max"]) < 0.015 && num(&faces["rel"]["mean"]) < 0.001,
        "{faces}"
    );
}

/// 8-bit RGB pixels and size of a PNG.
fn read_png(path: &Path) -> (usize, usize, Vec<u8>) {
    support::read_png(path)
}

/// Mean |a − b| over all channels (in 1/255 steps) and the share of channel values more than
/// 8/255 apart.
fn image_difference(a: &Path, b: &Path) -> (f64, f64) {
    let (wa, ha, pa) = read_png(a);
    let (wb, hb, pb) = read_png(b);
    assert_eq!((wa, ha), (wb, hb), "{} vs {}", a.display(), b.display());
    let diffs: Vec<u8> = pa.iter().zip(&pb).map(|(x, y)| x.abs_diff(*y)).collect();
    let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
    let far = diffs.iter().filter(|&&d| d > 8).count() as f64 / diffs.len() as f64;
    (mean, far)
}

/// What Blender renders of a bake imported by the add-on (Cycles, CPU, from `camera_interior`,
/// luminaire openings hidden) is what a glTF viewer shows: `bake view --display` of the same
/// bake, pixel for pixel within rounding and antialiasing. Blender's importer alone (no add-on)
/// wires base colour × `Color` too, but Blender's default view transform (AgX) shifts the tones:
/// many more values off by more than 8/255 (measured 4.9 % against 0.076 %).
#[test]
fn blender_render_of_an_imported_bake_is_what_a_viewer_shows() {
    if !tools::have_blender() {
        return;
    }
    let dir = scratch("blender-addon-render");
    let lit = dir.join("office-lit.gltf");
    bake_ok(
        &repo("samples/office/office.gltf"),
        &lit,
        &["--quality", "draft"],
    );
    let view = dir.join("view.png");
    let run = support::cli::bake([
        "view".as_ref(),
        lit.as_os_str(),
        "-o".as_ref(),
        dir.join("view.exr").as_os_str(),
        "--camera".as_ref(),
        "camera_interior".as_ref(),
        "--size".as_ref(),
        "600x400".as_ref(),
        "--display".as_ref(),
        view.as_os_str(),
    ]);
    assert!(run.ok(), "{}", run.stderr);
    let script = repo("blender/examples/render.py");
    let render = |out: &Path, extra: &[&str]| {
        let mut args = vec![lit.as_os_str(), out.as_os_str()];
        args.extend(
            ["--size", "600x400", "--samples", "16"]
                .iter()
                .map(std::ffi::OsStr::new),
        );
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let done = std::process::Command::new(bpy_python())
            .arg(&script)
            .args(&args)
            .output()
            .unwrap();
        assert!(
            done.status.success(),
            "{}",
            String::from_utf8_lossy(&done.stderr)
        );
    };
    let (addon, plain) = (dir.join("addon.png"), dir.join("plain.png"));
    render(&addon, &["--no-openings"]);
    render(&plain, &["--plain"]);
    let (mean, far) = image_difference(&addon, &view);
    let (plain_mean, plain_far) = image_difference(&plain, &view);
    println!(
        "Blender render vs bake view --display: mean |Δ| {mean:.2}/255, {:.3} % of values > 8/255; Blender's importer alone: {plain_mean:.2}/255, {:.1} %",
        100.0 * far,
        100.0 * plain_far
    );
    assert!(mean < 1.0 && far < 0.005, "{mean} {far}");
    assert!(plain_far > 10.0 * far, "{plain_far} vs {far}");
}

/// The Python that has bpy (as `support::tools` finds it).
fn bpy_python() -> std::path::PathBuf {
    std::env::var_os("LUXBAKE_BPY_PYTHON")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| repo(".venv-bpy/bin/python"))
}

/// Installing is one step: `blender/build_extension.py` builds the zip with Blender's own
/// extension builder, and Blender's "Install from Disk" (`extensions.package_install_files`,
/// into a scratch user folder) installs and enables it as the extension
/// `bl_ext.user_default.luxbake`, whose hooks then act on Blender's plain glTF export (which
/// refuses a profile on a Light while its Punctual Lights option is off, instead of losing it).
#[test]
fn extension_zip_installs_and_exports() {
    if !tools::have_blender() {
        return;
    }
    let dir = scratch("blender-addon-zip");
    let built = std::process::Command::new(bpy_python())
        .arg(repo("blender/build_extension.py"))
        .arg("--output-dir")
        .arg(dir.join("dist"))
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let zip = String::from_utf8(built.stdout).unwrap().trim().to_string();
    assert!(
        zip.ends_with("luxbake-0.1.0.zip") && Path::new(&zip).is_file(),
        "{zip}"
    );

    let user = dir.join("user");
    let out = dir.join("out");
    std::fs::create_dir_all(&user).unwrap();
    std::fs::create_dir_all(&out).unwrap();
    let run = std::process::Command::new(bpy_python())
        .env("BLENDER_USER_RESOURCES", &user)
        .arg(repo("blender/tests/install_zip.py"))
        .arg(&zip)
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report: Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(report["install"], serde_json::json!(["FINISHED"]));
    assert_eq!(
        report["modules"],
        serde_json::json!(["bl_ext.user_default.luxbake"])
    );
    assert_eq!(report["operators"], true);
    assert!(same(
        &report["material"]["extensions"]["LUXBAKE_material"],
        &serde_json::json!({"reflectance": 0.4})
    ));
    assert_eq!(report["probe"], serde_json::json!({"probe": true}));
    assert!(
        user.join("extensions/user_default/luxbake/blender_manifest.toml")
            .is_file()
    );
}

/// The Bake operator's interactive path (timer → modal), driven by hand in
/// `blender/tests/modal_bake.py` (no event loop in a script): while bake runs the status shows
/// "luxbake: baking N s" and bake's latest stderr line (bake behind a wrapper script that writes
/// a line first); at the end the bake is imported into its
/// own scene, which the window shows, and bake's warnings are reported.
#[test]
fn operator_shows_progress_and_ends_in_the_bake() {
    if !tools::have_blender() {
        return;
    }
    let dir = scratch("blender-addon-modal");
    // bake behind a wrapper that says something on stderr and waits a second first, so the
    // polls surely see a line while bake runs
    let wrapper = dir.join("slow-bake");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/sh\necho 'wrapper: starting' >&2\nsleep 1\nexec '{}' \"$@\"\n",
            env!("CARGO_BIN_EXE_bake")
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();
    let report = tools::blender_run(
        &repo("blender/tests/modal_bake.py"),
        &[
            "--bake".as_ref(),
            wrapper.as_os_str(),
            "--out".as_ref(),
            dir.as_os_str(),
        ],
    );
    assert_eq!(
        report["result"],
        serde_json::json!(["FINISHED"]),
        "{report}"
    );
    let statuses = report["statuses"].as_array().unwrap();
    assert!(!statuses.is_empty(), "{report}");
    assert!(
        statuses
            .iter()
            .all(|s| s.as_str().unwrap().starts_with("luxbake: baking")),
        "{report}"
    );
    assert!(
        statuses
            .iter()
            .any(|s| s.as_str().unwrap().ends_with(" s  wrapper: starting")),
        "bake's stderr shown: {report}"
    );
    assert_eq!(report["shown"], "scene-lit");
    assert_eq!(report["scenes"], serde_json::json!(["Scene", "scene-lit"]));
    assert!(
        report["final_status"]
            .as_str()
            .unwrap()
            .starts_with("baked in"),
        "{report}"
    );
    let reports = report["reports"].as_array().unwrap();
    assert!(
        reports
            .iter()
            .any(|r| r[0][0] == "WARNING" && r[1].as_str().unwrap().contains("no material")),
        "{report}"
    );
}
