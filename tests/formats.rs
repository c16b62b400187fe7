//! Every output's format follows its file extension (issue 57, `cli/formats.rs`), or the run is
//! refused before any work with one error line naming the flag and the path, and nothing is
//! written: `bake view -o x.exr|x.png` (and its `.png` pictures), `bake luminaire --polar x.svg`,
//! `bake plan -o x.svg|x.png`, `bake report -o x.txt|md|csv|json|html`.

mod support;

use std::path::Path;
use support::cli::{Mini, assert_error_line, bake, bake_draft, listing, repo_file};
use support::scratch;

const PNG: &[u8] = b"\x89PNG\r\n\x1a\n";
const EXR: &[u8] = &[0x76, 0x2f, 0x31, 0x01];

fn starts(path: &Path, magic: &[u8]) -> bool {
    std::fs::read(path).is_ok_and(|b| b.starts_with(magic))
}

#[test]
fn view_report_plan_and_polar_write_what_their_extension_names() {
    let dir = scratch("formats");
    let input = Mini::new().write_gltf(&dir, "mini.gltf", Some("mini.bin"));
    let lit = dir.join("lit.gltf");
    let run = bake_draft(&input, &lit, &["--working-plane", "0.5"]);
    assert!(run.ok(), "{run:?}");
    let lit = lit.to_str().unwrap();
    let view = [
        "--eye", "0,0.5,0", "--target", "0,1,0", "--up", "0,0,1", "--size", "40x30",
    ];
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();

    // bake view: .exr is the luminance image, .png the tone-mapped view.
    for (name, magic) in [("v.exr", EXR), ("v.png", PNG), ("V.PNG", PNG)] {
        let mut args = vec!["view", lit, "-o"];
        let o = out(name);
        args.push(&o);
        args.extend(view);
        let run = bake(args);
        assert!(run.ok(), "{name}: {run:?}");
        assert!(starts(&dir.join(name), magic), "{name}");
    }
    // Refused, nothing written: a view under another format's name, a PNG picture that is not.
    let before = listing(&dir);
    for (flag, name) in [
        ("-o", "v.jpg"),
        ("-o", "v"),
        ("--display", "d.exr"),
        ("--png", "p.svg"),
        ("--false-colour", "f.jpeg"),
    ] {
        let o = out(name);
        let mut args = vec!["view", lit];
        let main = out("ok.exr");
        match flag {
            "-o" => args.extend(["-o", o.as_str()]),
            _ => args.extend(["-o", main.as_str(), flag, o.as_str()]),
        }
        args.extend(view);
        let run = bake(args);
        assert_eq!(run.code, Some(2), "{flag} {name}: {run:?}");
        assert_error_line(&run, &[flag, name, ".png"]);
    }
    assert_eq!(listing(&dir), before, "nothing written");

    // bake report: the extension names the format; --format must agree with it.
    for (name, needle) in [
        ("r.md", "| "),
        ("r.json", "{"),
        ("r.csv", ","),
        ("r.html", "<!DOCTYPE"),
    ] {
        let o = out(name);
        let run = bake(["report", lit, "-o", o.as_str()]);
        assert!(run.ok(), "{name}: {run:?}");
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(
            text.trim_start().starts_with(needle) || text.contains(needle),
            "{name}"
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("r.json")).unwrap()).unwrap();
    assert!(json.is_object());
    let before = listing(&dir);
    let (o1, o2) = (out("x.html"), out("x.pdf"));
    for args in [
        vec!["report", lit, "--format", "json", "-o", o1.as_str()],
        vec!["report", lit, "-o", o2.as_str()],
    ] {
        let run = bake(args.clone());
        assert_eq!(run.code, Some(2), "{args:?}: {run:?}");
        assert_error_line(&run, &["-o"]);
    }
    assert_eq!(listing(&dir), before, "nothing written");

    // bake luminaire --polar: SVG only.
    let ies = repo_file("samples/office/profiles/miral_58w.ies");
    let ies = ies.to_str().unwrap();
    let (svg, png) = (out("polar.svg"), out("polar.png"));
    assert!(bake(["luminaire", ies, "--polar", svg.as_str()]).ok());
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    let run = bake(["luminaire", ies, "--polar", png.as_str()]);
    assert_eq!(run.code, Some(2), "{run:?}");
    assert_error_line(&run, &["--polar", "polar.png", ".svg"]);
    assert!(!dir.join("polar.png").exists());
}
