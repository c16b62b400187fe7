//! The distributed bake (`bake shard plan|gather|merge`; `dask/dask_bake.py`
//! on a Dask cluster) writes the same bytes as one `bake` process, whatever the task count,
//! the tasks' order and threads; its errors name the file and leave no output.
//! The Dask test is skipped locally without `.venv-dask` (dask/install.sh), never under CI.

mod support;

use std::path::{Path, PathBuf};
use support::cli::bake;
use support::{scratch, tools};

/// A small open-plan floor (desks, chairs, screens, luminaires) written by `bake generate`.
fn floor(dir: &Path) -> PathBuf {
    floor_of(dir, "1")
}

/// The floor of [`floor`] with chairs turned by random `seed`, in DIR/floor.gltf.
fn floor_of(dir: &Path, seed: &str) -> PathBuf {
    let input = dir.join("floor.gltf");
    let run = bake([
        "generate",
        "openplan",
        "--seed",
        seed,
        "--triangles",
        "3000",
        "-q",
        "-o",
        input.to_str().unwrap(),
    ]);
    assert!(run.ok(), "{}", run.stderr);
    input
}

fn args<'a>(input: &'a Path, out: &'a Path, options: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![input.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
    a.extend_from_slice(options);
    a
}

/// `bake shard STEP --dir DIR [step options] IN -o OUT -q OPTIONS`.
fn step<'a>(
    name: &'a str,
    dir: &'a str,
    step_options: &[&'a str],
    input: &'a Path,
    out: &'a Path,
    options: &[&'a str],
) -> Vec<&'a str> {
    let mut a = vec!["shard", name, "--dir", dir];
    a.extend_from_slice(step_options);
    a.extend(args(input, out, options));
    a
}

/// Plan, gather the tasks in `order` (each with its own `--threads`), merge; the output's bytes.
fn sharded(input: &Path, out: &Path, options: &[&str], tasks: usize, order: &[usize]) -> Vec<u8> {
    let dir = out.with_extension("state");
    let dir_s = dir.to_str().unwrap();
    let n = tasks.to_string();
    let run = bake(step("plan", dir_s, &["--tasks", &n], input, out, options));
    assert!(run.ok(), "plan: {}", run.stderr);
    assert!(!out.exists(), "the plan writes no output");
    let plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("plan.json")).unwrap()).unwrap();
    assert_eq!(plan["tasks"], tasks, "{plan}");
    for (i, &k) in order.iter().enumerate() {
        let (k, threads) = (k.to_string(), (1 + i % 2).to_string());
        let run = bake(step(
            "gather",
            dir_s,
            &["--task", &k, "--threads", &threads],
            input,
            out,
            options,
        ));
        assert!(run.ok(), "gather {k}: {}", run.stderr);
    }
    let run = bake(step("merge", dir_s, &[], input, out, options));
    assert!(run.ok(), "merge: {}", run.stderr);
    std::fs::read(out).unwrap()
}

fn single(input: &Path, out: &Path, options: &[&str]) -> Vec<u8> {
    let run = bake(args(input, out, options));
    assert!(run.ok(), "{}", run.stderr);
    std::fs::read(out).unwrap()
}

#[test]
fn tasks_merged_in_any_order_give_the_single_bake_bytes() {
    let dir = scratch("distributed-bytes");
    let input = floor(&dir);
    let one = single(&input, &dir.join("one.glb"), &[]);
    let three = sharded(&input, &dir.join("three.glb"), &[], 3, &[2, 0, 1]);
    assert!(
        one == three,
        "3 tasks: the merged output differs from the single bake"
    );
    // Every vertex gathered (no sharing: the other code path), with probes and a working plane.
    let options = [
        "--quality",
        "draft",
        "--receiver-tolerance",
        "0",
        "--working-plane",
        "0.75",
    ];
    let one = single(&input, &dir.join("one-full.glb"), &options);
    let two = sharded(&input, &dir.join("two-full.glb"), &options, 2, &[1, 0]);
    assert!(one == two, "2 tasks, no sharing: the merged output differs");
}

