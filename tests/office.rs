//! The office sample with its real luminaire photometry, beside the seed paper: the lighting
//! report (per material, per node, the working plane at 0.8 m) and the seed's design values of
//! Table 1 (`samples/office/targets.json`). Run with `--nocapture` to see the report in Markdown
//! (it is reproduced in samples/office/README.md; `bake samples/office/office.gltf -o lit.gltf
//! --working-plane 0.8 --report markdown --targets samples/office/targets.json` prints the same).

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::progress::Silent;
use luxbake::report::{self, By, Filter, Options, Targets};
use luxbake::settings::{ProbeGrid, Settings};

#[test]
fn office_report_beside_the_seed() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = luxbake::import::load(
        &root.join("samples/office/office.gltf"),
        &Default::default(),
    )
    .unwrap();
    let settings = Settings {
        working_plane: Some(ProbeGrid {
            spacing: 0.5,
            height: 0.8,
        }),
        ..Settings::default()
    };
    let r = bake(&scene, &settings, &Silent).unwrap();
    let input = luxbake::readback::as_written(&scene, &r).unwrap();
    let options = Options {
        by: By::Both,
        targets: Some(Targets::read(&root.join("samples/office/targets.json")).unwrap()),
        border: 0.0,
    };
    let rep = report::build(&input, &options).unwrap();
    eprintln!("{}", rep.render(report::Format::Markdown));
    eprintln!(
        "sources: {}",
        serde_json::to_string_pretty(&r.summary.sources).unwrap()
    );
    let all = rep.by_node.as_ref().unwrap();
    let pick = |name: &str| {
        all.iter()
            .find(|r| r.name == name)
            .cloned()
            .unwrap_or_else(|| panic!("{name}"))
    };
    // Sanity against physics, not against earlier bakes: the ceiling gets no direct light from
    // these downlights, the floor's luminance is ρ·E/π, and every area matches the layout.
    let ceiling = pick("ceiling");
    assert!(ceiling.e_direct_avg < 0.01 * ceiling.e_avg, "{ceiling:?}");
    let floor = pick("floor");
    assert!((floor.l_avg - 0.3 * floor.e_avg / std::f64::consts::PI).abs() < 1e-3 * floor.l_avg);
    assert!((floor.area - 40.0).abs() < 1e-5 && (pick("picture").area - 0.25).abs() < 1e-6);
    let up = report::rows::by_node(&input, &Filter::Facing(DVec3::Y));
    let desk = up.iter().find(|r| r.name == "desk_dark/top").unwrap();
    assert!((desk.area - 1.5).abs() < 1e-6);
    // The working plane lies between the floor and the desks' upper faces in light.
    let plane = rep.working_plane.as_ref().unwrap();
    assert!(
        plane.e_avg > floor.e_avg && plane.e_avg < 1.2 * desk.e_avg,
        "{plane:?}"
    );
}
