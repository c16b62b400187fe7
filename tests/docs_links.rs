//! Every relative link in the repository's Markdown (README, manual, ARCHITECTURE, bench and
//! sample notes) points at a file that exists, and every `#anchor` at a heading of that file
//! (GitHub's slugs: lower case, punctuation dropped, spaces as hyphens, repeats numbered).
//! Links in code blocks and inline code are not links and are skipped.

mod support;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The tracked Markdown files (git ls-files), or every `.md` under the repository's own
/// folders when git is absent (a source tarball).
fn markdown_files() -> Vec<PathBuf> {
    let out = std::process::Command::new("git")
        .args(["ls-files", "*.md"])
        .current_dir(repo())
        .output();
    let listed: Vec<PathBuf> = match out {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
            .lines()
            .map(|l| repo().join(l))
            .collect(),
        _ => walk(&repo()),
    };
    listed
        .into_iter()
        .filter(|p| p.exists())
        .filter(|p| {
            let s = p.to_string_lossy();
            !s.contains("node_modules") && !s.contains("/fuzz/corpus") && !s.contains("/target/")
        })
        .collect()
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || name == "target" || name == "node_modules" {
            continue;
        }
        if p.is_dir() {
            out.extend(walk(&p));
        } else if name.ends_with(".md") {
            out.push(p);
        }
    }
    out
}

/// The text with fenced code blocks and inline code blanked out (line structure kept).
fn prose(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            out.push('\n');
            continue;
        }
        if fenced {
            out.push('\n');
            continue;
        }
        let mut code = false;
        for c in line.chars() {
            if c == '`' {
                code = !code;
                out.push(' ');
            } else {
                out.push(if code { ' ' } else { c });
            }
        }
        out.push('\n');
    }
    out
}

/// `(line, target)` of every inline link `[text](target)` and image `![alt](target)`.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in prose(text).lines().enumerate() {
        let b = line.as_bytes();
        let mut i = 0;
        while let Some(k) = line[i..].find("](") {
            let start = i + k + 2;
            let mut depth = 1;
            let mut end = start;
            while end < b.len() && depth > 0 {
                match b[end] {
                    b'(' => depth += 1,
                    b')' => depth -= 1,
                    _ => {}
                }
                end += 1;
            }
            if depth == 0 {
                let target = line[start..end - 1].split_whitespace().next().unwrap_or("");
                out.push((n + 1, target.trim_matches(['<', '>']).to_string()));
            }
            i = end.max(start);
        }
    }
    out
}

/// GitHub's anchors of a Markdown file's headings.
fn anchors(text: &str) -> HashSet<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = HashSet::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if fenced || !line.starts_with('#') {
            continue;
        }
        let title = line.trim_start_matches('#').trim();
        let slug: String = title
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        let n = seen.entry(slug.clone()).or_insert(0);
        out.insert(if *n == 0 {
            slug.clone()
        } else {
            format!("{slug}-{n}")
        });
        *n += 1;
    }
    // Explicit HTML anchors.
    for part in text.split("<a id=\"").skip(1) {
        if let Some(end) = part.find('"') {
            out.insert(part[..end].to_string());
        }
    }
    out
}

#[test]
fn every_relative_link_and_anchor_in_the_docs_resolves() {
    let files = markdown_files();
    assert!(
        files.len() >= 10,
        "only {} Markdown files found",
        files.len()
    );
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (line, target) in links(&text) {
            if target.is_empty()
                || target.contains("://")
                || target.starts_with("mailto:")
                || target.starts_with('{')
            {
                continue;
            }
            checked += 1;
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let resolved = if path.is_empty() {
                file.clone()
            } else {
                file.parent().unwrap().join(path)
            };
            let name = file.strip_prefix(repo()).unwrap_or(file).display();
            if !resolved.exists() {
                broken.push(format!("{name}:{line}: {target}: no such file"));
                continue;
            }
            if let Some(a) = anchor
                && resolved.extension().is_some_and(|e| e == "md")
                && !anchors(&std::fs::read_to_string(&resolved).unwrap()).contains(a)
            {
                broken.push(format!("{name}:{line}: {target}: no heading #{a}"));
            }
        }
    }
    assert!(checked > 50, "only {checked} links checked");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_checker_sees_links_and_anchors() {
    let text = "# A title: with `code`, punctuation!\n## Again\n## Again\n\
                see [x](a.md#b) and ![img](p.png), not `[y](z.md)`\n```\n[q](r.md)\n```\n";
    assert_eq!(
        links(text),
        vec![(4, "a.md#b".to_string()), (4, "p.png".to_string())]
    );
    let a = anchors(text);
    for want in ["a-title-with-code-punctuation", "again", "again-1"] {
        assert!(a.contains(want), "{want} not in {a:?}");
    }
}

