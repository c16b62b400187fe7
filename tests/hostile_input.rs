//! Careless and hostile input (issue 25): numbers that are not finite or overflow, geometry without
//! area, values outside the spec's ranges and flags of the wrong type. Each gives a clear error
//! naming the file, the element and the value (exit 1, nothing written), or a warning and a
//! correct bake; `bake diff` fails on any non-finite value. The inputs are small variations of the
//! valid scene of `support::cli` (a floor under an emissive panel).

mod support;

use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use support::cli::{Mini, Run, assert_error_line, bake, bake_draft_into, listing};
use support::{bakes, in_out};

/// A test's folders: `in/` for the input, `out/` (empty) for the output.
fn folders(name: &str) -> (PathBuf, PathBuf) {
    in_out(&format!("hostile-{name}"))
}

/// The minimal scene with `edit` applied to its JSON, written as `in/name` (buffer as data URI).
fn variant(input: &Path, name: &str, edit: impl FnOnce(&mut Value)) -> PathBuf {
    let mut mini = Mini::new();
    edit(&mut mini.json);
    mini.write_gltf(input, name, None)
}

/// Exit code 1, one `error:` line holding every needle, nothing written to `out`.
fn assert_refused(run: &Run, out: &Path, needles: &[&str]) {
    assert_eq!(run.code, Some(1), "{run:?}");
    assert_error_line(run, needles);
    assert_eq!(
        listing(out),
        Vec::<String>::new(),
        "output folder not empty"
    );
}

/// Exit 0 and a `warning:` line holding every needle.
fn assert_warned(run: &Run, needles: &[&str]) {
    assert!(run.ok(), "{run:?}");
    let found = run
        .stderr
        .lines()
        .any(|l| l.contains("warning") && needles.iter().all(|n| l.contains(n)));
    assert!(
        found,
        "expected a warning with {needles:?} in:\n{}",
        run.stderr
    );
}

