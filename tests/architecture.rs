//! The layers of ARCHITECTURE.md hold in the code: every `use crate::…` and `super::…` of
//! `src/` (outside `#[cfg(test)]` modules and comments) runs down the table's rows or stays in
//! its own module, and no files import each other round a loop (a module's `mod.rs` declaring
//! and re-exporting its own children is not an import of them).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Top-level module of each row of ARCHITECTURE.md's layer table (`bake`, `summary`, …), with
/// its row number (1 at the top).
fn rows() -> BTreeMap<String, usize> {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let table = text
        .split("## Layers")
        .nth(1)
        .expect("ARCHITECTURE.md has a Layers section");
    let mut out = BTreeMap::new();
    for line in table
        .lines()
        .skip_while(|l| !l.starts_with("| row"))
        .skip(2)
    {
        if !line.starts_with('|') {
            break;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let row: usize = cells[1].parse().expect("a row number");
        for module in cells[2].split(',') {
            let name = module.trim().trim_matches('`');
            let name = name.trim_end_matches('/').trim_end_matches(".rs");
            assert!(out.insert(name.to_string(), row).is_none(), "{name} twice");
        }
    }
    assert!(out.len() > 10, "the layer table was not found: {out:?}");
    out
}

/// Every `.rs` file under `src/`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file: `src/bake/direct.rs` → [bake, direct]; `src/bake/mod.rs` → [bake].
fn module_of(file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(root().join("src")).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    // `src/lib.rs` and `src/main.rs` keep their names; `m/mod.rs` is `m`.
    if parts.len() > 1 && parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// The code of a file without comments and without the items `#[cfg(test)]` marks (a test
/// module, a test-only function or import), wherever they are: the rest of the file is read.
fn code(text: &str) -> String {
    let mut out = String::new();
    // Inside a `#[cfg(test)]` item: its brace depth, and whether its body has opened.
    let mut skipping: Option<(i64, bool)> = None;
    for line in text.lines() {
        let line = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        if line.trim_start().starts_with("#[cfg(test)]") {
            skipping = Some((0, false));
            continue;
        }
        if let Some((depth, opened)) = skipping.as_mut() {
            for c in line.chars() {
                match c {
                    '{' => {
                        *depth += 1;
                        *opened = true;
                    }
                    '}' => *depth -= 1,
                    _ => {}
                }
            }
            let done = (*opened && *depth <= 0) || (!*opened && line.trim_end().ends_with(';'));
            if done {
                skipping = None;
            }
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The paths a file names after `crate::` or `super::` (brace groups expanded), as segments.
fn paths(code: &str, anchor: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find(anchor) {
        let before = rest[..i].chars().last();
        rest = &rest[i + anchor.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue; // `super::super::` is handled as a path segment below
        }
        expand(rest, Vec::new(), &mut out);
    }
    out
}

/// Parse one path (possibly a `{…}` group) at the start of `s` after `prefix`.
fn expand(s: &str, prefix: Vec<String>, out: &mut Vec<Vec<String>>) {
    let s = s.trim_start();
    if let Some(inner) = s.strip_prefix('{') {
        let mut depth = 0;
        let mut start = 0;
        for (i, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => {
                    expand(&inner[start..i], prefix.clone(), out);
                    return;
                }
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    expand(&inner[start..i], prefix.clone(), out);
                    start = i + 1;
                }
                _ => {}
            }
        }
        return;
    }
    let ident: String = s
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    if ident.is_empty() {
        if !prefix.is_empty() {
            out.push(prefix);
        }
        return;
    }
    let mut path = prefix;
    path.push(ident.clone());
    match s[ident.len()..].strip_prefix("::") {
        Some(more) => expand(more, path, out),
        None => out.push(path),
    }
}

/// The file a path names, given the modules that exist: the longest prefix that is a module.
fn resolve(path: &[String], files: &BTreeMap<Vec<String>, PathBuf>) -> Option<Vec<String>> {
    (1..=path.len())
        .rev()
        .map(|n| path[..n].to_vec())
        .find(|p| files.contains_key(p))
}

#[test]
fn imports_run_down_the_layers_without_loops() {
    let rows = rows();
    let mut all = Vec::new();
    sources(&root().join("src"), &mut all);
    let files: BTreeMap<Vec<String>, PathBuf> =
        all.iter().map(|f| (module_of(f), f.clone())).collect();
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    let mut wrong = Vec::new();
    for (module, file) in &files {
        if module.is_empty() || module[0] == "main" {
            continue; // lib.rs and the binary's root
        }
        let text = code(&std::fs::read_to_string(file).unwrap());
        let own = &module[0];
        let own_row = *rows
            .get(own)
            .unwrap_or_else(|| panic!("{own} is in no row of ARCHITECTURE.md's layer table"));
        let mut targets = paths(&text, "crate::");
        // `super::` names the enclosing module (for m/mod.rs and m/a.rs alike, one up).
        let parent: Vec<String> = module[..module.len() - 1].to_vec();
        for p in paths(&text, "super::") {
            let mut base = parent.clone();
            let mut rest = p.as_slice();
            while rest.first().is_some_and(|s| s == "super") {
                base.pop();
                rest = &rest[1..];
            }
            base.extend(rest.iter().cloned());
            targets.push(base);
        }
        for target in targets {
            let Some(first) = target.first() else {
                continue;
            };
            if first.chars().next().is_some_and(char::is_uppercase) {
                continue; // `crate::Error`, `crate::Result`: lib.rs re-exports
            }
            if let Some(&row) = rows.get(first)
                && first != own
                && row <= own_row
            {
                let shown = file.strip_prefix(root()).unwrap_or(file).display();
                wrong.push(format!("{shown} (row {own_row}) → {first} (row {row})"));
            }
            // A module's own children are its parts, not imports (a `mod.rs` declares and
            // re-exports them; they may use its items).
            if let Some(to) = resolve(&target, &files)
                && !to.starts_with(module)
                && !to.is_empty()
            {
                edges.entry(module.clone()).or_default().insert(to);
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports running up the layers:\n{}",
        wrong.join("\n")
    );

    // No loop between files: a depth-first search finds no back edge.
    let mut state: BTreeMap<&Vec<String>, u8> = BTreeMap::new(); // 1 on the stack, 2 done
    fn visit<'a>(
        m: &'a Vec<String>,
        edges: &'a BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        state: &mut BTreeMap<&'a Vec<String>, u8>,
        stack: &mut Vec<&'a Vec<String>>,
    ) -> Option<String> {
        state.insert(m, 1);
        stack.push(m);
        for to in edges.get(m).into_iter().flatten() {
            match state.get(to) {
                Some(1) => {
                    let at = stack.iter().position(|s| *s == to).unwrap();
                    let names: Vec<String> = stack[at..].iter().map(|s| s.join("::")).collect();
                    return Some(format!("{} → {}", names.join(" → "), to.join("::")));
                }
                Some(_) => {}
                None => {
                    if let Some(found) = visit(to, edges, state, stack) {
                        return Some(found);
                    }
                }
            }
        }
        stack.pop();
        state.insert(m, 2);
        None
    }
    for m in edges.keys() {
        if !state.contains_key(m) {
            let mut stack = Vec::new();
            if let Some(found) = visit(m, &edges, &mut state, &mut stack) {
                panic!("files importing each other round a loop: {found}");
            }
        }
    }
    eprintln!(
        "{} files, {} imports between them, none up a layer, no loop",
        files.len(),
        edges.values().map(BTreeSet::len).sum::<usize>()
    );
}

#[test]
fn test_items_are_skipped_wherever_they_are_and_the_rest_is_read() {
    let text = "use crate::a::X; // comment use crate::z\n\
                #[cfg(test)]\n\
                use crate::t::Y;\n\
                #[cfg(test)]\n\
                mod tests {\n    use crate::u::Z;\n    fn f() { if true { } }\n}\n\
                use crate::b::W;\n";
    let c = code(text);
    assert!(
        c.contains("crate::a::X") && c.contains("crate::b::W"),
        "{c}"
    );
    for hidden in ["crate::z", "crate::t", "crate::u"] {
        assert!(!c.contains(hidden), "{hidden} read in {c}");
    }
}
