//! Outputs never lost, never half-written (issue 25, Deliver 2), through the real `bake` binary:
//! - every output path is checked before any work: against the inputs (the profile of
//!   `bake luminaire --polar`, `--targets`, `--probes`, through `./`, symlinks and hard links),
//!   against the other outputs, for being a directory or a device; nothing is written then;
//! - a kill (SIGKILL, `LUXBAKE_FAULT_AT=N`) at every staging write, rename and cleanup removal
//!   leaves `lit.gltf` / `lit.glb` with exactly the old or the new set of files it references, a
//!   sibling output's set untouched, and the probes file old or new (new only with the new set);
//!   the next normal bake leaves exactly the new files (no temporary, no stale side file);
//! - SIGTERM / SIGINT during staging exit 143 / 130 with no temporary left and the old set intact;
//! - a re-bake removes the old set's side files it no longer uses (also the pre-hash names).

mod support;

use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use support::cli::{Mini, Run, bake, bake_draft, listing, mini_in};
use support::scratch;

/// Every file of `dir` by name (hidden ones included) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| {
            let name = e.file_name().into_string().unwrap();
            (name, std::fs::read(e.path()).unwrap())
        })
        .collect()
}

fn assert_refused(run: &Run, needles: &[&str]) {
    assert_eq!(run.code, Some(1), "{run:?}");
    assert!(run.stderr.starts_with("error: "), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    for n in needles {
        assert!(run.stderr.contains(n), "{n:?} not in {}", run.stderr);
    }
}

fn os<S: AsRef<std::ffi::OsStr> + ?Sized>(s: &S) -> &std::ffi::OsStr {
    s.as_ref()
}

#[test]
fn polar_curve_over_its_own_profile_is_refused() {
    let dir = scratch("out-polar");
    let profile = dir.join("x.ies");
    let source = support::cli::repo_file("samples/office/profiles");
    let first = std::fs::read_dir(&source)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "ies"))
        .expect("an .ies sample profile");
    std::fs::copy(&first, &profile).unwrap();
    std::fs::hard_link(&profile, dir.join("link.ies")).unwrap();
    std::os::unix::fs::symlink(&profile, dir.join("sym.svg")).unwrap();
    let before = snapshot(&dir);
    let spelled = dir.join("sub/../x.ies");
    std::fs::create_dir(dir.join("sub")).unwrap();
    for polar in [
        profile.clone(),
        spelled,
        dir.join("link.ies"),
        dir.join("sym.svg"),
    ] {
        let run = bake([
            os("luminaire"),
            profile.as_os_str(),
            os("--polar"),
            polar.as_os_str(),
        ]);
        assert_refused(&run, &[&polar.display().to_string(), "input file"]);
        assert_eq!(snapshot(&dir), before, "--polar {}", polar.display());
    }
    // A directory as the SVG: refused before reading anything.
    let run = bake([
        os("luminaire"),
        profile.as_os_str(),
        os("--polar"),
        dir.as_os_str(),
    ]);
    assert_refused(&run, &["is a directory"]);
    // The check passes an ordinary new file.
    let svg = dir.join("x.svg");
    let run = bake([
        os("luminaire"),
        profile.as_os_str(),
        os("--polar"),
        svg.as_os_str(),
    ]);
    assert!(run.ok(), "{run:?}");
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
}

/// `bake generate -o` is checked before the scene is built: a directory, a missing folder.
#[test]
fn generate_into_a_directory_is_refused() {
    let dir = scratch("out-generate");
    let missing = dir.join("nowhere/office.gltf");
    for (path, why) in [
        (dir.as_path(), "unsupported output extension"),
        (missing.as_path(), "create it first"),
    ] {
        let run = bake([os("generate"), os("openplan"), os("-o"), path.as_os_str()]);
        assert_refused(&run, &[&path.display().to_string(), why]);
    }
    let as_dir = dir.join("office.gltf");
    std::fs::create_dir(&as_dir).unwrap();
    let run = bake([os("generate"), os("openplan"), os("-o"), as_dir.as_os_str()]);
    assert_refused(&run, &["office.gltf", "is a directory"]);
    assert_eq!(listing(&dir), ["office.gltf"]);
}

/// Bake `input` to `output` (draft, quiet) with `extra` arguments.
fn draft(input: &Path, output: &Path, extra: &[&std::ffi::OsStr]) -> Run {
    bake_draft(input, output, &[&[os("-q")], extra].concat())
}

