//! The `bake` command on bad inputs and bad settings: each run must exit non-zero with exactly one
//! stderr line `error: ...` naming the file (or option) at fault, the problem and, for glTF, the
//! JSON pointer of the element; and it must leave the output folder empty (no `.gltf`, no `.bin`,
//! no temporary file). The inputs are small variations of the valid scene of `support::cli`,
//! which is first checked to bake (and, with the validator present, to validate).

mod support;

use std::path::{Path, PathBuf};
use support::cli::{Mini, Run, assert_error_line, bake, bake_draft_into, listing};
use support::{in_out, tools};

/// A test's folders: `in/` for the input, `out/` (empty) for the output.
fn folders(name: &str) -> (PathBuf, PathBuf) {
    in_out(&format!("cli-{name}"))
}

/// The run failed cleanly: non-zero exit, one `error:` line holding every needle, `out` empty.
fn assert_refused(run: &Run, out: &Path, needles: &[&str]) {
    assert_error_line(run, needles);
    assert_eq!(
        listing(out),
        Vec::<String>::new(),
        "output folder not empty"
    );
}

#[test]
fn the_minimal_scene_is_valid_and_bakes() {
    let (input, out) = folders("mini-ok");
    let mini = Mini::new();
    let gltf = mini.write_gltf(&input, "mini.gltf", Some("mini.bin"));
    let glb = input.join("mini.glb");
    std::fs::write(&glb, mini.glb_bytes()).unwrap();
    let embedded = mini.write_gltf(&input, "embedded.gltf", None);
    for path in [&gltf, &glb, &embedded] {
        // Default quality: in draft the scene's energy balance error (1.5e-3, mostly light
        // escaping past the floor's edges) is above the 1e-3 that warns.
        let output = out.join("lit.gltf");
        let run = bake([
            path.as_os_str(),
            "-o".as_ref(),
            output.as_os_str(),
            "--quiet".as_ref(),
        ]);
        assert!(run.ok(), "{}: {run:?}", path.display());
        assert_eq!(run.stderr, "", "{}", path.display());
        assert_eq!(listing(&out), ["lit.#.bin", "lit.gltf"]);
    }
    if tools::have_validator() {
        for path in [&gltf, &glb] {
            let report = tools::validate(path);
            assert_eq!(
                (report.errors, report.warnings),
                (0, 0),
                "{}:\n{}",
                path.display(),
                report.listing()
            );
        }
    }
}

#[test]
fn missing_buffer_file() {
    let (input, out) = folders("missing-bin");
    let path = Mini::new().write_gltf(&input, "scene.gltf", Some("scene.bin"));
    std::fs::remove_file(input.join("scene.bin")).unwrap();
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &[&path.display().to_string(), "/buffers/0", "scene.bin"],
    );
}

#[test]
fn truncated_glb() {
    let (input, out) = folders("truncated-glb");
    let bytes = Mini::new().glb_bytes();
    for cut in [7, 20, bytes.len() / 2, bytes.len() - 3] {
        let path = input.join(format!("cut{cut}.glb"));
        std::fs::write(&path, &bytes[..cut]).unwrap();
        let run = bake_draft_into(&path, &out, &[] as &[&str]);
        assert_refused(&run, &out, &[&path.display().to_string(), "truncated"]);
    }
}

#[test]
fn nan_position() {
    let (input, out) = folders("nan");
    let floor = [
        [-1.0, 0.0, -1.0],
        [-1.0, f32::NAN, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
    ];
    let path = Mini::with_floor(floor).write_gltf(&input, "nan.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &[
            &path.display().to_string(),
            "/meshes/0/primitives/0/attributes/POSITION: ",
            "/accessors/0",
            "non-finite",
        ],
    );
}

#[test]
fn reflectance_above_one() {
    let (input, out) = folders("reflectance");
    let mut mini = Mini::new();
    mini.json["materials"][0] = serde_json::json!({"name": "floor",
        "extensions": {"LUXBAKE_material": {"reflectance": 1.2}}});
    let path = mini.write_gltf(&input, "bright.gltf", None);
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &[&path.display().to_string(), "/materials/0: ", "1.2"],
    );
}