#[test]
fn a_missing_or_foreign_task_fails_the_merge_with_no_output() {
    let dir = scratch("distributed-errors");
    let input = floor(&dir);
    let out = dir.join("out.glb");
    let state = dir.join("state");
    let s = state.to_str().unwrap();
    let draft = ["--quality", "draft"];
    assert!(bake(step("plan", s, &["--tasks", "2"], &input, &out, &draft)).ok());
    assert!(bake(step("gather", s, &["--task", "0"], &input, &out, &draft)).ok());

    // Task 1 never ran.
    let merge = step("merge", s, &[], &input, &out, &draft);
    let run = bake(&merge);
    assert!(
        !run.ok() && run.stderr.contains("task-1.bin"),
        "{}",
        run.stderr
    );
    assert!(!out.exists());

    // A task run with other settings, and a task the plan does not have.
    let other = ["--quality", "default"];
    let run = bake(step("gather", s, &["--task", "1"], &input, &out, &other));
    assert!(
        !run.ok() && run.stderr.contains("settings differ"),
        "{}",
        run.stderr
    );
    let run = bake(step("gather", s, &["--task", "2"], &input, &out, &draft));
    assert!(
        !run.ok() && run.stderr.contains("task 2 is not in the plan"),
        "{}",
        run.stderr
    );

    // A task given another scene file than the plan's.
    let other_dir = dir.join("other");
    std::fs::create_dir_all(&other_dir).unwrap();
    let other_input = floor_of(&other_dir, "2");
    let one = ["--task", "1"];
    let run = bake(step("gather", s, &one, &other_input, &out, &draft));
    assert!(
        !run.ok() && run.stderr.contains("not the scene the plan meshed"),
        "{}",
        run.stderr
    );
    assert!(!state.join("task-1.bin").exists());

    // A damaged task file: named, and nothing written.
    std::fs::copy(state.join("task-0.bin"), state.join("task-1.bin")).unwrap();
    let bytes = std::fs::read(state.join("task-0.bin")).unwrap();
    std::fs::write(state.join("task-0.bin"), &bytes[..bytes.len() / 2]).unwrap();
    let run = bake(&merge);
    assert!(
        !run.ok() && run.stderr.contains("task-0.bin"),
        "{}",
        run.stderr
    );
    assert!(!out.exists());
    // 64 bytes flipped anywhere (issue 59: this panicked, or merged wrong values): damaged.
    for at in [100, 1000, bytes.len() / 3, bytes.len() / 2] {
        let mut bad = bytes.clone();
        bad[at..at + 64].iter_mut().for_each(|b| *b ^= 0xff);
        std::fs::write(state.join("task-0.bin"), &bad).unwrap();
        let run = bake(&merge);
        assert_eq!(run.code, Some(1), "flipped at {at}: {}", run.stderr);
        assert!(
            run.stderr.contains("task-0.bin") && run.stderr.contains("damaged"),
            "{}",
            run.stderr
        );
        assert!(!out.exists());
    }
    // Whole again, but task 1's file is task 0's result.
    std::fs::write(state.join("task-0.bin"), &bytes).unwrap();
    let run = bake(&merge);
    assert!(
        !run.ok() && run.stderr.contains("once each"),
        "{}",
        run.stderr
    );
    assert!(!out.exists());
}