#[test]
fn report_out_over_the_targets_file_is_refused() {
    let (scene, input, out) = mini_in("out-targets");
    let targets = input.join("targets.json");
    std::fs::write(&targets, r#"{"floor": 100}"#).unwrap();
    std::fs::hard_link(&targets, out.join("hard.json")).unwrap();
    let before = snapshot(&input);
    for report in [targets.clone(), out.join("hard.json")] {
        let run = draft(
            &scene,
            &out.join("lit.gltf"),
            &[
                os("--targets"),
                targets.as_os_str(),
                os("--report-out"),
                report.as_os_str(),
            ],
        );
        assert_refused(&run, &[&report.display().to_string(), "input file"]);
        assert_eq!(snapshot(&input), before);
        assert_eq!(listing(&out), ["hard.json"]);
    }
    // The --probes input as --summary-json.
    let probes = input.join("p.csv");
    std::fs::write(&probes, "0,1,0\n").unwrap();
    let run = draft(
        &scene,
        &out.join("lit.gltf"),
        &[
            os("--probes"),
            probes.as_os_str(),
            os("--summary-json"),
            probes.as_os_str(),
        ],
    );
    assert_refused(&run, &["p.csv", "input file"]);
    assert_eq!(std::fs::read(&probes).unwrap(), b"0,1,0\n");
}

/// An existing output set and a later output that is a directory or a device: refused before
/// the bake, the old set byte for byte as it was.
#[test]
fn a_bad_later_output_changes_nothing() {
    let (scene, _, out) = mini_in("out-late");
    let lit = out.join("lit.gltf");
    assert!(draft(&scene, &lit, &[]).ok());
    let (dir, csv) = (out.join("d"), out.join("d.csv"));
    std::fs::create_dir(&dir).unwrap();
    std::fs::create_dir(&csv).unwrap();
    let before = snapshot(&out);
    let missing = out.join("nowhere/x.json");
    for (option, path, why) in [
        ("--summary-json", dir.as_path(), "is a directory"),
        (
            "--summary-json",
            Path::new("/dev/null"),
            "not a regular file",
        ),
        ("--probes-out", csv.as_path(), "is a directory"),
        ("--report-out", dir.as_path(), "is a directory"),
        ("--report-out", missing.as_path(), "create it first"),
    ] {
        let mut extra = vec![os(option), path.as_os_str()];
        if option == "--probes-out" {
            extra.extend([os("--probe-grid"), os("0.5")]);
        }
        let run = draft(&scene, &lit, &extra);
        assert_refused(&run, &[&path.display().to_string(), why]);
        assert_eq!(snapshot(&out), before, "{option} {}", path.display());
    }
    // Two outputs on one file, through a symlink.
    std::os::unix::fs::symlink(out.join("s.json"), out.join("alias.json")).unwrap();
    let (a, b) = (out.join("s.json"), out.join("alias.json"));
    std::fs::write(&a, b"old").unwrap();
    let run = draft(
        &scene,
        &lit,
        &[
            os("--summary-json"),
            a.as_os_str(),
            os("--report-out"),
            b.as_os_str(),
        ],
    );
    assert_refused(&run, &["alias.json", "same file"]);
    assert_eq!(std::fs::read(&a).unwrap(), b"old");
}

/// The scene with the panel's flux changed, so every output file differs.
fn mini_with_flux(lm: f64) -> Mini {
    let mut mini = Mini::new();
    mini.json["materials"][1]["extensions"]["LUXBAKE_material"]["emission"]["luminousFlux"] =
        json!(lm);
    mini
}

/// `bake scene -o dir/lit.<ext>` with lightmaps, coarse (a few hundredths of a second), and the
/// probe at `points.csv` beside `scene` written to `dir/probes.csv`.
fn command(scene: &Path, dir: &Path, ext: &str) -> Command {
    let points = scene.with_file_name("points.csv");
    if !points.exists() {
        std::fs::write(&points, "0,0.5,0,centre\n").unwrap();
    }
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_bake"));
    cmd.arg(scene)
        .arg("-o")
        .arg(dir.join(format!("lit.{ext}")))
        .args(["--quality", "draft", "--patch-size", "0.5", "-q"])
        .args(["--lightmaps", "--texel-size", "0.25", "--probes"])
        .arg(points)
        .arg("--probes-out")
        .arg(dir.join("probes.csv"))
        .env_remove("LUXBAKE_FAULT_AT");
    cmd
}

/// [`command`] run with `LUXBAKE_FAULT_AT=env`, if given.
fn run_bake(scene: &Path, dir: &Path, ext: &str, env: Option<&str>) -> std::process::Output {
    let mut cmd = command(scene, dir, ext);
    if let Some(at) = env {
        cmd.env("LUXBAKE_FAULT_AT", at);
    }
    cmd.output().unwrap()
}

/// The file names a `.gltf` / `.glb` references by URI (its side files).
fn references(main: &Path) -> Vec<String> {
    let bytes = std::fs::read(main).unwrap();
    let json: Value = if bytes.starts_with(b"glTF") {
        let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        serde_json::from_slice(&bytes[20..20 + len]).unwrap()
    } else {
        serde_json::from_slice(&bytes).unwrap()
    };
    let mut out = Vec::new();
    let mut stack = vec![&json];
    while let Some(v) = stack.pop() {
        match v {
            Value::Object(m) => {
                for (k, v) in m {
                    match v.as_str() {
                        Some(s) if k == "uri" => out.push(s.to_string()),
                        _ => stack.push(v),
                    }
                }
            }
            Value::Array(a) => stack.extend(a),
            _ => {}
        }
    }
    out.sort();
    out
}

/// The main file `name` and the files it references, from a folder's snapshot.
fn set(files: &BTreeMap<String, Vec<u8>>, dir: &Path, name: &str) -> BTreeMap<String, Vec<u8>> {
    let mut set = BTreeMap::new();
    for n in std::iter::once(name.to_string()).chain(references(&dir.join(name))) {
        let bytes = files
            .get(&n)
            .unwrap_or_else(|| panic!("{name} references {n}: missing"));
        set.insert(n, bytes.clone());
    }
    set
}

/// Kill the bake at every step; after each, the output is the old set or the new set.
#[test]
fn a_kill_at_any_step_leaves_the_old_set_or_the_new_set() {
    let dir = scratch("out-kill");
    let old_scene = mini_with_flux(500.0).write_gltf(&dir, "old.gltf", Some("old.bin"));
    let new_scene = mini_with_flux(800.0).write_gltf(&dir, "new.gltf", Some("new.bin"));
    // Reference bakes: the old sets of both formats in one folder, the new ones in another.
    let reference = |scene: &Path, name: &str| {
        let d = dir.join(name);
        std::fs::create_dir(&d).unwrap();
        for ext in ["gltf", "glb"] {
            let out = run_bake(scene, &d, ext, None);
            assert!(out.status.success(), "{out:?}");
        }
        (d.clone(), snapshot(&d))
    };
    let (old_dir, old) = reference(&old_scene, "old");
    let (new_dir, new) = reference(&new_scene, "new");
    // The sibling output (the other format) is a third bake, so no file is shared with it.
    let other_scene = mini_with_flux(300.0).write_gltf(&dir, "other.gltf", Some("other.bin"));
    let (other_dir, other) = reference(&other_scene, "other");
    assert_ne!(old["lit.gltf"], new["lit.gltf"]);
    let run = dir.join("run");
    let (mut kills, started) = (0, std::time::Instant::now());
    for (ext, sibling) in [("gltf", "glb"), ("glb", "gltf")] {
        let main = format!("lit.{ext}");
        let old_set = set(&old, &old_dir, &main);
        let new_set = set(&new, &new_dir, &main);
        let sibling_set = set(&other, &other_dir, &format!("lit.{sibling}"));
        // Side files of both formats, named by content, so every set differs from the other.
        assert!(old_set.len() >= 2);
        assert!(
            new_set
                .keys()
                .all(|k| *k == main || !old_set.contains_key(k))
        );
        // The folder as the new bake leaves it: the new set, the old sibling, the new probes.
        let mut done = sibling_set.clone();
        done.extend(new_set.clone());
        done.insert("probes.csv".into(), new["probes.csv"].clone());
        let mut start = sibling_set.clone();
        start.extend(old_set.clone());
        start.insert("probes.csv".into(), old["probes.csv"].clone());
        let reset = || {
            let _ = std::fs::remove_dir_all(&run);
            std::fs::create_dir(&run).unwrap();
            for (name, bytes) in &start {
                std::fs::write(run.join(name), bytes).unwrap();
            }
        };
        // A run without a fault counts the steps.
        reset();
        let counted = run_bake(&new_scene, &run, ext, Some("0"));
        assert!(counted.status.success(), "{counted:?}");
        let steps = String::from_utf8_lossy(&counted.stderr)
            .lines()
            .filter(|l| l.starts_with("luxbake-fault: step"))
            .count();
        // Per file of the new set and the probes file: a write and a rename; then the
        // removals of the old set's side files.
        assert_eq!(steps, 2 * (new_set.len() + 1) + old_set.len() - 1, "{main}");
        assert_eq!(snapshot(&run), done, "{main}: after a normal bake");
        for n in 1..=steps {
            reset();
            let out = run_bake(&new_scene, &run, ext, Some(&n.to_string()));
            assert_eq!(
                out.status.signal(),
                Some(9),
                "{main} step {n}: not killed: {out:?}"
            );
            kills += 1;
            let files = snapshot(&run);
            let now = set(&files, &run, &main);
            let which = if now == old_set {
                "old"
            } else {
                assert!(
                    now == new_set,
                    "{main} step {n}: neither the old set nor the new set"
                );
                "new"
            };
            assert_eq!(set(&files, &run, &format!("lit.{sibling}")), sibling_set);
            let probes = &files["probes.csv"];
            assert!(
                probes == &old["probes.csv"] || (probes == &new["probes.csv"] && which == "new"),
                "{main} step {n}: the probes file is new while the set is {which}"
            );
            // The next bake leaves exactly the new files: no temporary, no stale side file.
            let again = run_bake(&new_scene, &run, ext, None);
            assert!(again.status.success(), "{again:?}");
            assert_eq!(snapshot(&run), done, "{main} step {n}: leftovers");
        }
    }
    eprintln!("{kills} kills in {:.1} s", started.elapsed().as_secs_f64());
}

/// SIGTERM and SIGINT while the outputs are being staged: exit 143 / 130, no temporary left,
/// the old set as it was.
#[test]
fn a_signal_removes_the_temporaries() {
    let dir = scratch("out-signal");
    let old_scene = mini_with_flux(500.0).write_gltf(&dir, "old.gltf", Some("old.bin"));
    let new_scene = mini_with_flux(800.0).write_gltf(&dir, "new.gltf", Some("new.bin"));
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    assert!(run_bake(&old_scene, &out, "gltf", None).status.success());
    let before = snapshot(&out);
    // Steps 1 and 3 are staging writes (the first and second atlas or the .bin), each paused
    // with half its bytes written.
    for (signal, code, step) in [(libc::SIGTERM, 143, 1), (libc::SIGINT, 130, 3)] {
        let mut child = command(&new_scene, &out, "gltf")
            .env("LUXBAKE_FAULT_AT", format!("{step}:pause"))
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
        let paused = lines
            .by_ref()
            .map(|l| l.unwrap())
            .find(|l| l.starts_with("luxbake-fault: pause"))
            .expect("the bake pauses");
        assert!(paused.contains("(write "), "{paused}");
        // One temporary per staging write so far, the last half-written.
        let temporaries = listing(&out).into_iter().filter(|n| n.ends_with(".tmp"));
        assert_eq!(temporaries.count(), step, "while paused at step {step}");
        let pid = libc::pid_t::try_from(child.id()).unwrap();
        // SAFETY: sends a signal to the child started above.
        assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(code), "signal {signal}");
        assert_eq!(
            snapshot(&out),
            before,
            "signal {signal}: the folder changed"
        );
    }
}