#[test]
fn buffer_outside_the_input_folder() {
    let (input, out) = folders("outside");
    let nested = input.join("a").join("b");
    std::fs::create_dir_all(&nested).unwrap();
    let mini = Mini::new();
    // `../../x.bin` exists (it is the right buffer), but lies above the input's folder.
    std::fs::write(input.join("x.bin"), &mini.bin).unwrap();
    let path = nested.join("escape.gltf");
    let json = mini.document(Some("../../x.bin"));
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(
        &run,
        &out,
        &[&path.display().to_string(), "/buffers/0: ", "outside"],
    );
}

#[test]
fn nonexistent_input() {
    let (input, out) = folders("nonexistent");
    let path = input.join("nowhere.gltf");
    let run = bake_draft_into(&path, &out, &[] as &[&str]);
    assert_refused(&run, &out, &[&path.display().to_string()]);
}

#[test]
fn unsupported_output_extension() {
    let (input, out) = folders("out-obj");
    let path = Mini::new().write_gltf(&input, "scene.gltf", None);
    let target = out.join("out.obj");
    let run = bake([
        path.as_os_str(),
        "-o".as_ref(),
        target.as_os_str(),
        "--quality".as_ref(),
        "draft".as_ref(),
    ]);
    assert_refused(
        &run,
        &out,
        &[
            &target.display().to_string(),
            "unsupported output extension",
        ],
    );
}

#[test]
fn output_over_an_input_file_is_refused() {
    let (input, _) = folders("over-input");
    let data = "data.0123456789abcdef.bin";
    let path = Mini::new().write_gltf(&input, "scene.gltf", Some(data));
    let before = |p: &str| std::fs::read(input.join(p)).unwrap();
    let (gltf, bin) = (before("scene.gltf"), before(data));
    // The input itself, and an output one of whose side-file names (`data.<hash>.bin`, which
    // a bake writes and removes) the input buffer has.
    for (target, at_fault, why) in [
        (
            "scene.gltf",
            "scene.gltf",
            "refusing to overwrite an input file",
        ),
        ("data.gltf", data, "has the name of a side file of"),
    ] {
        let run = bake([
            path.as_os_str(),
            "-o".as_ref(),
            input.join(target).as_os_str(),
        ]);
        let named = input.join(at_fault).display().to_string();
        assert_error_line(&run, &[&named, why]);
        assert_eq!(listing(&input), ["data.#.bin", "scene.gltf"], "-o {target}");
        assert_eq!(before("scene.gltf"), gltf, "-o {target}: input changed");
        assert_eq!(before(data), bin, "-o {target}: input buffer changed");
    }
}

#[test]
fn invalid_settings() {
    let (input, out) = folders("settings");
    let path = Mini::new().write_gltf(&input, "scene.gltf", None);
    for (args, needles) in [
        (&["--patch-size=-1"][..], &["--patch-size", "-1"][..]),
        (&["--patch-size", "0"], &["--patch-size"]),
        (&["--exposure", "foo"], &["--exposure", "foo"]),
        (&["--exposure=-5"], &["--exposure"]),
        (&["--threads", "0"], &["--threads"]),
        (&["--direct-budget", "0.5"], &["--direct-budget", "0.5"]),
        (&["--direct-budget", "-0.1"], &["--direct-budget", "-0.1"]),
        (
            &["--exact-direct", "--direct-budget", "0.01"],
            &["--exact-direct", "--direct-budget"],
        ),
    ] {
        let run = bake_draft_into(&path, &out, args);
        assert_refused(&run, &out, needles);
    }
}

/// `--patch-size -1` / `--exposure -5` (with a space, as users type them) must get the same
/// one-line settings error as `--patch-size=-1`; clap takes `-1` for an unknown flag and prints a
/// 7-line usage error whose tip (`-- -1`) does not work either.
#[test]

fn negative_numbers_with_a_space() {
    let (input, out) = folders("settings-space");
    let path = Mini::new().write_gltf(&input, "scene.gltf", None);
    for (option, value) in [("--patch-size", "-1"), ("--exposure", "-5")] {
        let run = bake_draft_into(&path, &out, &[option, value]);
        assert_refused(&run, &out, &[option, value]);
    }
}