/// The manual (docs/, an mdBook) builds without a warning; every chapter of SUMMARY.md becomes a
/// page.
#[test]
fn the_manual_builds_with_mdbook() {
    let Some(mdbook) = support::tools::mdbook() else {
        return;
    };
    let out = support::scratch("docs-book");
    let run = std::process::Command::new(mdbook)
        .arg("build")
        .arg(repo().join("docs"))
        .arg("--dest-dir")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "mdbook build failed:\n{stderr}");
    assert!(
        !stderr.contains("WARN") && !stderr.contains("ERROR"),
        "mdbook warned:\n{stderr}"
    );
    let summary = std::fs::read_to_string(repo().join("docs/SUMMARY.md")).unwrap();
    let mut pages = 0;
    for (_, target) in links(&summary) {
        // mdBook makes a folder's README.md its index.html.
        let page = out.join(
            target
                .replace("README.md", "index.md")
                .replace(".md", ".html"),
        );
        assert!(page.is_file(), "{} not built", page.display());
        pages += 1;
    }
    assert!(pages >= 15, "only {pages} chapters in SUMMARY.md");
}

/// The README stays a page: at most 200 lines, opening with the two set-up commands, and every
/// subcommand `bake --help` lists is in its tour with a link into the manual.
#[test]
fn the_readme_is_short_and_tours_every_subcommand() {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 200, "README.md has {lines} lines");
    let commands = "```\ncargo run --release -- samples/office/office.gltf -o office-lit.gltf\n\
                    cargo test --release\n```";
    assert!(
        readme.starts_with(&format!("# luxbake\n\n{commands}")),
        "README.md does not open with the two set-up commands"
    );
    let help = support::cli::bake(["--help"]);
    assert!(help.ok(), "{}", help.stderr);
    let listed: Vec<&str> = help
        .stdout
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(listed.len() >= 8, "{listed:?}");
    for c in listed {
        let row = readme
            .lines()
            .find(|l| l.starts_with(&format!("| `bake {c}")))
            .unwrap_or_else(|| panic!("`bake {c}` is not in the README's tour"));
        assert!(row.contains("](docs/"), "`bake {c}`'s row links no chapter");
    }
}

/// The manual's closed-form table is the one `bench/closed_forms.py` last wrote
/// (`bench/results/closed_forms.md`), row for row: a rerun updates both or the test fails.
#[test]
fn the_manuals_closed_form_table_is_the_generated_one() {
    let rows = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with('|'))
            .map(str::to_string)
            .collect()
    };
    let manual = std::fs::read_to_string(repo().join("docs/accuracy.md")).unwrap();
    let begin = "<!-- closed-forms table: bench/closed_forms.py writes it -->";
    let end = "<!-- end of closed-forms table -->";
    let inside = manual
        .split_once(begin)
        .and_then(|(_, r)| r.split_once(end))
        .map(|(t, _)| t)
        .expect("docs/accuracy.md has the closed-forms table's markers");
    let generated = std::fs::read_to_string(repo().join("bench/results/closed_forms.md")).unwrap();
    let (a, b) = (rows(inside), rows(&generated));
    assert!(a.len() > 20, "{} rows", a.len());
    assert_eq!(
        a, b,
        "docs/accuracy.md's table is not bench/results/closed_forms.md's"
    );
}
