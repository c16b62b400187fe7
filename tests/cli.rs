//! The `bake` command on good inputs: exit code and output files of a good run, the
//! `--summary-json` file (the office's energy balance), byte-identical output whatever
//! `--threads`, the warning for a scene without light, `--obj-up z`, and where `--summary-json`
//! may write (never over the output's side buffer, never over an input, never after a partial
//! success). Bakes use `--quality draft`.

mod support;

use serde_json::Value;
use std::path::Path;
use std::process::Command;
use support::cli::{Mini, Run, bake_draft, listing, mini_in, repo_file};
use support::{scratch, tools};

#[test]
fn good_run_writes_the_output_and_the_summary() {
    let dir = scratch("cli-good");
    let (output, summary) = (dir.join("office.gltf"), dir.join("summary.json"));
    let office = repo_file("samples/office/office.gltf");
    let run = bake_draft(
        &office,
        &output,
        &["--summary-json", summary.to_str().unwrap()],
    );
    assert_eq!(run.code, Some(0), "{run:?}");
    // The two report lines, no `error:` or `warning:`.
    assert!(run.stderr.starts_with("baked "), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 2, "{}", run.stderr);
    assert_eq!(
        listing(&dir),
        ["office.#.bin", "office.gltf", "summary.json"],
        "exactly the output, its buffer and the summary (no temporary file)"
    );
    assert!(std::fs::metadata(&output).unwrap().len() > 0);

    let s: Value = serde_json::from_slice(&std::fs::read(&summary).unwrap())
        .expect("--summary-json writes valid JSON");
    let e = &s["energy"];
    let lm = |k: &str| e[k].as_f64().unwrap_or_else(|| panic!("energy.{k}: {e}"));
    // Six louvred fluorescents (5200 lm lamp, LOR 0.65: 3380 lm) and the spotlight (990 lm
    // lamp, LOR 0.8: 792 lm), from their photometric profiles.
    let expected = 6.0 * 3380.0 + 792.0;
    assert!(
        (lm("emittedLm") - expected).abs() <= 0.01 * expected,
        "emittedLm {} vs {expected}",
        lm("emittedLm")
    );
    assert_eq!(lm("emittedBySurfacesLm"), 0.0, "{e}");
    assert!(
        (lm("emittedByLightsLm") - expected).abs() <= 0.01 * expected,
        "{e}"
    );
    let balance = lm("emittedLm") - lm("absorbedLm") - lm("escapedLm");
    assert!(
        (balance - lm("balanceErrorLm")).abs() < 1e-6 * expected,
        "{e}"
    );
    assert!(lm("balanceErrorRelative") < 0.01, "{e}");
    assert_eq!(s["settings"]["quality"], "draft");
    assert_eq!(s["output"], output.to_str().unwrap());
    // Linux: the stages' memory, in the order they ran, each peak at least what it held at its
    // end; the output's extras never carry it (it differs run to run).
    if cfg!(target_os = "linux") {
        let stages = s["memoryKib"].as_array().expect("memoryKib on Linux");
        let names: Vec<&str> = stages
            .iter()
            .map(|m| m["stage"].as_str().unwrap())
            .collect();
        assert_eq!(
            names,
            [
                "import",
                "meshing",
                "direct light",
                "form factors",
                "solving",
                "output"
            ]
        );
        for m in stages {
            let (peak, held) = (
                m["peakKib"].as_u64().unwrap(),
                m["residentKib"].as_u64().unwrap(),
            );
            assert!(held > 1000 && peak >= held, "{m}");
        }
    }
    // The scene's extras carry the same summary (without the run-specific keys).
    let written = support::gltf_read::read(&output);
    assert_eq!(written.json["scenes"][0]["extras"]["luxbake"]["energy"], *e);
    assert!(written.json["scenes"][0]["extras"]["luxbake"]["memoryKib"].is_null());
}

#[test]
fn threads_do_not_change_the_output() {
    let dir = scratch("cli-threads");
    let office = repo_file("samples/office/office.gltf");
    let mut files = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.join(format!("t{threads}"));
        std::fs::create_dir(&out).unwrap();
        let run = bake_draft(
            &office,
            &out.join("lit.gltf"),
            &["--threads", threads, "-q"],
        );
        assert_eq!(run.code, Some(0), "--threads {threads}: {run:?}");
        assert_eq!(listing(&out), ["lit.#.bin", "lit.gltf"]);
        let read = |name: &str| std::fs::read(out.join(name)).unwrap();
        let bin = support::hashed(&out, "lit.#.bin");
        files.push((read("lit.gltf"), read(bin.to_str().unwrap())));
    }
    // Compare the lengths first so a failure does not print two 100 kB byte arrays.
    for (k, name) in [(0, "lit.gltf"), (1, "lit.bin")] {
        let pick = |t: &(Vec<u8>, Vec<u8>)| if k == 0 { t.0.clone() } else { t.1.clone() };
        let (a, b) = (pick(&files[0]), pick(&files[1]));
        assert_eq!(
            a.len(),
            b.len(),
            "{name}: length differs between 1 and 2 threads"
        );
        let first = a.iter().zip(&b).position(|(x, y)| x != y);
        assert_eq!(
            first, None,
            "{name}: first differing byte between 1 and 2 threads"
        );
    }
}

