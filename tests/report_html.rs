//! The designer's report document (`bake report --format html`, `src/html_report/`): on the sample
//! office baked at draft quality — self-contained (no network reference, no script, images as
//! `data:` URIs), every section there, the numbers those of the JSON report of the same bake,
//! deterministic bytes; and in headless Chromium (skipped when absent, failed under CI): a
//! screenshot that is not blank, the tables in the rendered DOM, and a PDF on A4 pages; bad
//! `--border` values are usage errors (exit 2), `-o` never overwrites the input.

mod support;

use serde_json::Value;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use support::cli::{bake, bake_draft, repo_file};
use support::scratch;
use support::tools::{chromium, have_chromium};

/// The office baked at draft with a working plane and a probe grid, and its HTML report
/// (targets, 0.5 m border) beside the JSON report of the same options.
fn office_report(name: &str) -> (PathBuf, String, Value) {
    let dir = scratch(name);
    let lit = dir.join("lit.gltf");
    let run = bake_draft(
        &repo_file("samples/office/office.gltf"),
        &lit,
        &[
            "--working-plane",
            "0.8",
            "--probe-grid",
            "2",
            "--probe-height",
            "1.2",
        ],
    );
    assert!(run.ok(), "{}", run.stderr);
    let targets = repo_file("samples/office/targets.json");
    let report = |format: &str, out: &Path| {
        let run = bake([
            OsStr::new("report"),
            lit.as_os_str(),
            "--format".as_ref(),
            format.as_ref(),
            "--targets".as_ref(),
            targets.as_os_str(),
            "--border".as_ref(),
            "0.5".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        assert!(run.ok(), "{}", run.stderr);
        assert!(run.stdout.is_empty(), "-o writes the file, prints nothing");
    };
    let html = dir.join("report.html");
    report("html", &html);
    let json = dir.join("report.json");
    report("json", &json);
    let text = std::fs::read_to_string(&html).unwrap();
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // Same bake, same options: same bytes.
    let again = dir.join("again.html");
    report("html", &again);
    assert_eq!(
        std::fs::read(&again).unwrap(),
        text.as_bytes(),
        "deterministic"
    );
    (html, text, json)
}

/// Whole lx as the document writes them.
fn lux(x: f64) -> String {
    if x.abs() < 0.5 {
        "0".into()
    } else {
        format!("{x:.0}")
    }
}

/// The cells of the table row whose first cell is `first` in table `id`.
fn row<'a>(html: &'a str, id: &str, first: &str) -> Vec<&'a str> {
    let table = html
        .split(&format!("<table id=\"{id}\">"))
        .nth(1)
        .unwrap_or_else(|| panic!("no table {id}"));
    let table = table.split("</table>").next().unwrap();
    let tr = table
        .split("<tr>")
        .find(|tr| tr.contains(&format!(">{first}</td>")))
        .unwrap_or_else(|| panic!("no row {first} in {id}"));
    tr.split("</td>")
        .filter_map(|c| c.rsplit_once('>').map(|(_, text)| text))
        .filter(|t| !t.trim().is_empty())
        .collect()
}

