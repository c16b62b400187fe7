//! Figures that cannot go stale (issue 58, item 2): every results page under bench/results/
//! names, in a `Provenance:` line under its title, the commit its figures were measured at (a
//! commit `git cat-file -e HASH^{commit}` accepts), the date (YYYY-MM-DD), the machine and the
//! command that regenerates it, and is named in bench/regenerate.sh; every picture of the manual
//! (each picture file under docs/, and each picture under bench/results/ that a page of docs/ or
//! the README shows) is named in bench/regenerate.sh, literally or by a `*` pattern, as a file a
//! step writes. Skipped, with a message, only when git or the .git directory is absent (a source
//! tarball), never under CI=true.

use std::path::{Path, PathBuf};
use std::process::Command;

const PICTURES: [&str; 3] = ["png", "svg", "jpg"];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn git(args: &[&str]) -> Option<std::process::Output> {
    Command::new("git")
        .args(args)
        .current_dir(repo())
        .output()
        .ok()
}

/// git and the repository's .git (a directory, or a file in a worktree), else a skip message.
fn git_available() -> Result<(), String> {
    if !repo().join(".git").exists() {
        return Err("no .git in the source tree".into());
    }
    match git(&["rev-parse", "--git-dir"]) {
        Some(o) if o.status.success() => Ok(()),
        Some(o) => Err(format!(
            "git rev-parse failed: {}",
            String::from_utf8_lossy(&o.stderr)
        )),
        None => Err("git cannot be run".into()),
    }
}

/// A shallow clone (CI may fetch only the last commit) cannot say whether an older hash is a
/// commit: then only the hash's form is checked.
fn shallow() -> bool {
    git(&["rev-parse", "--is-shallow-repository"])
        .is_some_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "true")
}

fn skip_or_fail() -> bool {
    if let Err(why) = git_available() {
        if std::env::var("CI").as_deref() == Ok("true") {
            panic!("results_provenance: {why}, and CI=true: the check must run in CI");
        }
        println!("results_provenance skipped: {why}");
        return true;
    }
    false
}

fn is_commit(hash: &str) -> bool {
    git(&["cat-file", "-e", &format!("{hash}^{{commit}}")]).is_some_and(|o| o.status.success())
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            walk(&p, out);
        } else {
            out.push(p);
        }
    }
}

fn files_under(rel: &str, pred: impl Fn(&Path) -> bool) -> Vec<String> {
    let mut all = Vec::new();
    walk(&repo().join(rel), &mut all);
    let mut out: Vec<String> = all
        .into_iter()
        .filter(|p| pred(p))
        .map(|p| {
            p.strip_prefix(repo())
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .collect();
    out.sort();
    out
}

fn has_ext(p: &Path, exts: &[&str]) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| exts.contains(&e))
}

fn regenerate_script() -> String {
    std::fs::read_to_string(repo().join("bench/regenerate.sh"))
        .expect("bench/regenerate.sh is missing: it must regenerate every results file")
}

/// The path-like words of bench/regenerate.sh (those with a '/'), quotes and brackets stripped.
fn script_paths(script: &str) -> Vec<String> {
    script
        .split(|c: char| c.is_whitespace() || "\"'()`;,".contains(c))
        .filter(|w| w.contains('/') && !w.starts_with('$'))
        .map(str::to_string)
        .collect()
}

/// `pattern` matches `path`, '*' standing for any run of characters other than '/'.
fn glob(pattern: &str, path: &str) -> bool {
    let (p, s) = (pattern.as_bytes(), path.as_bytes());
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < s.len() {
        if i < p.len() && p[i] == b'*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if i < p.len() && p[i] == s[j] {
            i += 1;
            j += 1;
        } else if let Some(st) = star {
            if s[mark] == b'/' {
                return false;
            }
            mark += 1;
            i = st + 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == b'*')
}

fn named_in_script(paths: &[String], file: &str) -> bool {
    paths
        .iter()
        .any(|p| p == file || (p.contains('*') && glob(p, file)))
}