#[test]
fn a_scene_without_light_bakes_with_a_warning() {
    let dir = scratch("cli-dark");
    let mut mini = Mini::new();
    mini.json["materials"][1]["extensions"]["LUXBAKE_material"] =
        serde_json::json!({"reflectance": 0.5});
    let input = mini.write_gltf(&dir, "dark.gltf", None);
    let output = dir.join("dark-lit.glb");
    let run = bake_draft(&input, &output, &["--quiet"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    let warnings: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect();
    assert_eq!(warnings.len(), 1, "{}", run.stderr);
    assert!(warnings[0].contains("no light"), "{}", run.stderr);
    assert!(std::fs::metadata(&output).unwrap().len() > 0);
}

#[test]
fn cornell_box_with_z_up() {
    let dir = scratch("cli-obj-up");
    let output = dir.join("cornell.glb");
    let input = repo_file("samples/cornell-box/cornell-box.obj");
    let run = bake_draft(&input, &output, &["--obj-up", "z", "-q"]);
    assert_eq!(run.code, Some(0), "{run:?}");
    assert!(std::fs::metadata(&output).unwrap().len() > 1000);
    assert_eq!(listing(&dir), ["cornell.glb"]);
    if tools::have_validator() {
        let report = tools::validate(&output);
        assert_eq!(
            (report.errors, report.warnings),
            (0, 0),
            "{}",
            report.listing()
        );
    }
}

/// The run was refused with one `error:` line naming `--summary-json`'s file.
fn assert_summary_refused(run: &Run, summary: &Path) {
    assert_ne!(run.code, Some(0), "{run:?}");
    assert!(run.stderr.starts_with("error: "), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(
        run.stderr.contains(summary.to_str().unwrap()),
        "{}",
        run.stderr
    );
}

#[test]
fn summary_json_over_the_output_is_refused() {
    let (input, _, out) = mini_in("cli-summary-main");
    let output = out.join("lit.gltf");
    let run = bake_draft(
        &input,
        &output,
        &["--summary-json", output.to_str().unwrap()],
    );
    assert_summary_refused(&run, &output);
    assert_eq!(listing(&out), Vec::<String>::new());
}

#[test]

fn summary_json_over_the_output_buffer_is_refused() {
    let (input, _, out) = mini_in("cli-summary-bin");
    let (output, bin) = (out.join("lit.gltf"), out.join("lit.0123456789abcdef.bin"));
    let run = bake_draft(&input, &output, &["--summary-json", bin.to_str().unwrap()]);
    assert_summary_refused(&run, &bin);
    assert_eq!(listing(&out), Vec::<String>::new());
}

#[test]

fn summary_json_over_an_input_file_is_refused() {
    let (input, folder, out) = mini_in("cli-summary-input");
    let bin = folder.join("scene.bin");
    let before = std::fs::read(&bin).unwrap();
    let run = bake_draft(
        &input,
        &out.join("lit.glb"),
        &["--summary-json", bin.to_str().unwrap()],
    );
    let after = std::fs::read(&bin).unwrap();
    assert!(
        after == before,
        "the input's scene.bin was overwritten: {run:?}"
    );
    assert_summary_refused(&run, &bin);
    assert_eq!(listing(&out), Vec::<String>::new());
}

#[test]

fn summary_json_in_a_missing_folder_writes_nothing() {
    let (input, _, out) = mini_in("cli-summary-nodir");
    let summary = out.join("missing").join("summary.json");
    let run = bake_draft(
        &input,
        &out.join("lit.glb"),
        &["--summary-json", summary.to_str().unwrap()],
    );
    assert_summary_refused(&run, &summary);
    assert_eq!(
        listing(&out),
        Vec::<String>::new(),
        "output written by a failed run"
    );
}

#[test]
fn luminaire_subcommand_summarises_a_profile_and_draws_its_polar_curve() {
    let dir = scratch("cli-luminaire");
    let svg = dir.join("miral.svg");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/office/profiles/miral_58w.ies");
    let out = Command::new(env!("CARGO_BIN_EXE_bake"))
        .arg("luminaire")
        .arg(&file)
        .arg("--polar")
        .arg(&svg)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "Rated lamp flux: 5200.0 lm",
        "Flux:            3380.",
        "LOR 65.0 %",
        "Beam (50 %):",
    ] {
        assert!(text.contains(needle), "{needle} missing in:\n{text}");
    }
    let drawing = std::fs::read_to_string(&svg).unwrap();
    assert!(drawing.starts_with("<?xml") && drawing.trim_end().ends_with("</svg>"));
    // A malformed file: one line naming the file and the line.
    let bad = dir.join("bad.ies");
    std::fs::write(
        &bad,
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 x 1 1 2 0 0 0\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_bake"))
        .arg("luminaire")
        .arg(&bad)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.ies") && err.contains("line 3"), "{err}");
}
