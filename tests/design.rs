//! `bake design`: the flux table reproduces the seed paper's Table 1 as printed (from
//! samples/office/table1.csv), by the library and through the command line in every format;
//! bad tables are refused with the file and line; a surface designed below the indirect
//! illuminance keeps its negative direct part and is warned about.

use luxbake::design::{self, FluxTable, Format};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn table1() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/office/table1.csv")
}

/// The seed's Table 1 as printed: surface, area, reflectance, illuminance, reflected flux,
/// direct illuminance, direct flux.
const PRINTED: [(&str, &str, &str, &str, &str, &str, &str); 9] = [
    ("Roof", "40", "0.7", "100", "2800", "7", "272"),
    ("Back Wall", "15.75", "0.6", "200", "1890", "107", "1682"),
    ("Front Wall", "16", "0.5", "200", "1600", "107", "1709"),
    ("Left Wall", "25.6", "0.5", "200", "2560", "107", "2734"),
    ("Right Wall", "25.6", "0.5", "200", "2560", "107", "2734"),
    ("Floor", "37", "0.3", "280", "3108", "187", "6911"),
    ("Picture", "0.25", "0.5", "750", "93.75", "657", "164"),
    ("Dark Desk", "1.5", "0.2", "500", "150", "407", "610"),
    ("Light Desk", "1.5", "0.6", "500", "450", "407", "610"),
];

fn bake(args: &[&std::ffi::OsStr]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bake"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn design_run(file: &Path, format: &str) -> (Option<i32>, String, String) {
    bake(&[
        "design".as_ref(),
        file.as_os_str(),
        "--format".as_ref(),
        format.as_ref(),
    ])
}

fn seed_table() -> FluxTable {
    let text = std::fs::read_to_string(table1()).unwrap();
    FluxTable::compute(&design::parse(&table1(), &text).unwrap()).unwrap()
}

#[test]
fn the_seeds_table_1_in_numbers() {
    let t = seed_table();
    let area = 40.0 + 15.75 + 16.0 + 25.6 + 25.6 + 37.0 + 0.25 + 1.5 + 1.5;
    let reflected = 2800.0 + 1890.0 + 1600.0 + 2560.0 + 2560.0 + 3108.0 + 93.75 + 150.0 + 450.0;
    assert!((t.totals.area - 163.2).abs() < 1e-9, "{}", t.totals.area);
    assert!((t.totals.reflected_flux - 15211.75).abs() < 1e-9);
    assert!((t.totals.area - area).abs() < 1e-9);
    assert!((t.totals.reflected_flux - reflected).abs() < 1e-9);
    let e_r = 15211.75 / 163.2; // 93.209…
    assert!((t.totals.indirect_illuminance - e_r).abs() < 1e-9);
    assert_eq!(t.totals.indirect_illuminance.round(), 93.0);
    assert_eq!(t.totals.reflected_flux.round(), 15212.0);
    assert_eq!(t.rows.len(), PRINTED.len());
    for (row, p) in t.rows.iter().zip(PRINTED) {
        assert_eq!(row.name, p.0);
        let num = |s: &str| s.parse::<f64>().unwrap();
        assert_eq!(row.area, num(p.1));
        assert_eq!(row.reflectance, num(p.2));
        assert_eq!(row.illuminance, num(p.3));
        assert!((row.reflected_flux - num(p.4)).abs() < 1e-9, "{}", row.name);
        assert!((row.direct_illuminance - (row.illuminance - e_r)).abs() < 1e-9);
        assert!((row.direct_flux - (row.illuminance - e_r) * row.area).abs() < 1e-9);
        // Printed at whole lx and lm, from the unrounded E_r (E − 93 would give floor 6919 lm).
        assert_eq!(row.direct_illuminance.round(), num(p.5), "{}", row.name);
        assert_eq!(row.direct_flux.round(), num(p.6), "{}", row.name);
    }
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    let direct: f64 = t.rows.iter().map(|r| r.direct_flux).sum();
    assert!((t.totals.direct_flux - direct).abs() < 1e-9);
}

