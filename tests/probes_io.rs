//! Probe input and output: the `--probes` CSV parser, the probe nodes and glyphs in the glTF
//! (Khronos validator, Blender import), `--probes-out` (.json, .csv) against the glTF extras,
//! grid points inside objects, node probes of a Blender-made file, and the errors of the probe
//! options. Bakes use `--quality draft`.

mod support;

use luxbake::probes::{ProbeOrigin, csv};
use serde_json::{Value, json};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use support::cli::{Mini, Run, bake_draft, listing, repo_file};
use support::gltf_read::{self, Gltf};
use support::{scratch, tools};

const FACES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

fn os<S: AsRef<OsStr> + ?Sized>(s: &S) -> &OsStr {
    s.as_ref()
}

// ---- the CSV parser -------------------------------------------------------------------------

#[test]
fn csv_good_file_with_header_comments_and_names() {
    let text = "\u{feff}# probes for the office\r\n\
                x, y, z, name\r\n\
                \r\n\
                1.5, 1.2, 2.2, \"beside the desk\"  # quoted name\r\n\
                2.5,1.2,4\n\
                -1e-1, 0.8, 3.25, window\n";
    let p = csv::parse(text).unwrap();
    let got: Vec<(&str, [f64; 3], usize)> = p
        .iter()
        .map(|p| {
            let ProbeOrigin::File { line } = p.origin else {
                panic!("{:?}", p.origin)
            };
            (p.name.as_str(), p.position.to_array(), line)
        })
        .collect();
    assert_eq!(
        got,
        [
            ("beside the desk", [1.5, 1.2, 2.2], 4),
            ("probe_5", [2.5, 1.2, 4.0], 5),
            ("window", [-0.1, 0.8, 3.25], 6),
        ]
    );
    assert!(
        p.iter()
            .all(|p| p.world_from_probe == glam::DMat3::IDENTITY)
    );
    // No header at all is fine too.
    assert_eq!(csv::parse("0,1,2").unwrap()[0].name, "probe_1");
}

#[test]
fn csv_errors_name_their_line() {
    let cases = [
        ("x,y,z\n1,2\n", 2, "3 or 4 fields"),
        ("1,2,3,a,b\n", 1, "3 or 4 fields"),
        ("# c\n1,2,3\n1,two,3\n", 3, "y must be a finite number"),
        ("1,2,3\n1,2,NaN\n", 2, "z must be a finite number"),
        ("1,2,oops\n", 1, "z must be a finite number"),
        ("1,2,3,\"\"\n", 1, "name is empty"),
        ("1,2,3,a\n\n4,5,6,a\n", 3, "already used on line 1"),
        ("x,y,z\n# nothing\n", 2, "no probe rows"),
        ("", 1, "no probe rows"),
    ];
    for (text, line, needle) in cases {
        let (got, message) = csv::parse(text).unwrap_err();
        assert_eq!(got, line, "{text:?}: {message}");
        assert!(message.contains(needle), "{text:?}: {message}");
    }
}

// ---- reading the output ---------------------------------------------------------------------

/// The output's nodes by name (first of each name).
fn node<'a>(g: &'a Gltf, name: &str) -> (usize, &'a Value) {
    g.json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .find(|(_, n)| n["name"] == name)
        .unwrap_or_else(|| panic!("no node {name}"))
}

fn children<'a>(g: &'a Gltf, n: &Value) -> Vec<&'a Value> {
    n["children"]
        .as_array()
        .map(|c| {
            c.iter()
                .map(|i| &g.json["nodes"][i.as_u64().unwrap() as usize])
                .collect()
        })
        .unwrap_or_default()
}

/// `a == b` up to serde_json's float parsing (without `float_roundtrip` it may be 1 ulp off).
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 4.0 * f64::EPSILON * a.abs().max(b.abs())
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn assert_valid(path: &Path) {
    if tools::have_validator() {
        let report = tools::validate(path);
        assert_eq!(
            (report.errors, report.warnings),
            (0, 0),
            "{}",
            report.listing()
        );
    }
}

