//! Covered parts left out of the report: a box resting on a floor under a point light. The bake
//! writes the floor under the box (no light) as the primitive's last triangles and marks them
//! (`extras.luxbake.coveredFrom`); the report leaves them out of area, averages and extremes and
//! gives their area as `covered_area`. Exact expectations: the floor's row area is the floor less
//! the box's footprint, its covered area the footprint, its minimum above 0; a primitive without
//! the marker (an older output) has nothing left out.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::SceneBuilder;
use luxbake::progress::Silent;
use luxbake::report::{self, By, Filter, Options};
use luxbake::scene::Scene;
use luxbake::settings::{LightmapSettings, Quality, Settings};

const FOOTPRINT: f64 = 0.4 * 0.6;

/// A 4 × 4 m floor (ρ 0.5), a 0.4 × 0.3 × 0.6 m box standing on it off centre, a point light
/// 2 m above the floor's centre.
fn box_on_floor() -> Scene {
    let mut b = SceneBuilder::new();
    let grey = b.material("grey", 0.5);
    b.floor("floor", 2.0, 0.0, grey);
    b.axis_box(
        "box",
        DVec3::new(0.5, 0.0, -0.3),
        DVec3::new(0.9, 0.3, 0.3),
        false,
        grey,
    );
    b.point_light("lamp", DVec3::new(0.0, 2.0, 0.0), 2000.0);
    b.build()
}

fn settings(lightmaps: bool) -> Settings {
    Settings {
        quality: Quality::Draft,
        lightmaps: lightmaps.then(|| LightmapSettings::with_texel(0.05)),
        ..Settings::default()
    }
}

fn floor_row(input: &luxbake::readback::BakedOutput) -> report::Row {
    let rows = report::rows::by_node(input, &Filter::All);
    rows.into_iter().find(|r| r.name == "floor").unwrap()
}

#[test]
fn the_floor_under_a_box_is_left_out() {
    let scene = box_on_floor();
    for lightmaps in [false, true] {
        let r = bake(&scene, &settings(lightmaps), &Silent).unwrap();
        // The bake marks the floor's covered part, after its lit triangles.
        let floor = r.surfaces.iter().find(|s| s.surface == 0).unwrap();
        let k = floor
            .covered_from
            .expect("the floor under the box is covered") as usize;
        assert!(k > 0 && k < floor.triangles.len());
        let input = luxbake::readback::as_written(&scene, &r).unwrap();
        let row = floor_row(&input);
        // Positions are f32 in the file, texel footprints f32 sums.
        let tol = if lightmaps { 1e-4 } else { 1e-6 };
        assert!(
            (row.area - (16.0 - FOOTPRINT)).abs() < tol,
            "lightmaps {lightmaps}: {row:?}"
        );
        assert!((row.covered_area - FOOTPRINT).abs() < 1e-6, "{row:?}");
        assert!(row.e_min > 0.0, "lightmaps {lightmaps}: {row:?}");
        assert!(row.uniformity > 0.0 && row.uniformity_d > 0.0);
        assert!((row.uniformity_d - row.e_min / row.e_max).abs() < 1e-12);
        // The box's sides stand on the floor, but nothing covers them.
        let json: serde_json::Value = serde_json::from_str(
            &report::build(
                &input,
                &Options {
                    by: By::Node,
                    ..Options::default()
                },
            )
            .unwrap()
            .render(report::Format::Json),
        )
        .unwrap();
        assert_eq!(json["byNode"][0]["name"], "floor");
        assert!((json["byNode"][0]["coveredArea"].as_f64().unwrap() - FOOTPRINT).abs() < 1e-6);

        // An output without the marker: nothing left out, the covered part's 0 lx the minimum.
        let mut old = input.clone();
        for p in &mut old.primitives {
            p.covered_from = None;
        }
        let row = floor_row(&old);
        assert!((row.area - 16.0).abs() < tol, "{row:?}");
        assert_eq!(row.e_min, 0.0);
        assert_eq!(row.covered_area, 0.0);
    }
}

#[test]
fn the_marker_is_written_and_read_back() {
    let scene = box_on_floor();
    let r = bake(&scene, &settings(false), &Silent).unwrap();
    let floor = r.surfaces.iter().find(|s| s.surface == 0).unwrap();
    let dir = std::env::temp_dir().join(format!("luxbake-covered-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("lit.gltf");
    luxbake::export::write(&out, &scene, &r, &luxbake::export::ExportOptions::default()).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let floor_mesh = json["nodes"][0]["mesh"].as_u64().unwrap() as usize;
    assert_eq!(
        json["meshes"][floor_mesh]["primitives"][0]["extras"]["luxbake"]["coveredFrom"],
        floor.covered_from.unwrap()
    );
    let input = luxbake::readback::read(&out).unwrap();
    assert_eq!(input.primitives[0].covered_from, floor.covered_from);
    std::fs::remove_dir_all(&dir).unwrap();
}