#[test]
fn the_command_prints_table_1_as_the_seed_does() {
    let (code, out, err) = design_run(&table1(), "table");
    assert_eq!(code, Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
    for p in PRINTED {
        let cells: Vec<&str> = out
            .lines()
            .find(|l| l.starts_with(&format!("{}  ", p.0)))
            .unwrap_or_else(|| panic!("no row {} in:\n{out}", p.0))
            .split("  ")
            .map(str::trim)
            .filter(|c| !c.is_empty())
            .collect();
        assert_eq!(cells, [p.0, p.1, p.2, p.3, p.4, p.5, p.6], "{out}");
    }
    let total = |name: &str| -> String {
        let line = out.lines().find(|l| l.starts_with(name)).unwrap();
        line.split_whitespace().last().unwrap().to_string()
    };
    assert_eq!(total("area m²"), "163.2");
    assert_eq!(total("reflected flux lm"), "15212");
    assert_eq!(total("indirect illuminance"), "93");
    assert!(!out.contains("warning"), "{out}");
    // The default format is the table.
    let (_, default, _) = bake(&["design".as_ref(), table1().as_os_str()]);
    assert_eq!(default, out);
}

#[test]
fn markdown_csv_and_json() {
    let (code, md, err) = design_run(&table1(), "markdown");
    assert_eq!(code, Some(0), "{err}");
    assert!(
        md.contains("| Floor | 37 | 0.3 | 280 | 3108 | 187 | 6911 |"),
        "{md}"
    );
    assert!(
        md.contains("| Picture | 0.25 | 0.5 | 750 | 93.75 | 657 | 164 |"),
        "{md}"
    );
    assert!(md.contains("| area m² | 163.2 |"), "{md}");

    let (code, json, err) = design_run(&table1(), "json");
    assert_eq!(code, Some(0), "{err}");
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["rows"].as_array().unwrap().len(), 9);
    assert_eq!(v["rows"][6]["name"], "Picture");
    assert_eq!(v["rows"][6]["reflectedFlux"].as_f64(), Some(93.75));
    assert_eq!(v["totals"]["area"].as_f64().unwrap().round(), 163.0);
    let e_r = v["totals"]["indirectIlluminance"].as_f64().unwrap();
    assert!((e_r - 15211.75 / 163.2).abs() < 1e-9, "{e_r}");
    assert_eq!(v["rows"][5]["directFlux"].as_f64().unwrap().round(), 6911.0);
    assert_eq!(v["warnings"].as_array().unwrap().len(), 0);

    let (code, csv, err) = design_run(&table1(), "csv");
    assert_eq!(code, Some(0), "{err}");
    let blocks: Vec<&str> = csv.split("\n\n").collect();
    assert_eq!(blocks.len(), 2, "{csv}");
    let rows: Vec<Vec<&str>> = blocks[0].lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        [
            "section",
            "name",
            "area",
            "reflectance",
            "illuminance",
            "reflectedFlux",
            "directIlluminance",
            "directFlux"
        ]
    );
    assert_eq!(rows.len(), 10);
    let floor = &rows[6];
    assert_eq!(floor[..2], ["surfaces", "Floor"]);
    let f: Vec<f64> = floor[2..].iter().map(|c| c.parse().unwrap()).collect();
    assert_eq!(f[..4], [37.0, 0.3, 280.0, 3108.0]);
    assert!((f[5] - (280.0 - 15211.75 / 163.2) * 37.0).abs() < 1e-9);
    let totals: Vec<&str> = blocks[1].lines().nth(1).unwrap().split(',').collect();
    assert_eq!(totals[0], "totals");
    assert_eq!(totals[1].parse::<f64>().unwrap(), 163.2);
    assert_eq!(totals[2].parse::<f64>().unwrap(), 15211.75);
}