/// The glyph of probe node `probe`: sizes from its extras, checked against its mesh.
fn check_glyph(g: &Gltf, probe: &Value, scale: f64, reference: f64) {
    let kids = children(g, probe);
    assert_eq!(kids.len(), 1, "{probe}");
    let glyph = kids[0];
    let name = probe["name"].as_str().unwrap();
    assert_eq!(glyph["name"], format!("{name}_glyph"));
    let info = &glyph["extras"]["luxbake"]["glyph"];
    assert_eq!(f(&info["scale"]), scale);
    assert_eq!(f(&info["referenceScalar"]), reference);
    let m = &probe["extras"]["luxbake"]["metrics"];
    let radius = (scale * f(&m["symmetricMean"]) / reference).max(0.05 * scale);
    assert!((f(&info["sphereRadius"]) - radius).abs() < 1e-12, "{info}");
    let length = (scale * f(&m["vectorMagnitude"]) / reference).max(0.15 * scale);
    assert!((f(&info["arrowLength"]) - length).abs() < 1e-12, "{info}");

    let mesh = &g.json["meshes"][glyph["mesh"].as_u64().unwrap() as usize];
    let prims = mesh["primitives"].as_array().unwrap();
    assert_eq!(prims.len(), 2, "arrow and sphere");
    for p in prims {
        let attrs: Vec<&str> = p["attributes"]
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(attrs, ["POSITION", "NORMAL", "COLOR_0"]);
        let material = &g.json["materials"][p["material"].as_u64().unwrap() as usize];
        assert!(material["extensions"]["KHR_materials_unlit"].is_object());
    }
    // Arrow: its farthest point is the tip, `length` along E; sphere: radius `radius`.
    let e: Vec<f64> = m["vector"].as_array().unwrap().iter().map(f).collect();
    let mag = f(&m["vectorMagnitude"]);
    let arrow = g.floats(prims[0]["attributes"]["POSITION"].as_u64().unwrap() as usize);
    let tip = arrow
        .iter()
        .max_by(|a, b| norm(a).total_cmp(&norm(b)))
        .unwrap();
    for k in 0..3 {
        let want = length * e[k] / mag;
        assert!(
            (f64::from(tip[k]) - want).abs() < 1e-5,
            "{tip:?} vs E {e:?}"
        );
    }
    let sphere = g.floats(prims[1]["attributes"]["POSITION"].as_u64().unwrap() as usize);
    for v in &sphere {
        assert!((norm(v) - radius).abs() < 1e-5, "{v:?} vs {radius}");
    }
}

fn norm(v: &[f32]) -> f64 {
    v.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>().sqrt()
}

// ---- the office end to end ------------------------------------------------------------------

const OFFICE_CSV: &str = "x,y,z,name\n# two desks, 20 cm above their tops\n\
                          1.5,1.0,2.2,desk dark\n3.5,1.0,5.0,desk light\n";

/// Bake the office with every probe option; `out` is the `--probes-out` file name.
fn office(dir: &Path, out: &str, plane_spacing: &str) -> (Run, PathBuf, PathBuf) {
    let probes = dir.join("desks.csv");
    std::fs::write(&probes, OFFICE_CSV).unwrap();
    let (output, probes_out) = (dir.join("lit.gltf"), dir.join(out));
    let run = bake_draft(
        &repo_file("samples/office/office.gltf"),
        &output,
        &[
            os("--probe-grid"),
            os("1"),
            os("--probe-height"),
            os("1.2"),
            os("--probes"),
            probes.as_os_str(),
            os("--working-plane"),
            os("0.8"),
            os("--working-plane-spacing"),
            os(plane_spacing),
            os("--probe-glyphs"),
            os("--probes-out"),
            probes_out.as_os_str(),
        ],
    );
    (run, output, probes_out)
}

/// The probe nodes of the output by layer, checked for layout; returns (layer, node) pairs.
fn probe_layers(g: &Gltf) -> Vec<(String, Value)> {
    let (root, probes) = node(g, "probes");
    let roots = g.json["scenes"][0]["nodes"].as_array().unwrap();
    assert_eq!(roots.last().unwrap(), &json!(root), "`probes` is a root");
    assert_eq!(probes["extras"]["luxbake"]["probeRoot"], true);
    let mut out = Vec::new();
    for group in children(g, probes) {
        let layer = group["name"].as_str().unwrap().to_string();
        for p in children(g, group) {
            assert!(p.get("mesh").is_none(), "probe nodes have no mesh");
            assert!(p.get("rotation").is_none(), "axis-aligned probes");
            assert_eq!(
                p["translation"], p["extras"]["luxbake"]["probe"]["position"],
                "{p}"
            );
            out.push((layer.clone(), p.clone()));
        }
    }
    out
}