#[test]
fn the_office_report_is_self_contained_and_holds_the_report_s_numbers() {
    let (_, html, json) = office_report("report-html");
    // Self-contained: nothing to fetch, nothing to run.
    for bad in [
        "src=\"http",
        "href=\"http",
        "src=\"//",
        "href=\"//",
        "<script",
        "<link",
        "@import",
        "<iframe",
    ] {
        assert!(!html.contains(bad), "the document holds {bad}");
    }
    for (i, _) in html.match_indices("url(") {
        assert!(
            html[i..].starts_with("url(#"),
            "only local references: {}",
            &html[i..i + 30]
        );
    }
    for (i, _) in html.match_indices(" src=\"") {
        assert!(
            html[i..].starts_with(" src=\"data:image/png;base64,"),
            "{}",
            &html[i..i + 40]
        );
    }
    assert!(!html.contains(" href="), "no links");
    // Sections and tables.
    for id in [
        "room",
        "luminaires",
        "targets",
        "surfaces",
        "working-plane",
        "views",
        "cubic",
        "schedule",
        "targets-table",
        "by-node",
        "by-material",
        "plane",
        "cubic-plane",
        "cubic-probes",
        "flow",
        "plan",
    ] {
        assert!(html.contains(&format!(" id=\"{id}\"")), "no #{id}");
    }
    // One false-colour view per camera node of the office, each a PNG.
    assert_eq!(
        html.matches("src=\"data:image/png;base64,iVBORw0KGgo")
            .count(),
        3
    );
    assert!(html.contains("<svg"), "inline SVG plan");

    // The numbers are the report's.
    for r in json["byNode"].as_array().unwrap() {
        let name = r["name"].as_str().unwrap();
        let cells = row(&html, "by-node", name);
        let f = |k: &str| r[k].as_f64().unwrap();
        assert_eq!(cells[1], format!("{:.2}", f("area")), "{name} {cells:?}");
        assert_eq!(cells[3], lux(f("eAvg")), "{name}");
        assert_eq!(cells[4], lux(f("eMin")), "{name}");
        assert_eq!(cells[8], format!("{:.2}", f("uniformity")), "{name}");
        assert_eq!(cells[9], format!("{:.2}", f("uniformityD")), "{name}");
    }
    // Contacts left out: the ceiling above the six surface-mounted luminaires (6 × 0.3 m²
    // nominal) and the wall behind the 0.25 m² picture are covered, their minima no longer 0.
    let node = |name: &str| {
        json["byNode"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == name)
            .unwrap()
            .clone()
    };
    let ceiling = node("ceiling");
    assert!(ceiling["eMin"].as_f64().unwrap() > 0.0, "{ceiling}");
    assert!(ceiling["coveredArea"].as_f64().unwrap() > 1.5, "{ceiling}");
    let back = node("wall_back");
    assert!(
        (back["coveredArea"].as_f64().unwrap() - 0.25).abs() < 1e-6,
        "{back}"
    );
    assert!(
        (back["area"].as_f64().unwrap() - 15.75).abs() < 1e-6,
        "{back}"
    );
    assert!(back["uniformity"].as_f64().unwrap() > 0.1, "{back}");
    assert_eq!(
        row(&html, "by-node", "ceiling")[11],
        format!("{:.2}", ceiling["coveredArea"].as_f64().unwrap())
    );

    // Working plane inside a 0.5 m border: a 5 × 8 m room at 0.25 m keeps 16 × 28 of 20 × 32.
    let plane = &json["workingPlane"];
    assert_eq!(plane["points"], 16 * 28);
    assert_eq!(plane["pointsTotal"], 20 * 32);
    assert_eq!(plane["extent"], serde_json::json!([0.0, 0.0, 5.0, 8.0]));
    let cells = row(&html, "plane", "0.80");
    assert_eq!(cells[3], "448 of 640");
    assert_eq!(cells[4], lux(plane["eAvg"].as_f64().unwrap()));

    // Luminaire schedule: six fluorescents of 58 W, one 50 W spot (the sample's extras.power_W).
    let l = json["luminaires"].as_array().unwrap();
    assert_eq!(l.len(), 2);
    assert_eq!(
        (l[1]["count"].as_u64(), l[1]["powerTotalW"].as_f64()),
        (Some(6), Some(348.0))
    );
    assert_eq!(l[1]["ratedLampLm"], 5200.0);
    let cells = row(&html, "schedule", "6");
    assert_eq!(cells[2], "Miral 1/58W louvred");
    assert_eq!(cells[9..], ["58.0", "348.0"]);
    // Rated × LOR × MF.
    let emitted = l[1]["emittedLm"].as_f64().unwrap();
    let expect = 5200.0 * l[1]["lightOutputRatio"].as_f64().unwrap();
    assert!(
        (emitted - expect).abs() < 1e-6 * expect,
        "{emitted} {expect}"
    );

    // Targets: pass when achieved ≥ target.
    for t in json["targets"].as_array().unwrap() {
        let pass = t["achieved"].as_f64().unwrap() >= t["target"].as_f64().unwrap();
        assert_eq!(t["pass"], pass);
        let cells = row(&html, "targets-table", t["name"].as_str().unwrap());
        assert_eq!(cells[4], if pass { "pass" } else { "FAIL" });
    }

    // Cubic illuminance: the grid probes at 1.2 m, each row the metrics of its six faces.
    let probes = json["cubic"]["probes"].as_array().unwrap();
    assert!(!probes.is_empty());
    for p in probes {
        let r = p["vectorScalarRatio"].as_f64().unwrap();
        assert!((0.0..=4.0).contains(&r), "{p}");
        assert!((p["position"][1].as_f64().unwrap() - 1.2).abs() < 1e-6);
    }
    let w = &json["cubic"]["workingPlane"];
    assert_eq!(
        w["points"],
        16 * 28,
        "the border applies to the cubic summary too"
    );
}