/// A re-bake removes the side files of the old set it does not reference (also the names from
/// before content hashes, `lit.bin`, when the old `lit.gltf` used them), keeps those a sibling
/// `lit.glb` references and files that only look like side files of another output.
#[test]
fn a_rebake_removes_only_the_old_sets_unused_side_files() {
    let (scene, _, out) = mini_in("out-rebake");
    let lit = out.join("lit.gltf");
    let lm = [os("--lightmaps"), os("--texel-size"), os("0.25")];
    assert!(draft(&scene, &out.join("lit.glb"), &lm).ok());
    assert!(draft(&scene, &lit, &lm).ok());
    let glb_refs = references(&out.join("lit.glb"));
    // An old output from before content hashes: `lit.gltf` uses `lit.bin`.
    let bin = support::hashed(&out, "lit.#.bin");
    let bin_name = bin.file_name().unwrap().to_str().unwrap().to_string();
    let text = std::fs::read_to_string(&lit)
        .unwrap()
        .replace(&bin_name, "lit.bin");
    std::fs::write(&lit, text).unwrap();
    std::fs::rename(&bin, out.join("lit.bin")).unwrap();
    std::fs::write(
        out.join("lit.lightmap3.exr"),
        b"not ours: no output references it",
    )
    .unwrap();
    std::fs::write(out.join("lit2.0123456789abcdef.bin"), b"another stem").unwrap();
    // Without lightmaps now: the .gltf's EXR files go unless the .glb uses them.
    assert!(draft(&scene, &lit, &[]).ok());
    let mut expected: std::collections::BTreeSet<String> = glb_refs.into_iter().collect();
    expected.extend([
        "lit.glb".into(),
        "lit.gltf".into(),
        "lit.lightmap3.exr".into(),
        "lit2.0123456789abcdef.bin".into(),
    ]);
    expected.extend(references(&lit));
    let names: std::collections::BTreeSet<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(names, expected);
    assert!(!references(&lit).iter().any(|r| r.ends_with(".exr")));
}