/// A third mesh (node "extra", material 0) with the given positions and u16 indices, appended
/// to the buffer as data of its own.
fn add_mesh(mini: &mut Mini, positions: &[[f32; 3]], indices: &[u16], node: Value) {
    let start = mini.bin.len();
    mini.bin
        .extend(positions.iter().flatten().flat_map(|v| v.to_le_bytes()));
    let index_start = mini.bin.len();
    mini.bin
        .extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    while !mini.bin.len().is_multiple_of(4) {
        mini.bin.push(0);
    }
    let j = &mut mini.json;
    let views = j["bufferViews"].as_array_mut().unwrap();
    views.push(json!({"buffer": 0, "byteOffset": start, "byteLength": positions.len() * 12}));
    views.push(json!({"buffer": 0, "byteOffset": index_start, "byteLength": indices.len() * 2}));
    let (pv, iv) = (views.len() - 2, views.len() - 1);
    let accessors = j["accessors"].as_array_mut().unwrap();
    let fold = |f: fn(f32, f32) -> f32, init: f32| {
        (0..3)
            .map(|c| positions.iter().fold(init, |a, v| f(a, v[c])))
            .collect::<Vec<f32>>()
    };
    accessors.push(json!({"bufferView": pv, "componentType": 5126, "count": positions.len(),
        "type": "VEC3", "min": fold(f32::min, f32::INFINITY), "max": fold(f32::max, f32::NEG_INFINITY)}));
    accessors.push(
        json!({"bufferView": iv, "componentType": 5123, "count": indices.len(),
        "type": "SCALAR"}),
    );
    let (pa, ia) = (accessors.len() - 2, accessors.len() - 1);
    let meshes = j["meshes"].as_array_mut().unwrap();
    meshes.push(
        json!({"name": "extra", "primitives": [{"attributes": {"POSITION": pa},
        "indices": ia, "material": 0}]}),
    );
    let mesh = meshes.len() - 1;
    let mut node = node;
    node["mesh"] = json!(mesh);
    let nodes = j["nodes"].as_array_mut().unwrap();
    nodes.push(node);
    let n = nodes.len() - 1;
    j["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(n));
}

const QUAD: [[f32; 3]; 4] = [
    [-0.5, 0.5, -0.5],
    [0.5, 0.5, -0.5],
    [0.5, 0.5, 0.5],
    [-0.5, 0.5, 0.5],
];

#[test]
fn a_primitive_without_area_is_dropped_with_a_warning() {
    let (input, out) = folders("zero-area");
    // Two triangles on one line and one on a point: all without area.
    let line = [
        [0.0, 0.5, 0.0],
        [0.2, 0.5, 0.0],
        [0.4, 0.5, 0.0],
        [0.1, 0.5, 0.0],
    ];
    let mut mini = Mini::new();
    add_mesh(
        &mut mini,
        &line,
        &[0, 1, 2, 3, 3, 3],
        json!({"name": "extra"}),
    );
    let path = mini.write_gltf(&input, "flat.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &[
            "flat.gltf",
            "/meshes/2/primitives/0",
            "extra",
            "none of its 2 triangles",
        ],
    );
    let doc: Value = serde_json::from_slice(&std::fs::read(out.join("lit.gltf")).unwrap()).unwrap();
    assert!(doc["nodes"][2].get("mesh").is_none(), "{}", doc["nodes"][2]);
    assert!(doc["nodes"][0].get("mesh").is_some());

    // Some triangles of a primitive without area: those are dropped, the rest baked.
    let (input, out) = folders("some-zero-area");
    let mut mini = Mini::new();
    add_mesh(
        &mut mini,
        &QUAD,
        &[0, 1, 2, 0, 2, 3, 0, 0, 1],
        json!({"name": "extra"}),
    );
    let path = mini.write_gltf(&input, "some.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &[
            "some.gltf",
            "/meshes/2/primitives/0",
            "1 of its 3 triangles",
        ],
    );
    let doc: Value = serde_json::from_slice(&std::fs::read(out.join("lit.gltf")).unwrap()).unwrap();
    assert!(doc["nodes"][2].get("mesh").is_some(), "{}", doc["nodes"][2]);
}