/// 8-bit RGB(A) pixels of a PNG and its size.
fn png_pixels(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let n = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("{other:?}"),
    };
    let px = buf[..info.buffer_size()]
        .chunks(n)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width, info.height, px)
}

#[test]
fn chromium_shows_the_tables_and_prints_a4() {
    if !have_chromium() {
        return;
    }
    let (html, _, _) = office_report("report-html-chromium");
    let dir = html.parent().unwrap();
    let url = format!("file://{}", html.display());

    // The rendered DOM has the tables and headings.
    let dom = String::from_utf8(chromium(&["--dump-dom".as_ref(), url.as_ref()])).unwrap();
    for needle in [
        "<h1>Lighting report</h1>",
        "<h2>Luminaire schedule</h2>",
        "<h2>Surfaces</h2>",
        "<h2>Working plane</h2>",
        "<h2>False-colour views</h2>",
        "<table id=\"by-node\">",
        "<table id=\"schedule\">",
        "<table id=\"targets-table\">",
        "<table id=\"plane\">",
    ] {
        assert!(dom.contains(needle), "the rendered page lacks {needle}");
    }

    // A screenshot: not blank (many pixels not white, several colours: tables, plan, views).
    let shot = dir.join("shot.png");
    let arg = format!("--screenshot={}", shot.display());
    chromium(&[
        "--window-size=900,2400".as_ref(),
        arg.as_ref(),
        url.as_ref(),
    ]);
    let (w, h, px) = png_pixels(&shot);
    assert_eq!((w, h), (900, 2400));
    let inked = px.iter().filter(|p| p.iter().any(|&c| c < 200)).count();
    assert!(
        inked > px.len() / 50,
        "{inked} of {} pixels inked",
        px.len()
    );
    let colours: std::collections::BTreeSet<[u8; 3]> =
        px.iter().map(|p| p.map(|c| c >> 4)).collect();
    assert!(colours.len() > 20, "{} colours", colours.len());

    // Printed: A4 pages (595 × 842 pt), at least two.
    let pdf = dir.join("report.pdf");
    let arg = format!("--print-to-pdf={}", pdf.display());
    chromium(&[arg.as_ref(), url.as_ref()]);
    let bytes = std::fs::read(&pdf).unwrap();
    assert!(bytes.starts_with(b"%PDF-"));
    let text = String::from_utf8_lossy(&bytes);
    let boxes: Vec<&str> = text
        .match_indices("/MediaBox [")
        .map(|(i, _)| &text[i..i + 40])
        .collect();
    assert!(boxes.len() >= 2, "{boxes:?}");
    for b in &boxes {
        let nums: Vec<f64> = b["/MediaBox [".len()..]
            .split(']')
            .next()
            .unwrap()
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        assert!(
            (nums[2] - 595.0).abs() < 1.0 && (nums[3] - 842.0).abs() < 1.0,
            "{b}"
        );
    }
}

#[test]
fn bad_borders_and_outputs_are_usage_errors() {
    use support::cli::{Mini, assert_error_line};
    let dir = scratch("report-html-errors");
    let input = Mini::new().write_gltf(&dir, "mini.gltf", Some("mini.bin"));
    let lit = dir.join("lit.gltf");
    let run = bake_draft(&input, &lit, &["--working-plane", "0.5"]);
    assert!(run.ok(), "{}", run.stderr);
    let report = |extra: &[&str]| {
        let mut args = vec!["report", lit.to_str().unwrap()];
        args.extend(extra);
        bake(args)
    };
    // A border leaving no point of the 2 × 2 m floor's plane, and a negative one: exit 2.
    let run = report(&["--border", "1.5"]);
    assert_eq!(run.code, Some(2), "{run:?}");
    assert_error_line(&run, &["--border 1.5 m leaves no working-plane point"]);
    let run = report(&["--border=-1"]);
    assert_eq!(run.code, Some(2), "{run:?}");
    assert_error_line(&run, &["--border -1"]);
    // Never over an input.
    let run = report(&["--format", "html", "-o", lit.to_str().unwrap()]);
    assert!(!run.ok());
    assert_error_line(&run, &[]);
    // The mini scene has no camera: a document without views.
    let out = dir.join("r.html");
    let run = report(&[
        "--format",
        "html",
        "--border",
        "0.25",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(run.ok(), "{}", run.stderr);
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(!html.contains("id=\"views\"") && html.contains("<table id=\"plane\">"));
}