#[test]
fn office_probes_in_gltf_json_out_validator_and_blender() {
    let dir = scratch("probes-office-json");
    let (run, output, json_out) = office(&dir, "probes.json", "0.5");
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(!run.stderr.contains("warning:"), "{}", run.stderr);
    assert!(
        run.stderr.contains("probes: 202 measured"),
        "{}",
        run.stderr
    );
    assert_eq!(
        listing(&dir),
        ["desks.csv", "lit.#.bin", "lit.gltf", "probes.json"]
    );
    let g = gltf_read::read(&output);
    let layers = probe_layers(&g);
    let count = |l: &str| layers.iter().filter(|(k, _)| k == l).count();
    // 5 × 8 m office: grid points every 1 m (5 × 8), the working plane every 0.5 m (10 × 16).
    assert_eq!(
        (count("grid"), count("csv"), count("working_plane")),
        (40, 2, 160)
    );
    let names: Vec<&str> = layers
        .iter()
        .filter(|(l, _)| l == "csv")
        .map(|(_, p)| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["desk dark", "desk light"]);
    for (layer, p) in &layers {
        let r = &p["extras"]["luxbake"];
        let y = f(&r["probe"]["position"][1]);
        match layer.as_str() {
            "grid" => assert!((y - 1.2).abs() < 1e-4, "{y}"),
            "working_plane" => {
                assert!((y - 0.8).abs() < 1e-4, "{y}");
                assert!(r["metrics"].get("exactScalar").is_none());
            }
            _ => assert!(r["metrics"]["exactScalar"].is_number()),
        }
        for face in FACES {
            let (t, d, i) = (
                f(&r["faces"][face]),
                f(&r["facesDirect"][face]),
                f(&r["facesIndirect"][face]),
            );
            assert!((t - d - i).abs() <= 1e-9 * t.max(1.0), "{face}: {r}");
        }
        // In a lit office every grid and desk probe sees light on its upward face.
        assert!(f(&r["faces"]["+y"]) > 50.0, "{r}");
    }

    // --probes-out .json: the same objects as the extras, in bake order.
    let out: Vec<Value> = serde_json::from_slice(&std::fs::read(&json_out).unwrap()).unwrap();
    let extras: Vec<&Value> = layers
        .iter()
        .map(|(_, p)| &p["extras"]["luxbake"])
        .collect();
    assert_eq!(out.len(), extras.len());
    for (a, b) in out.iter().zip(&extras) {
        assert_eq!(a, *b);
    }

    // Glyphs: s = 0.4 × the smaller grid spacing (0.5 m), E_ref the largest scalar illuminance.
    let reference = out
        .iter()
        .map(|r| f(&r["metrics"]["scalar"]))
        .fold(0.0, f64::max);
    for (_, p) in layers.iter().step_by(7) {
        check_glyph(&g, p, 0.2, reference);
    }

    assert_valid(&output);
    if !tools::have_blender() {
        return;
    }
    let report = tools::blender_import(&output);
    let objects = report["objects"].as_array().unwrap();
    let object = |name: &str| {
        objects
            .iter()
            .find(|o| o["name"] == name)
            .unwrap_or_else(|| panic!("no Blender object {name}"))
    };
    assert_eq!(object("probes")["type"], "EMPTY");
    for layer in ["grid", "csv", "working_plane"] {
        assert_eq!(object(layer)["parent"], "probes");
    }
    for (layer, p) in layers.iter().step_by(5) {
        let name = p["name"].as_str().unwrap();
        let o = object(name);
        assert_eq!((&o["type"], &o["parent"]), (&json!("EMPTY"), &json!(layer)));
        let props = &o["properties"]["luxbake"];
        for face in FACES {
            assert_eq!(
                props["faces"][face], p["extras"]["luxbake"]["faces"][face],
                "{name} {face}"
            );
        }
        assert_eq!(props, &p["extras"]["luxbake"], "{name}");
        let glyph = object(&format!("{name}_glyph"));
        assert_eq!(
            (&glyph["type"], &glyph["parent"]),
            (&json!("MESH"), &json!(name))
        );
    }
    let glyph_mesh = report["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "grid_0_0_glyph")
        .unwrap();
    let attrs: Vec<&str> = glyph_mesh["attributes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert!(attrs.contains(&"Color"), "{attrs:?}");
    assert!(
        !attrs.iter().any(|a| a.starts_with("_ILLUMINANCE")),
        "{attrs:?}"
    );
}

#[test]
fn office_probes_csv_out_matches_the_extras() {
    let dir = scratch("probes-office-csv");
    let (run, output, csv_out) = office(&dir, "probes.csv", "0.25");
    assert_eq!(run.code, Some(0), "{run:?}");
    let g = gltf_read::read(&output);
    let layers = probe_layers(&g);
    assert_eq!(layers.len(), 40 + 2 + 20 * 32, "default spacing 0.25 m");
    let text = std::fs::read_to_string(&csv_out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.len(), 5 + 18 + 11 + 4 + 3);
    assert_eq!(
        &header[..6],
        ["name", "origin", "x_m", "y_m", "z_m", "E+x_lx"]
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), layers.len());
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    for (row, (_, p)) in rows.iter().zip(&layers) {
        let r = &p["extras"]["luxbake"];
        assert_eq!(row[0], p["name"]);
        assert_eq!(row[1], r["probe"]["origin"]["kind"]);
        let num = |c: &str| row[col(c)].parse::<f64>().unwrap();
        for (k, axis) in ["x_m", "y_m", "z_m"].iter().enumerate() {
            assert!(same(num(axis), f(&r["probe"]["position"][k])));
        }
        for face in FACES {
            for (prefix, key) in [
                ("E", "faces"),
                ("direct", "facesDirect"),
                ("indirect", "facesIndirect"),
            ] {
                let (a, b) = (num(&format!("{prefix}{face}_lx")), f(&r[key][face]));
                assert!(same(a, b), "{prefix}{face}: {a} vs {b}");
            }
        }
        let m = &r["metrics"];
        for (c, key) in [
            ("vector_magnitude_lx", "vectorMagnitude"),
            ("altitude_deg", "altitudeDeg"),
            ("azimuth_deg", "azimuthDeg"),
            ("symmetric_mean_lx", "symmetricMean"),
            ("scalar_lx", "scalar"),
            ("vector_scalar_ratio", "vectorScalarRatio"),
            ("horizontal_lx", "horizontal"),
            ("cylindrical_lx", "cylindrical"),
            ("cuttle_indirect_lx", "cuttleIndirect"),
        ] {
            assert!(same(num(c), f(&m[key])), "{c}");
        }
        assert!(same(num("vector_y_lx"), f(&m["vector"][1])));
        assert!(same(
            num("semicylindrical-z_lx"),
            f(&m["semicylindrical"][3])
        ));
        match m.get("exactScalar") {
            Some(v) => assert!(same(num("exact_scalar_lx"), f(v))),
            None => assert_eq!(row[col("exact_scalar_lx")], ""),
        }
    }
}

// ---- grid points inside objects ---------------------------------------------------------------

/// The minimal scene with a closed 0.6 m box (outward faces) standing on the floor.
fn mini_with_box(dir: &Path) -> PathBuf {
    let mut mini = Mini::new();
    let (lo, hi) = (
        glam::DVec3::new(0.2, 0.0, 0.2),
        glam::DVec3::new(0.8, 0.6, 0.8),
    );
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut indices: Vec<u16> = Vec::new();
    for face in luxbake::fixtures::box_faces(lo, hi) {
        // box_faces winds each face seen from inside: reverse it to face outward.
        let base = positions.len() as u16;
        positions.extend([face[0], face[3], face[2], face[1]].map(|p| p.as_vec3().to_array()));
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let offset = mini.bin.len();
    mini.bin
        .extend(positions.iter().flatten().flat_map(|v| v.to_le_bytes()));
    mini.bin
        .extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let j = &mut mini.json;
    let views = j["bufferViews"].as_array_mut().unwrap();
    views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 288, "target": 34962}));
    views.push(json!({"buffer": 0, "byteOffset": offset + 288, "byteLength": 72, "target": 34963}));
    let accessors = j["accessors"].as_array_mut().unwrap();
    accessors.push(
        json!({"bufferView": 4, "componentType": 5126, "count": 24, "type": "VEC3",
                          "min": lo.as_vec3().to_array(), "max": hi.as_vec3().to_array()}),
    );
    accessors.push(json!({"bufferView": 5, "componentType": 5123, "count": 36, "type": "SCALAR"}));
    j["meshes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "box",
        "primitives": [{"attributes": {"POSITION": 4}, "indices": 5, "material": 0}]}));
    j["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "box", "mesh": 2}));
    j["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(2));
    mini.write_gltf(dir, "boxed.gltf", None)
}

#[test]
fn grid_points_inside_objects_are_skipped_with_a_warning() {
    let dir = scratch("probes-inside");
    let input = mini_with_box(&dir);
    let (output, out) = (dir.join("lit.glb"), dir.join("probes.json"));
    let run = bake_draft(
        &input,
        &output,
        &[
            os("--probe-grid"),
            os("0.25"),
            os("--probe-height"),
            os("0.3"),
            os("--probes-out"),
            out.as_os_str(),
            os("-q"),
        ],
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    let warnings: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect();
    // The 2 × 2 m floor at 0.25 m: 8 × 8 points, of which 2 × 2 fall in the box (x, z 0.2…0.8).
    assert_eq!(
        warnings,
        [
            "warning: grid: 4 grid point(s) inside objects and 0 with no floor below were skipped (60 kept)"
        ],
        "{}",
        run.stderr
    );
    let probes: Vec<Value> = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(probes.len(), 60);
    for p in &probes {
        let q: Vec<f64> = p["probe"]["position"]
            .as_array()
            .unwrap()
            .iter()
            .map(f)
            .collect();
        let inside = (0.2..0.8).contains(&q[0]) && (0.2..0.8).contains(&q[2]);
        assert!(!inside, "{q:?} is inside the box");
    }
    assert_valid(&output);
}

// ---- node probes ----------------------------------------------------------------------------

#[test]
fn node_probe_of_a_blender_file_gets_its_results() {
    let dir = scratch("probes-node");
    let (output, out) = (dir.join("room.glb"), dir.join("probes.csv"));
    let input = repo_file("tests/data/blender-room/room.glb");
    let run = bake_draft(
        &input,
        &output,
        &[os("--probe-glyphs"), os("--probes-out"), out.as_os_str()],
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(
        run.stderr.contains("probes: 1 measured (1 node)"),
        "{}",
        run.stderr
    );
    let g = gltf_read::read(&output);
    let (index, p) = node(&g, "probe_1");
    assert_eq!(index, 7);
    assert!(p.get("mesh").is_none());
    assert_eq!(p["translation"], json!([-1.0, 0.800000011920929, 0.0]));
    let extras = &p["extras"];
    assert_eq!(extras["probe"], true, "the node's own extras are kept");
    let r = &extras["luxbake"];
    assert_eq!(r["probe"]["origin"], json!({"kind": "node", "node": 7}));
    assert_eq!(r["probe"]["position"], p["translation"]);
    assert!(
        g.json["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|n| n["name"] != "probes"),
        "no `probes` root without grid, CSV or working-plane probes"
    );
    // The lamp (5435 cd at (-1.2, 2, 0.8)) lights the upward face directly:
    // I·cos θ / d² with d = (-0.2, 1.2, 0.8), plus a little from the 500 cd/m² panel.
    let d = glam::DVec3::new(-0.2, 2.0 - 0.800000011920929, 0.8);
    let lamp = 5435.141306588225 * (d.y / d.length()) / d.length_squared();
    let direct = f(&r["facesDirect"]["+y"]);
    assert!(
        direct > lamp && direct < 1.1 * lamp,
        "{direct} vs lamp {lamp}"
    );
    let s = 0.15; // no grid
    check_glyph(&g, p, s, f(&r["metrics"]["scalar"]));

    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    let row: Vec<&str> = lines[1].split(',').collect();
    assert_eq!(&row[..2], ["probe_1", "node"]);
    assert!(same(row[7].parse::<f64>().unwrap(), f(&r["faces"]["+y"])));

    assert_valid(&output);
    if tools::have_blender() {
        let report = tools::blender_import(&output);
        let o = report["objects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["name"] == "probe_1")
            .unwrap();
        assert_eq!(o["type"], "EMPTY");
        assert_eq!(o["properties"]["probe"], true);
        assert_eq!(o["properties"]["luxbake"]["faces"]["+y"], r["faces"]["+y"]);
        assert_eq!(&o["properties"]["luxbake"], r);
    }
}

// ---- errors ---------------------------------------------------------------------------------

/// Refused with one `error:` line containing every needle; nothing written to `out_dir`.
fn assert_refused(run: &Run, needles: &[&str], out_dir: &Path) {
    assert_ne!(run.code, Some(0), "{run:?}");
    assert!(run.stderr.starts_with("error: "), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    for n in needles {
        assert!(run.stderr.contains(n), "{n:?} not in {}", run.stderr);
    }
    assert_eq!(listing(out_dir), Vec::<String>::new(), "output written");
}

#[test]
fn bad_probes_file_is_one_error_naming_file_and_line() {
    let dir = scratch("probes-bad-file");
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let input = Mini::new().write_gltf(&dir, "scene.gltf", None);
    let bad = dir.join("bad probes.csv");
    std::fs::write(&bad, "x,y,z,name\n0,0.5,0,a\n0.5,half,0,b\n").unwrap();
    let run = bake_draft(
        &input,
        &out.join("lit.gltf"),
        &[
            os("--probes"),
            bad.as_os_str(),
            os("--probes-out"),
            out.join("p.json").as_os_str(),
        ],
    );
    let at = format!("{}:3:", bad.display());
    assert_refused(&run, &[&at, "y must be a finite number", "'half'"], &out);

    let missing = dir.join("missing.csv");
    let run = bake_draft(
        &input,
        &out.join("lit.gltf"),
        &[os("--probes"), missing.as_os_str()],
    );
    assert_refused(&run, &[missing.to_str().unwrap(), "cannot read"], &out);
}

#[test]
fn probe_option_errors_are_caught_before_baking() {
    let dir = scratch("probes-bad-options");
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let input = Mini::new().write_gltf(&dir, "scene.gltf", None);
    let lit = out.join("lit.gltf");
    let (txt, json) = (out.join("p.txt"), out.join("p.json"));
    let probes = dir.join("probes.csv");
    std::fs::write(&probes, "0,0.5,0\n").unwrap();
    let cases: Vec<(Vec<&OsStr>, Vec<String>)> = vec![
        (
            vec![os("--probe-height"), os("1")],
            vec!["--probe-height needs --probe-grid".into()],
        ),
        (
            vec![os("--working-plane-spacing"), os("0.5")],
            vec!["--working-plane-spacing needs --working-plane".into()],
        ),
        (
            vec![os("--probe-grid"), os("0")],
            vec!["--probe-grid".into(), "positive".into()],
        ),
        (
            vec![
                os("--working-plane"),
                os("0.8"),
                os("--working-plane-spacing"),
                os("-1"),
            ],
            vec!["--working-plane".into(), "positive".into()],
        ),
        (
            vec![os("--probes-out"), txt.as_os_str()],
            vec!["p.txt".into(), "use .csv or .json".into()],
        ),
        (
            vec![
                os("--summary-json"),
                json.as_os_str(),
                os("--probes-out"),
                json.as_os_str(),
            ],
            vec!["p.json".into(), "same file".into()],
        ),
        (
            vec![
                os("--probes"),
                probes.as_os_str(),
                os("--probes-out"),
                probes.as_os_str(),
            ],
            vec!["probes.csv".into(), "--probes input file".into()],
        ),
    ];
    for (args, needles) in &cases {
        let run = bake_draft(&input, &lit, args);
        let needles: Vec<&str> = needles.iter().map(String::as_str).collect();
        assert_refused(&run, &needles, &out);
    }
}