#[test]
fn a_local_dask_cluster_bakes_the_single_bake_bytes() {
    if !tools::have_dask() {
        return;
    }
    let python = tools::dask_python().unwrap();
    let dir = scratch("distributed-dask");
    let input = floor(&dir);
    let options = ["--quality", "draft"];
    let one = single(&input, &dir.join("one.glb"), &options);
    let out = dir.join("dask.glb");
    let timings = dir.join("timings.json");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("dask/dask_bake.py");
    let run = std::process::Command::new(python)
        .arg(script)
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .args([
            "--local-workers",
            "2",
            "--tasks",
            "3",
            "--bake",
            env!("CARGO_BIN_EXE_bake"),
        ])
        .arg("--timings")
        .arg(&timings)
        .arg("--")
        .args(options)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "dask_bake.py failed: {stderr}");
    assert!(
        one == std::fs::read(&out).unwrap(),
        "the Dask bake differs from the single bake"
    );
    let t: serde_json::Value = serde_json::from_slice(&std::fs::read(&timings).unwrap()).unwrap();
    assert!(t.to_string().contains("merge"), "{t}");
}

/// A bake wrapper for `dask_bake.py --bake`: gather task 1 fails (exit 3) on its first `fails`
/// attempts, counted in DIR/attempts; every other call is the real bake.
fn flaky_bake(dir: &Path, fails: u32) -> PathBuf {
    let script = dir.join(format!("flaky-{fails}.sh"));
    let count = dir.join(format!("attempts-{fails}"));
    let text = format!(
        "#!/bin/sh\ncase \" $* \" in *\" gather \"*\" --task 1 \"*)\n  \
         n=$(cat '{c}' 2>/dev/null || echo 0); n=$((n + 1)); echo $n > '{c}'\n  \
         if [ $n -le {fails} ]; then echo 'injected failure' >&2; exit 3; fi;;\nesac\n\
         exec '{bake}' \"$@\"\n",
        c = count.display(),
        bake = env!("CARGO_BIN_EXE_bake"),
    );
    std::fs::write(&script, text).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    script
}

/// `dask_bake.py IN -o OUT --local-workers 2 --tasks 3 --bake BAKE -- --quality draft`.
fn dask_run(python: &Path, input: &Path, out: &Path, bake: &Path) -> std::process::Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("dask/dask_bake.py");
    std::process::Command::new(python)
        .arg(script)
        .arg(input)
        .arg("-o")
        .arg(out)
        .args(["--local-workers", "2", "--tasks", "3", "--bake"])
        .arg(bake)
        .args(["--", "--quality", "draft"])
        .output()
        .unwrap()
}

/// The driver's promises (dask/README.md): a failed gather task is retried once and the bake
/// still gives the single bake's bytes; a task failing twice fails the run with exit 1, naming
/// the task and its stderr, writing no output; bad arguments exit 2.
#[test]
fn dask_retries_a_failed_task_once_and_exits_1_when_it_fails_again() {
    if !tools::have_dask() {
        return;
    }
    let python = tools::dask_python().unwrap();
    let dir = scratch("distributed-dask-retry");
    let input = floor(&dir);
    let one = single(&input, &dir.join("one.glb"), &["--quality", "draft"]);

    let out = dir.join("retried.glb");
    let run = dask_run(&python, &input, &out, &flaky_bake(&dir, 1));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    let attempts = std::fs::read_to_string(dir.join("attempts-1")).unwrap();
    assert_eq!(attempts.trim(), "2", "task 1 ran {attempts} times");
    assert!(
        one == std::fs::read(&out).unwrap(),
        "the retried bake differs"
    );

    let out = dir.join("failed.glb");
    let run = dask_run(&python, &input, &out, &flaky_bake(&dir, 2));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("gather task 1 failed") && stderr.contains("injected failure"),
        "{stderr}"
    );
    let attempts = std::fs::read_to_string(dir.join("attempts-2")).unwrap();
    assert_eq!(attempts.trim(), "2", "task 1 ran {attempts} times");
    assert!(!out.exists(), "a failed run wrote its output");

    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("dask/dask_bake.py");
    let run = std::process::Command::new(&python)
        .arg(script)
        .arg(&input)
        .args(["-o", "x.glb", "--local-workers", "0"])
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2), "{run:?}");
}