/// What a provenance line lacks: an existing commit, a date, a machine, a command.
fn provenance_problems(file: &str, text: &str) -> Vec<String> {
    let Some(line) = text.lines().take(40).find(|l| l.starts_with("Provenance:")) else {
        return vec![format!(
            "{file}: no `Provenance: commit HASH …; date YYYY-MM-DD; machine: …; regenerate: …` \
             line in its first 40 lines"
        )];
    };
    let mut out = Vec::new();
    let hash: String = line
        .split_once("commit ")
        .map(|(_, rest)| rest.chars().take_while(char::is_ascii_hexdigit).collect())
        .unwrap_or_default();
    if !(7..=40).contains(&hash.len()) {
        out.push(format!(
            "{file}: its provenance line names no commit hash (`commit HASH`)"
        ));
    } else if !shallow() && !is_commit(&hash) {
        out.push(format!(
            "{file}: its provenance line's commit {hash} is not a commit of this repository \
             (`git cat-file -e {hash}^{{commit}}` fails)"
        ));
    }
    let has_date = line.as_bytes().windows(10).any(|w| {
        w.iter().enumerate().all(|(k, c)| {
            if k == 4 || k == 7 {
                *c == b'-'
            } else {
                c.is_ascii_digit()
            }
        })
    });
    if !has_date {
        out.push(format!(
            "{file}: its provenance line has no date (YYYY-MM-DD)"
        ));
    }
    if !line.contains("machine: ") {
        out.push(format!(
            "{file}: its provenance line names no machine (`machine: …`)"
        ));
    }
    if !line.contains("regenerate: ") {
        out.push(format!(
            "{file}: its provenance line names no command (`regenerate: …`)"
        ));
    }
    out
}

#[test]
fn results_pages_name_commit_date_machine_and_are_regenerated() {
    if skip_or_fail() {
        return;
    }
    let script = regenerate_script();
    let paths = script_paths(&script);
    let pages = files_under("bench/results", |p| has_ext(p, &["md"]));
    assert!(!pages.is_empty(), "no Markdown under bench/results/");
    let mut problems = Vec::new();
    for page in &pages {
        let text = std::fs::read_to_string(repo().join(page)).unwrap();
        problems.extend(provenance_problems(page, &text));
        if !named_in_script(&paths, page) {
            problems.push(format!(
                "{page}: not named in bench/regenerate.sh (no step lists it among the files it \
                 writes)"
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "{} problem(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
    println!(
        "{} results pages: provenance and regenerate.sh entries present",
        pages.len()
    );
}

/// The pictures a Markdown page shows: `](x.png)` and `src="x.png"` targets, relative to it.
fn shown_pictures(page: &str, text: &str) -> Vec<String> {
    let dir = Path::new(page).parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    let mut rest = text;
    loop {
        let (a, b) = (rest.find("]("), rest.find("src=\""));
        let (at, skip, end) = match (a, b) {
            (Some(a), Some(b)) if b < a => (b, 5, '"'),
            (Some(a), _) => (a, 2, ')'),
            (None, Some(b)) => (b, 5, '"'),
            (None, None) => break,
        };
        let tail = &rest[at + skip..];
        let target = tail
            .split(end)
            .next()
            .unwrap_or("")
            .split('#')
            .next()
            .unwrap_or("");
        let target = target.split_whitespace().next().unwrap_or("");
        if !target.contains("://") && has_ext(Path::new(target), &PICTURES) {
            let mut parts: Vec<String> = Vec::new();
            for c in dir.join(target).components() {
                match c {
                    std::path::Component::ParentDir => {
                        parts.pop();
                    }
                    std::path::Component::Normal(s) => parts.push(s.to_string_lossy().into()),
                    _ => {}
                }
            }
            out.push(parts.join("/"));
        }
        rest = tail;
    }
    out
}

#[test]
fn manual_pictures_are_written_by_regenerate_sh() {
    if skip_or_fail() {
        return;
    }
    let script = regenerate_script();
    let paths = script_paths(&script);
    let mut pictures = files_under("docs", |p| has_ext(p, &PICTURES));
    let mut pages = files_under("docs", |p| has_ext(p, &["md"]));
    pages.push("README.md".into());
    for page in &pages {
        let text = std::fs::read_to_string(repo().join(page)).unwrap();
        for pic in shown_pictures(page, &text) {
            if pic.starts_with("bench/results/") || pic.starts_with("docs/") {
                pictures.push(pic);
            }
        }
    }
    pictures.sort();
    pictures.dedup();
    let missing: Vec<String> = pictures
        .iter()
        .filter(|p| !named_in_script(&paths, p))
        .map(|p| format!("{p}: a picture of the manual that no step of bench/regenerate.sh writes"))
        .collect();
    assert!(
        missing.is_empty(),
        "{} picture(s):\n{}",
        missing.len(),
        missing.join("\n")
    );
    println!(
        "{} manual pictures, each written by a step of bench/regenerate.sh",
        pictures.len()
    );
}

#[test]
fn glob_patterns() {
    assert!(glob(
        "docs/renders/after-*.png",
        "docs/renders/after-office-vertex-view.png"
    ));
    assert!(!glob(
        "docs/renders/after-*.png",
        "docs/renders/before-office-vertex-view.png"
    ));
    assert!(!glob("docs/*.png", "docs/renders/x.png"));
    assert!(glob(
        "docs/office-*.png",
        "docs/office-front-false-colour.png"
    ));
}