#[test]
fn a_node_scaled_to_zero_is_dropped_and_a_scene_left_empty_is_an_error() {
    let (input, out) = folders("scale-zero");
    let mut mini = Mini::new();
    add_mesh(
        &mut mini,
        &QUAD,
        &[0, 1, 2, 0, 2, 3],
        json!({"name": "flat", "scale": [1, 0, 1]}),
    );
    let path = mini.write_gltf(&input, "scaled.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &["scaled.gltf", "flat", "/nodes/2", "singular", "dropped"],
    );

    let (input, out) = folders("all-zero");
    let path = variant(&input, "nothing.gltf", |j| {
        j["nodes"][0]["scale"] = json!([0, 0, 0]);
        j["nodes"][1]["scale"] = json!([0, 0, 0]);
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(&run, &out, &["nothing.gltf", "nothing is left to bake"]);
}

#[test]
fn a_triangle_list_whose_length_is_not_a_multiple_of_three_is_refused() {
    let (input, out) = folders("index-count");
    let path = variant(&input, "count.gltf", |j| {
        j["accessors"][2]["count"] = json!(5)
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &[
            "count.gltf",
            "/meshes/0/primitives/0/indices",
            "/accessors/2",
            "5 elements",
        ],
    );
    // Not indexed: POSITION's count.
    let (input, out) = folders("vertex-count");
    let path = variant(&input, "count.gltf", |j| {
        j["meshes"][0]["primitives"][0]
            .as_object_mut()
            .unwrap()
            .remove("indices");
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &["/meshes/0/primitives/0/attributes/POSITION", "4 elements"],
    );
}

#[test]
fn factors_outside_the_spec_ranges_are_refused() {
    for (pointer, value, needle) in [
        ("/materials/0/emissiveFactor", json!([2.0, 0.0, 0.0]), "2.0"),
        (
            "/materials/0/pbrMetallicRoughness/baseColorFactor",
            json!([0.5, 0.5, 1.5, 1.0]),
            "1.5",
        ),
        (
            "/materials/0/pbrMetallicRoughness/roughnessFactor",
            json!(-0.5),
            "-0.5",
        ),
    ] {
        let (input, out) = folders("factors");
        let path = variant(&input, "factor.gltf", |j| {
            let (parent, key) = pointer.rsplit_once('/').unwrap();
            let parent = parent.strip_prefix("/materials/0").unwrap();
            let m = &mut j["materials"][0];
            let target = if parent.is_empty() {
                m
            } else {
                &mut m[parent.trim_start_matches('/')]
            };
            target[key] = value.clone();
        });
        let run = bake_draft_into(&path, &out, &[] as &[&str]);
        assert_refused(&run, &out, &["factor.gltf", pointer, needle, "in [0, 1]"]);
    }
}

#[test]
fn a_probe_flag_of_the_wrong_type_is_refused() {
    let (input, out) = folders("probe-yes");
    let path = variant(&input, "probe.gltf", |j| {
        j["nodes"][0]["extras"] = json!({"probe": "yes"});
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &["probe.gltf", "/nodes/0/extras/probe", "\"yes\""],
    );
}

#[test]
fn positions_beyond_any_room_are_refused_and_far_probes_warned() {
    let (input, out) = folders("probe-far");
    let path = variant(&input, "far.gltf", |j| {
        j["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!({"name": "p", "translation": [1e30, 1.0, 0.0], "extras": {"probe": true}}));
        j["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!(2));
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(&run, &out, &["far.gltf", "/nodes/2", "x = 1e30"]);

    // Scaled into overflow: the floor's world positions are beyond any room.
    let (input, out) = folders("scale-huge");
    let path = variant(&input, "huge.gltf", |j| {
        j["nodes"][0]["scale"] = json!([1e30, 1.0, 1.0]);
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &["huge.gltf", "/meshes/0/primitives/0", "floor", "1e30"],
    );

    let (input, out) = folders("probe-outside");
    let path = variant(&input, "outside.gltf", |j| {
        j["nodes"].as_array_mut().unwrap().push(
            json!({"name": "p", "translation": [100.0, 1.0, 0.0], "extras": {"probe": true}}),
        );
        j["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!(2));
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &["outside.gltf", "probe p", "outside the scene's geometry"],
    );
}

#[test]
fn emitters_beyond_any_lamp_are_refused() {
    type Case<'a> = (&'a str, Box<dyn Fn(&mut Value)>, &'a [&'a str]);
    let cases: [Case; 3] = [
        (
            "flux",
            Box::new(|j| {
                j["materials"][1]["extensions"]["LUXBAKE_material"]["emission"] =
                    json!({"luminousFlux": 1e300})
            }),
            &["/materials/1", "luminous flux (lm) 1e300"],
        ),
        (
            "luminance",
            Box::new(|j| {
                j["materials"][1]["extensions"]["LUXBAKE_material"]["emission"] =
                    json!({"luminance": 1e13})
            }),
            &["/materials/1", "luminance (cd/m²) 1e13"],
        ),
        (
            "light",
            Box::new(|j| {
                j["extensionsUsed"] = json!(["LUXBAKE_material", "KHR_lights_punctual"]);
                j["extensions"] = json!({"KHR_lights_punctual": {"lights":
                    [{"type": "point", "intensity": 1e30}]}});
                j["nodes"][1]["extensions"] = json!({"KHR_lights_punctual": {"light": 0}});
            }),
            &["/extensions/KHR_lights_punctual/lights/0", "1e30 cd"],
        ),
    ];
    for (name, edit, needles) in cases {
        let (input, out) = folders(&format!("emitter-{name}"));
        let path = variant(&input, "bright.gltf", |j| edit(j));
        let run = bake_draft_into(&path, &out, &[] as &[&str]);
        let mut all = vec!["bright.gltf"];
        all.extend_from_slice(needles);
        assert_refused(&run, &out, &all);
    }
}

/// The input limits hold at their edges, not only far past them: a probe at 0.99 × 10⁷ m is
/// taken (and warned about), at 1.01 × 10⁷ m refused; an emitting surface of 10¹² cd/m² bakes,
/// 1.01 × 10¹² is refused.
#[test]
fn input_limits_hold_at_their_edges() {
    let probe_at = |x: f64| {
        move |j: &mut Value| {
            j["nodes"].as_array_mut().unwrap().push(
                json!({"name": "p", "translation": [x, 1.0, 0.0], "extras": {"probe": true}}),
            );
            j["scenes"][0]["nodes"]
                .as_array_mut()
                .unwrap()
                .push(json!(2));
        }
    };
    let (input, out) = folders("limit-coordinate-in");
    let path = variant(&input, "near.gltf", probe_at(0.99e7));
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert!(run.ok(), "{}", run.stderr);
    assert_warned(
        &run,
        &["near.gltf", "probe p", "outside the scene's geometry"],
    );
    let (input, out) = folders("limit-coordinate-out");
    let path = variant(&input, "beyond.gltf", probe_at(1.01e7));
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(&run, &out, &["beyond.gltf", "/nodes/2", "x = 1.01e7"]);

    let luminance = |l: f64| {
        move |j: &mut Value| {
            j["materials"][1]["extensions"]["LUXBAKE_material"]["emission"] =
                json!({ "luminance": l })
        }
    };
    let (input, out) = folders("limit-luminance-in");
    let path = variant(&input, "bright.gltf", luminance(1e12));
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert!(run.ok(), "{}", run.stderr);
    let (input, out) = folders("limit-luminance-out");
    let path = variant(&input, "brighter.gltf", luminance(1.01e12));
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &["brighter.gltf", "/materials/1", "luminance (cd/m²) 1.01e12"],
    );
}

/// A tiny IES LM-63-2002 file whose candela multiplier is `multiplier`.
fn ies(multiplier: &str) -> String {
    format!(
        "IESNA:LM-63-2002\r\n[TEST] hostile\r\nTILT=NONE\r\n1 1000 {multiplier} 3 1 1 2 0.6 0.6 0\r\n\
         1 1 10\r\n0 45 90\r\n0\r\n300 200 0\r\n"
    )
}

#[test]
fn overflowing_profiles_are_refused_by_bake_and_by_luminaire() {
    let (input, out) = folders("ies-overflow");
    std::fs::write(input.join("huge.ies"), ies("1e308")).unwrap();
    let run = bake(["luminaire".as_ref(), input.join("huge.ies").as_os_str()]);
    assert_eq!(run.code, Some(1), "{run:?}");
    assert!(
        run.stderr.contains("huge.ies") && run.stderr.contains("not a finite"),
        "{run:?}"
    );
    assert!(!run.stdout.contains("inf"), "{run:?}");

    // A finite profile times a glTF multiplier beyond any lamp.
    std::fs::write(input.join("ok.ies"), ies("1")).unwrap();
    let path = variant(&input, "lum.gltf", |j| {
        j["extensionsUsed"] = json!(["LUXBAKE_material", "EXT_lights_ies"]);
        j["extensions"] = json!({"EXT_lights_ies": {"lights": [{"uri": "ok.ies"}]}});
        j["nodes"][1]["extensions"] = json!({"EXT_lights_ies": {"light": 0, "multiplier": 1e306}});
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(&run, &out, &["lum.gltf", "/nodes/1", "multiplier 1e306"]);
}

#[test]
fn diff_fails_on_infinity_on_either_side() {
    let (input, out) = folders("diff-inf");
    let path = variant(&input, "room.gltf", |_| {});
    let (a, b) = (out.join("a"), out.join("b"));
    for d in [&a, &b] {
        std::fs::create_dir(d).unwrap();
        let run = bake([
            path.as_os_str(),
            "-o".as_ref(),
            d.join("lit.gltf").as_os_str(),
            "--quality".as_ref(),
            "draft".as_ref(),
            "--quiet".as_ref(),
        ]);
        assert!(run.ok(), "{run:?}");
    }
    let (ga, gb) = (a.join("lit.gltf"), b.join("lit.gltf"));
    assert_eq!(bakes::diff(&ga, &gb, &[]).code, Some(0));
    bakes::edit(&gb, "floor", 0, 0, f32::INFINITY);
    let run = bakes::diff(&ga, &gb, &[]);
    assert_eq!(run.code, Some(1), "B holds +inf: {run:?}");
    bakes::edit(&ga, "floor", 0, 0, f32::INFINITY);
    let run = bakes::diff(&ga, &gb, &[]);
    assert_eq!(run.code, Some(1), "both hold +inf: {run:?}");
}

#[test]
fn quantized_and_sparse_positions_bake_like_plain_ones() {
    // The floor's positions as normalised shorts (KHR_mesh_quantization) and as a sparse accessor
    // without a bufferView: the same floor, the same light on it.
    let (input, out) = folders("plain");
    let plain = variant(&input, "plain.gltf", |_| {});
    let run = bake_draft_into(&plain, &out, &["--quiet"]);
    assert!(run.ok(), "{run:?}");
    let reference = bakes::node_mean(&out.join("lit.gltf"), "floor");
    assert!(reference > 1.0, "{reference}");

    let corners: [[i16; 3]; 4] = [
        [-32767, 0, -32767],
        [-32767, 0, 32767],
        [32767, 0, 32767],
        [32767, 0, -32767],
    ];
    let mut quantized = Mini::new();
    let start = quantized.bin.len();
    for c in corners {
        quantized.bin.extend(c.iter().flat_map(|v| v.to_le_bytes()));
        quantized.bin.extend([0, 0]); // each element padded to 4-byte alignment
    }
    let j = &mut quantized.json;
    j["bufferViews"].as_array_mut().unwrap().push(
        json!({"buffer": 0, "byteOffset": start, "byteLength": 32, "byteStride": 8, "target": 34962}),
    );
    j["accessors"][0] = json!({"bufferView": 4, "componentType": 5122, "normalized": true,
        "count": 4, "type": "VEC3", "min": [-32767, 0, -32767], "max": [32767, 0, 32767]});
    j["extensionsUsed"] = json!(["LUXBAKE_material", "KHR_mesh_quantization"]);
    j["extensionsRequired"] = json!(["KHR_mesh_quantization"]);

    let mut sparse = Mini::new();
    let start = sparse.bin.len();
    sparse.bin.extend([0u8, 1, 2, 3]);
    let j = &mut sparse.json;
    j["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 0, "byteOffset": start, "byteLength": 4}));
    j["accessors"][0] = json!({"componentType": 5126, "count": 4, "type": "VEC3",
        "min": [-1, 0, -1], "max": [1, 0, 1],
        "sparse": {"count": 4, "indices": {"bufferView": 4, "componentType": 5121},
                   "values": {"bufferView": 0}}});

    for (name, mini) in [("quantized", quantized), ("sparse", sparse)] {
        let (input, out) = folders(name);
        let path = mini.write_gltf(&input, &format!("{name}.gltf"), None);
        let run = bake_draft_into(&path, &out, &["--quiet"]);
        assert!(run.ok(), "{name}: {run:?}");
        let mean = bakes::node_mean(&out.join("lit.gltf"), "floor");
        assert!(
            (mean - reference).abs() <= 1e-3 * reference,
            "{name}: {mean} vs {reference}"
        );
    }
}

#[test]
fn missing_materials_are_warned_about() {
    // OBJ: a `usemtl` naming no material of the MTL file (docs/inputs.md promises a warning).
    let (input, out) = folders("usemtl");
    std::fs::write(input.join("room.mtl"), "newmtl floor\nKd 0.5 0.5 0.5\n").unwrap();
    let obj = "mtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 1 0\nv 1 1 0\nv 1 1 1\n\
               o floor\nusemtl floor\nf 1 3 2\no shelf\nusemtl flor\nf 4 5 6\n";
    let path = input.join("room.obj");
    std::fs::write(&path, obj).unwrap();
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &[
            "room.obj line 12",
            "usemtl 'flor'",
            "default reflectance 0.5",
        ],
    );

    // glTF: a primitive without a material.
    let (input, out) = folders("no-material");
    let path = variant(&input, "bare.gltf", |j| {
        j["meshes"][0]["primitives"][0]
            .as_object_mut()
            .unwrap()
            .remove("material");
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &[
            "bare.gltf",
            "1 primitive(s) have no material",
            "/meshes/0/primitives/0",
        ],
    );
}

#[test]
fn a_working_plane_target_without_a_working_plane_is_refused_before_baking() {
    let (input, out) = folders("plane-target");
    let path = variant(&input, "room.gltf", |_| {});
    let targets = input.join("targets.json");
    std::fs::write(&targets, r#"{"working_plane": 500}"#).unwrap();
    let run = bake_draft_into(&path, &out, &["--targets", targets.to_str().unwrap()]);
    assert_refused(
        &run,
        &out,
        &["targets.json", "working_plane", "--working-plane"],
    );
}

#[test]
fn a_large_energy_balance_error_is_loud() {
    // A 100 cd point light 1 m over a 0.4 m square floor: almost all light escapes and the
    // escape estimate's error leaves 0.34 % of the flux unaccounted for. Any balance error above
    // 1e-3 must come with a warning (issue 25 saw 10 % printed without one).
    let (input, out) = folders("balance");
    let s = 0.2;
    let mut mini = Mini::with_floor([[-s, 0.0, -s], [-s, 0.0, s], [s, 0.0, s], [s, 0.0, -s]]);
    let j = &mut mini.json;
    j["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    j["extensions"] =
        json!({"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 100.0}]}});
    j["nodes"][1] = json!({"name": "lamp", "translation": [0.013, 1.0, 0.007],
        "extensions": {"KHR_lights_punctual": {"light": 0}}});
    j["meshes"].as_array_mut().unwrap().truncate(1);
    j["accessors"].as_array_mut().unwrap().truncate(3);
    let path = mini.write_gltf(&input, "lamp.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert!(run.ok(), "{run:?}");
    let printed: f64 = run
        .stderr
        .split("balance error ")
        .last()
        .and_then(|s| s.split(';').next())
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or_else(|| panic!("no balance error in:\n{}", run.stderr));
    assert!(
        printed > 1e-3,
        "this scene no longer has a large balance error ({printed:e}): pick one that does"
    );
    assert_warned(
        &run,
        &["energy balance error", "above 1e-3", "unaccounted for"],
    );

    // Below the threshold (the minimal scene at default quality, 5.7e-4): no warning.
    let (input, out) = folders("balance-ok");
    let path = variant(&input, "room.gltf", |_| {});
    let output = out.join("lit.gltf");
    let run = bake([path.as_os_str(), "-o".as_ref(), output.as_os_str()]);
    assert!(run.ok() && !run.stderr.contains("warning"), "{run:?}");
}

#[test]
fn a_ground_plane_that_sets_the_patch_size_is_warned_about() {
    // A 2 km ground under a 0.5 m panel: the default patch size follows the ground's area.
    let (input, out) = folders("ground");
    let g = 1000.0;
    let mini = Mini::with_floor([[-g, 0.0, -g], [-g, 0.0, g], [g, 0.0, g], [g, 0.0, -g]]);
    let path = mini.write_gltf(&input, "ground.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &[
            "node 'floor'",
            "/meshes/0/primitives/0",
            "100.0 % of the scene's area",
            "--patch-size",
        ],
    );
    // With --patch-size given there is nothing to warn about.
    let (_, out) = folders("ground-given");
    let run = bake_draft_into(&path, &out, &["--patch-size", "100"]);
    assert!(run.ok() && !run.stderr.contains("area"), "{run:?}");
}

#[test]
fn usage_errors_exit_2_and_input_errors_exit_1() {
    let (input, out) = folders("exit-codes");
    let path = variant(&input, "room.gltf", |_| {});
    for extra in [
        &["--patch-size", "-1"][..],
        &["--probe-height", "1"],
        &["--working-plane-spacing", "0.5"],
        &["--exposure", "bright"],
        &["--max-patches", "0"],
        &["--no-such-option"],
    ] {
        let run = bake_draft_into(&path, &out, extra);
        assert_eq!(run.code, Some(2), "{extra:?}: {run:?}");
        assert!(run.stderr.starts_with("error: "), "{run:?}");
        assert!(listing(&out).is_empty());
    }
    let missing = input.join("missing.gltf");
    let run = bake_draft_into(&missing, &out, &[] as &[&str]);
    assert_refused(&run, &out, &["missing.gltf"]);
}

#[test]
fn a_material_black_only_because_metallic_defaulted_is_warned_about() {
    // docs/inputs.md promises it: metallicFactor absent defaults to 1 (metal), reflectance 0.
    let (input, out) = folders("metallic");
    let path = variant(&input, "metal.gltf", |j| {
        j["materials"][0]["pbrMetallicRoughness"]
            .as_object_mut()
            .unwrap()
            .remove("metallicFactor");
    });
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_warned(
        &run,
        &[
            "/materials/0",
            "metallicFactor is not given",
            "defaults to 1",
        ],
    );
}

/// Every input a subcommand reads, linked to `/dev/zero` (endless) or a FIFO (no writer), is
/// refused at once, naming the file, instead of being read until memory runs out.
#[cfg(unix)]
#[test]
fn devices_and_fifos_are_refused_as_inputs() {
    let (input, out) = folders("devices");
    let scene = Mini::new().write_gltf(&input, "room.gltf", None);
    let link = |name: &str| {
        let path = input.join(name);
        std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
        path.to_str().unwrap().to_string()
    };
    let fifo = input.join("pipe.gltf");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
    let (scene, o) = (scene.to_str().unwrap(), out.join("lit.glb"));
    let o = o.to_str().unwrap();
    let cases: Vec<(Vec<String>, String)> = vec![
        (vec![link("z.gltf"), "-o".into(), o.into()], "z.gltf".into()),
        (vec![link("z.glb"), "-o".into(), o.into()], "z.glb".into()),
        (vec![link("z.obj"), "-o".into(), o.into()], "z.obj".into()),
        (
            vec![fifo.to_str().unwrap().into(), "-o".into(), o.into()],
            "pipe.gltf".into(),
        ),
        (vec!["luminaire".into(), link("z.ies")], "z.ies".into()),
        (vec!["design".into(), link("z.csv")], "z.csv".into()),
        (
            vec![
                scene.into(),
                "-o".into(),
                o.into(),
                "--targets".into(),
                link("t.json"),
            ],
            "t.json".into(),
        ),
        (
            vec![
                scene.into(),
                "-o".into(),
                o.into(),
                "--probes".into(),
                link("p.csv"),
            ],
            "p.csv".into(),
        ),
    ];
    for (args, name) in cases {
        let start = std::time::Instant::now();
        let run = bake(&args);
        assert!(
            start.elapsed().as_secs() < 20,
            "{args:?} took {:?}",
            start.elapsed()
        );
        assert_refused(&run, &out, &[&name, "not a regular file"]);
    }
}

/// The later subcommands never write over a file they read (issue 59): `view -o` naming the
/// bake's own lightmap EXR and `report -o` naming its targets file are refused (exit 1), a
/// report named like the EXR is refused by its extension (exit 2), and the files keep their
/// bytes.
#[test]
fn report_and_view_refuse_to_overwrite_the_files_they_read() {
    let (input, out) = folders("overwrite-read");
    let office = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/office/office.gltf");
    let lit = out.join("lit.gltf");
    let run = bake([
        office.to_str().unwrap(),
        "-o",
        lit.to_str().unwrap(),
        "-q",
        "--quality",
        "draft",
        "--lightmaps",
        "--texel-size",
        "0.1",
    ]);
    assert!(run.ok(), "{}", run.stderr);
    let exr = (std::fs::read_dir(&out).unwrap())
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "exr"))
        .expect("a lightmap EXR");
    let targets = input.join("targets.json");
    std::fs::write(&targets, r#"{"floor": 100}"#).unwrap();
    let before = (
        std::fs::read(&exr).unwrap(),
        std::fs::read(&targets).unwrap(),
    );
    let (l, e, t) = (
        lit.to_str().unwrap(),
        exr.to_str().unwrap(),
        targets.to_str().unwrap(),
    );
    let cases: [Vec<&str>; 2] = [
        vec!["view", l, "--camera", "camera_interior", "-o", e],
        vec!["report", l, "--targets", t, "-o", t],
    ];
    for args in cases {
        let run = bake(&args);
        assert_eq!(run.code, Some(1), "{args:?}: {run:?}");
        assert_error_line(&run, &["refusing to overwrite an input file"]);
    }
    // A report is never an .exr: refused by its extension (a usage error) before anything.
    let run = bake(["report", l, "--format", "html", "-o", e]);
    assert_eq!(run.code, Some(2), "{run:?}");
    let after = (
        std::fs::read(&exr).unwrap(),
        std::fs::read(&targets).unwrap(),
    );
    assert!(before == after, "an input was overwritten");
}

/// Numbers that would overflow or exhaust memory are refused up front (issue 59): a design row
/// whose products overflow (exit 1, naming the line), `view --steps 10⁸` (its legend would take
/// 255 GB) and `view --near -1` (exit 2, naming the option); a glTF starting with a UTF-8
/// byte-order mark is read, with a warning.
#[test]
fn overflowing_design_rows_huge_steps_and_negative_near_are_refused_and_a_bom_is_read() {
    let (input, out) = folders("numbers-59");
    let csv = input.join("d.csv");
    std::fs::write(
        &csv,
        "name,area_m2,reflectance,illuminance_lx\nFloor,1e308,0.9,1e300\n",
    )
    .unwrap();
    let run = bake(["design", csv.to_str().unwrap()]);
    assert_refused(&run, &out, &["d.csv", "line 2", "area_m2"]);
    std::fs::write(
        &csv,
        "name,area_m2,reflectance,illuminance_lx\nFloor,10,0.5,1e300\n",
    )
    .unwrap();
    let run = bake(["design", csv.to_str().unwrap()]);
    assert_refused(&run, &out, &["d.csv", "line 2", "illuminance_lx"]);
    let view = |extra: &[&str]| {
        let mut a = vec!["view", "lit.gltf", "--camera", "c", "-o", "v.exr"];
        a.extend_from_slice(extra);
        bake(a)
    };
    let run = view(&["--false-colour", "f.png", "--steps", "100000000"]);
    assert_eq!(run.code, Some(2), "{run:?}");
    assert_error_line(&run, &["--steps", "0..=64"]);
    let run = view(&["--near", "-1"]);
    assert_eq!(run.code, Some(2), "{run:?}");
    assert_error_line(&run, &["--near -1", "≥ 0"]);

    let plain = Mini::new().write_gltf(&input, "plain.gltf", None);
    let mut bytes = b"\xEF\xBB\xBF".to_vec();
    bytes.extend(std::fs::read(&plain).unwrap());
    let bom = input.join("bom.gltf");
    std::fs::write(&bom, bytes).unwrap();
    let lit = out.join("lit.glb");
    let run = bake([
        bom.to_str().unwrap(),
        "-o",
        lit.to_str().unwrap(),
        "--quality",
        "draft",
    ]);
    assert_warned(&run, &["byte-order mark"]);
    assert!(lit.exists());
}
