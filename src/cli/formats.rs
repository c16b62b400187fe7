//! Output formats follow the output's file extension: each subcommand names the extensions an
//! output may have, and a path with any other is refused before any work, naming the flag, the
//! path and what to use instead (never a file of one format under another's name).

use luxbake::Error;
use std::path::Path;

/// The lowercased extension of `path` when it is one of `allowed` (lowercase, without the dot);
/// else an error `FLAG PATH: WHAT is written as .A or .B`.
pub fn extension(path: &Path, flag: &str, allowed: &[&str], what: &str) -> Result<String, Error> {
    let ext = (path.extension().and_then(|e| e.to_str()))
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if allowed.contains(&ext.as_str()) {
        return Ok(ext);
    }
    let list: Vec<String> = allowed.iter().map(|a| format!(".{a}")).collect();
    let found = match ext.is_empty() {
        true => "no extension".to_string(),
        false => format!("'.{ext}'"),
    };
    Err(Error::Settings(format!(
        "{flag} {}: {what} is written as {} (the format follows the extension; {found} given)",
        path.display(),
        list.join(" or ")
    )))
}

#[cfg(test)]
mod tests {
    use super::extension;
    use std::path::Path;

    #[test]
    fn extensions_are_matched_without_case_and_others_refused() {
        let ok = |p: &str| extension(Path::new(p), "-o", &["exr", "png"], "a view");
        assert_eq!(ok("a/view.EXR").unwrap(), "exr");
        assert_eq!(ok("view.png").unwrap(), "png");
        for bad in ["view.jpg", "view", "view.png.tmp"] {
            let e = ok(bad).unwrap_err().to_string();
            assert!(e.contains(".exr or .png") && e.contains(bad), "{e}");
        }
    }
}
