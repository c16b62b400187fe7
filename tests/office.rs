//! The office sample with its real luminaire photometry, beside the seed paper: per-surface
//! averages (the paper's Table 2) and the desks and picture against the design values of Table 1.
//! Run with `--nocapture` to see the table (it is reproduced in samples/office/README.md).

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::progress::Silent;
use luxbake::report::{self, Filter};
use luxbake::settings::Settings;

#[test]
fn office_per_surface_report() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/office/office.gltf");
    let scene = luxbake::import::load(&path, &Default::default()).unwrap();
    let r = bake(&scene, &Settings::default(), &Silent).unwrap();
    let all = report::by_node(&scene, &r, &Filter::All);
    let up = report::by_node(&scene, &r, &Filter::Facing(DVec3::Y));
    let pick = |rows: &[report::Row], name: &str| {
        rows.iter()
            .find(|r| r.name == name)
            .cloned()
            .unwrap_or_else(|| panic!("{name}"))
    };
    let mut table = Vec::new();
    for name in [
        "floor",
        "ceiling",
        "wall_front",
        "wall_left",
        "wall_back",
        "wall_right",
        "picture",
    ] {
        table.push(pick(&all, name));
    }
    for name in ["desk_dark/top", "desk_light/top"] {
        let mut row = pick(&up, name);
        row.name = format!("{name} (upper face)");
        table.push(row);
    }
    eprintln!("{}", report::markdown(&table));
    eprintln!(
        "sources: {}",
        serde_json::to_string_pretty(&r.summary["sources"]).unwrap()
    );
    // Sanity against physics, not against earlier bakes: the ceiling gets no direct light from
    // these downlights, the floor's luminance is ρ·E/π, and every area matches the layout.
    let ceiling = pick(&all, "ceiling");
    assert!(ceiling.e_direct_avg < 0.01 * ceiling.e_avg, "{ceiling:?}");
    let floor = pick(&all, "floor");
    assert!((floor.l_avg - 0.3 * floor.e_avg / std::f64::consts::PI).abs() < 1e-3 * floor.l_avg);
    assert!((floor.area - 40.0).abs() < 1e-9 && (pick(&all, "picture").area - 0.25).abs() < 1e-9);
    assert!((pick(&up, "desk_dark/top").area - 1.5).abs() < 1e-9);
}