#[test]
fn a_surface_below_the_indirect_illuminance_keeps_a_negative_direct_part() {
    // A = 10 + 10 m², A·ρ·E = 10·0.8·200 + 10·0.5·20 = 1700 lm, E_r = 85 lx.
    let text = "name,area_m2,reflectance,illuminance_lx\nwall,10,0.8,200\ndark,10,0.5,20\n";
    let file = Path::new("two.csv");
    let t = FluxTable::compute(&design::parse(file, text).unwrap()).unwrap();
    assert!((t.totals.indirect_illuminance - 85.0).abs() < 1e-12);
    assert!((t.rows[0].direct_flux - 1150.0).abs() < 1e-9);
    assert!((t.rows[1].direct_illuminance + 65.0).abs() < 1e-12);
    assert!((t.rows[1].direct_flux + 650.0).abs() < 1e-9);
    assert!((t.totals.direct_flux - 500.0).abs() < 1e-9);
    assert_eq!(t.warnings.len(), 1);
    assert!(t.warnings[0].starts_with("dark:"), "{:?}", t.warnings);
    let text_out = t.render(Format::Table);
    assert!(
        text_out.contains("warning: dark: designed at 20 lx, below"),
        "{text_out}"
    );
    assert!(
        text_out
            .lines()
            .any(|l| l.starts_with("dark") && l.ends_with("-650"))
    );
    let v: Value = serde_json::from_str(&t.render(Format::Json)).unwrap();
    assert_eq!(v["warnings"].as_array().unwrap().len(), 1);

    // Through the command: JSON on stdout stays clean, the warning goes to stderr.
    let dir = std::env::temp_dir().join(format!("luxbake-design-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("two.csv");
    std::fs::write(&path, text).unwrap();
    let (code, out, err) = design_run(&path, "json");
    assert_eq!(code, Some(0), "{err}");
    serde_json::from_str::<Value>(&out).unwrap();
    assert!(err.starts_with("warning: dark:"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn columns_in_any_order_quotes_comments_and_blank_lines() {
    let text = "\u{feff}# a comment\n\nIlluminance_lx, name ,reflectance,area_m2\n\
                # another\n300,\"Wall, north\",0.5,12\n  \n100,\"say \"\"hi\"\"\",0,3\n";
    let rows = design::parse(Path::new("x.csv"), text).unwrap();
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0].name, "Wall, north");
    assert_eq!(
        (rows[0].area, rows[0].reflectance, rows[0].illuminance),
        (Some(12.0), 0.5, 300.0)
    );
    assert_eq!(rows[0].line, 5);
    assert_eq!(rows[1].name, "say \"hi\"");
    assert_eq!(rows[1].line, 7);
    // A name with a comma is quoted again in CSV output.
    let csv = FluxTable::compute(&rows).unwrap().render(Format::Csv);
    assert!(csv.contains("surfaces,\"Wall, north\",12,"), "{csv}");
}

#[test]
fn bad_tables_are_refused_naming_the_file_and_line() {
    let header = "name,area_m2,reflectance,illuminance_lx\n";
    let cases: [(&str, String, &str); 12] = [
        (
            "bad number",
            format!("{header}a,1,0.5,200\nb,x1,0.5,200\n"),
            "line 3: area_m2",
        ),
        (
            "negative area",
            format!("#c\n{header}a,-2,0.5,200\n"),
            "line 3: area_m2 must be",
        ),
        (
            "zero area",
            format!("{header}a,0,0.5,200\n"),
            "line 2: area_m2",
        ),
        (
            "reflectance 1",
            format!("{header}a,1,1,200\n"),
            "line 2: reflectance must be",
        ),
        (
            "reflectance < 0",
            format!("{header}a,1,-0.1,200\n"),
            "line 2: reflectance",
        ),
        (
            "negative E",
            format!("{header}a,1,0.5,-5\n"),
            "line 2: illuminance_lx",
        ),
        (
            "not finite",
            format!("{header}a,1,0.5,inf\n"),
            "line 2: illuminance_lx",
        ),
        (
            "missing column",
            format!("{header}a,1,0.5\n"),
            "line 2: missing column 'illuminance_lx'",
        ),
        (
            "extra field",
            format!("{header}a,1,0.5,2,9\n"),
            "line 2: 5 fields",
        ),
        (
            "duplicate",
            format!("{header}a,1,0.5,2\n\na,1,0.5,2\n"),
            "line 4: surface 'a' is already on line 2",
        ),
        ("no rows", format!("# only\n{header}\n"), "no surface rows"),
        (
            "no header",
            "Roof,40,0.7,100\n".to_string(),
            "line 1: expected the header row",
        ),
    ];
    for (what, text, expected) in &cases {
        let e = design::parse(Path::new("t.csv"), text)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.csv: "), "{what}: {e}");
        assert!(e.contains(expected), "{what}: {e}");
    }
    for (text, expected) in [
        (
            "name,area_m2,reflectance\n",
            "missing column 'illuminance_lx' in the header",
        ),
        (
            "name,area,reflectance,illuminance_lx\n",
            "unknown column 'area'",
        ),
        (
            "name,name,area_m2,reflectance,illuminance_lx\n",
            "column 'name' twice",
        ),
        ("", "no header row"),
        (
            "name,area_m2,reflectance,illuminance_lx\n\"a,1,1,1\n",
            "line 2: a quoted field",
        ),
        (
            "name,area_m2,reflectance,illuminance_lx\n\"\",1,0.5,1\n",
            "line 2: the surface name is empty",
        ),
    ] {
        let e = design::parse(Path::new("t.csv"), text)
            .unwrap_err()
            .to_string();
        assert!(e.contains(expected), "{text:?}: {e}");
    }

    // Through the command: exit 1, one line on stderr, nothing on stdout; a missing file too.
    let dir = std::env::temp_dir().join(format!("luxbake-design-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.csv");
    std::fs::write(&path, &cases[1].1).unwrap();
    let (code, out, err) = design_run(&path, "table");
    assert_eq!(code, Some(1), "{err}");
    assert!(out.is_empty(), "{out}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.csv: line 3: area_m2"), "{err}");
    let (code, _, err) = design_run(&dir.join("missing.csv"), "table");
    assert_eq!(code, Some(1));
    assert!(
        err.contains("missing.csv") && err.contains("cannot read"),
        "{err}"
    );
    // A bad option value is a usage error.
    let (code, _, _) = design_run(&table1(), "html");
    assert_eq!(code, Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn areas_come_from_a_bake_with_scene() {
    let dir = std::env::temp_dir().join(format!("luxbake-design-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let lit = dir.join("office-lit.gltf");
    let (code, _, err) = bake(&[
        "--quality".as_ref(),
        "draft".as_ref(),
        table1().with_file_name("office.gltf").as_os_str(),
        "-o".as_ref(),
        lit.as_os_str(),
        "-q".as_ref(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    // Areas left empty are the bake's; a given one is replaced (and noted when it differs).
    let table = dir.join("t.csv");
    std::fs::write(
        &table,
        "name,area_m2,reflectance,illuminance_lx,surface\n\
         Left Wall,,0.5,200,wall_left\n\
         Front Wall,99,0.5,200,wall_front\n\
         Floor,,0.3,280,floor\n\
         Dark Desk,,0.2,500,desk_dark/top[+y]\n",
    )
    .unwrap();
    let (code, out, err) = bake(&[
        "design".as_ref(),
        table.as_os_str(),
        "--scene".as_ref(),
        lit.as_os_str(),
        "--format".as_ref(),
        "json".as_ref(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("Front Wall: area 99 m² in the table, 16.000 m²"),
        "{err}"
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    let area = |k: usize| v["rows"][k]["area"].as_f64().unwrap();
    // The office (samples/office/README.md): 8 m deep, 5 m wide, 3.2 m high, +Y up.
    assert!((area(0) - 25.6).abs() < 1e-4, "{}", area(0));
    assert!((area(1) - 16.0).abs() < 1e-4, "{}", area(1));
    // The desk top: 1.5 m² as the seed has it.
    assert!((area(3) - 1.5).abs() < 1e-4, "{}", area(3));
    // The floor as the report measures it (its own by-node area).
    let (_, report, _) = bake(&[
        "report".as_ref(),
        lit.as_os_str(),
        "--by".as_ref(),
        "node".as_ref(),
        "--format".as_ref(),
        "json".as_ref(),
    ]);
    let r: Value = serde_json::from_str(&report).unwrap();
    let floor = r["byNode"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"] == "floor")
        .unwrap()["area"]
        .as_f64()
        .unwrap();
    assert!((area(2) - floor).abs() < 1e-9, "{} vs {floor}", area(2));
    assert!(floor <= 40.0 + 1e-6);
    // No area and no --scene: an error naming the line.
    let (code, _, err) = bake(&["design".as_ref(), table.as_os_str()]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("t.csv: line 2: 'Left Wall' has no area_m2"),
        "{err}"
    );
    // A key the bake lacks: an error naming the line and the key.
    std::fs::write(
        &table,
        "name,area_m2,reflectance,illuminance_lx,surface\nX,,0.5,200,no_such_node\n",
    )
    .unwrap();
    let (code, _, err) = bake(&[
        "design".as_ref(),
        table.as_os_str(),
        "--scene".as_ref(),
        lit.as_os_str(),
    ]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("line 2") && err.contains("no_such_node"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
