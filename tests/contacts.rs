//! Things touching things: closed rooms with a panel just below the ceiling, cubes on the floor,
//! a cabinet against a wall, a picture on a wall. Oracles: Sumpner's balance from the output's
//! vertex values (in a closed room of one reflectance ρ, Σ(1 − ρ)·E·A over every baked triangle
//! equals the emitted flux Φ, whatever touches what), the energy report's balance, and the wall
//! beside a picture against the same wall bare. Axes: +Y up.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::fixtures::contacts::{self, ContactRoom};
use luxbake::progress::Silent;
use luxbake::result::{BakeResult, BakedSurface};
use luxbake::settings::Settings;

fn run(room: &ContactRoom) -> BakeResult {
    bake(&room.scene, &Settings::default(), &Silent).expect("bake")
}

/// Σ(1 − ρ)·E·A over every baked triangle (E linear between its vertices), over Φ, minus one.
fn sumpner_error(r: &BakeResult, rho: f64, flux: f64) -> f64 {
    let mut absorbed = 0.0;
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
            let e: f64 = t
                .iter()
                .map(|&v| s.illuminance[v as usize] as f64)
                .sum::<f64>()
                / 3.0;
            absorbed += (1.0 - rho) * e * a;
        }
    }
    absorbed / flux - 1.0
}

/// Illuminance on `s` at `point` (on its plane), linear within the triangle holding it: total
/// and direct.
fn value_at(s: &BakedSurface, point: DVec3) -> Option<(f64, f64)> {
    for t in &s.triangles {
        let p = t.map(|v| s.positions[v as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let area = n.length();
        if area == 0.0 || (point - p[0]).dot(n / area).abs() > 1e-6 {
            continue;
        }
        let w = [
            (p[2] - p[1]).cross(point - p[1]).dot(n) / (area * area),
            (p[0] - p[2]).cross(point - p[2]).dot(n) / (area * area),
            (p[1] - p[0]).cross(point - p[0]).dot(n) / (area * area),
        ];
        if w.iter().all(|x| *x >= -1e-9) {
            let at = |e: &[f32]| (0..3).map(|k| w[k] * e[t[k] as usize] as f64).sum();
            return Some((at(&s.illuminance), at(&s.illuminance_direct)));
        }
    }
    None
}

/// The illuminance of the room's wall z = 0 (node `room_4`, facing +Z) at `point`: total and
/// direct.
fn wall_at(room: &ContactRoom, r: &BakeResult, point: DVec3) -> (f64, f64) {
    let node = room
        .scene
        .nodes
        .iter()
        .position(|n| n.name.as_deref() == Some("room_4"));
    let surface = room.scene.nodes[node.expect("room_4")].surfaces[0];
    r.surfaces
        .iter()
        .filter(|s| s.surface == surface)
        .find_map(|s| value_at(s, point))
        .expect("a point on the wall")
}

/// Bake `room` and return what fails of: balance error ≤ 10⁻⁴, Sumpner within 0.5 %; `worst`
/// keeps the largest of each.
fn check_closed(name: &str, room: &ContactRoom, rho: f64, worst: &mut [f64; 2]) -> Vec<String> {
    let r = run(room);
    let balance = r.summary.energy.balance_error_relative;
    let sumpner = sumpner_error(&r, rho, room.flux);
    eprintln!("contacts/{name}: balance {balance:.2e}, Sumpner {sumpner:+.2e}");
    worst[0] = worst[0].max(balance);
    worst[1] = worst[1].max(sumpner.abs());
    let mut failed = Vec::new();
    if balance > 1e-4 {
        failed.push(format!("{name}: balance error {balance:.2e}"));
    }
    if sumpner.abs() > 0.005 {
        failed.push(format!("{name}: Σ(1 − ρ)·E·A off Φ by {sumpner:+.2e}"));
    }
    failed
}

#[test]
fn panel_below_a_ceiling_closes_energy_at_any_gap() {
    let (mut failed, mut worst) = (Vec::new(), [0.0; 2]);
    for (rho, gap) in [
        (0.5, 0.001),
        (0.9, 0.0),
        (0.9, 0.001),
        (0.9, 0.01),
        (0.9, 0.03),
        (0.9, 0.1),
    ] {
        let name = format!("panel/rho{rho}/gap{gap}");
        let room = contacts::panel_below_ceiling(rho, gap, false);
        failed.extend(check_closed(&name, &room, rho, &mut worst));
    }
    eprintln!("oracle: contacts/panel-balance measured {:e}", worst[0]);
    eprintln!("oracle: contacts/panel-sumpner measured {:e}", worst[1]);
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn a_flat_panel_below_a_ceiling_loses_nothing_unaccounted() {
    // A single-sided quad's back absorbs what reaches it (no Sumpner identity over the
    // vertices), but the energy report must still balance.
    let (mut failed, mut worst) = (Vec::new(), 0.0f64);
    for (rho, gap) in [
        (0.5, 0.001),
        (0.9, 0.001),
        (0.9, 0.01),
        (0.9, 0.03),
        (0.9, 0.1),
    ] {
        let r = run(&contacts::panel_below_ceiling(rho, gap, true));
        let balance = r.summary.energy.balance_error_relative;
        eprintln!("contacts/flat-panel/rho{rho}/gap{gap}: balance {balance:.2e}");
        worst = worst.max(balance);
        if balance > 1e-4 {
            failed.push(format!(
                "flat panel, ρ {rho}, gap {gap}: balance error {balance:.2e}"
            ));
        }
    }
    eprintln!("oracle: contacts/flat-panel-balance measured {worst:e}");
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn cubes_on_a_floor_close_energy() {
    let (mut failed, mut worst) = (Vec::new(), [0.0; 2]);
    for (rho, lift) in [(0.5, 0.0), (0.9, 0.0), (0.9, 0.001)] {
        let name = format!("cubes/rho{rho}/lift{lift}");
        let room = contacts::cubes_on_floor(rho, lift);
        failed.extend(check_closed(&name, &room, rho, &mut worst));
    }
    eprintln!("oracle: contacts/cubes-balance measured {:e}", worst[0]);
    eprintln!("oracle: contacts/cubes-sumpner measured {:e}", worst[1]);
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn cabinet_against_a_wall_closes_energy() {
    let mut worst = [0.0; 2];
    let room = contacts::cabinet_against_wall(0.9);
    let failed = check_closed("cabinet/rho0.9", &room, 0.9, &mut worst);
    eprintln!("oracle: contacts/cabinet-balance measured {:e}", worst[0]);
    eprintln!("oracle: contacts/cabinet-sumpner measured {:e}", worst[1]);
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn the_wall_beside_a_picture_reads_as_the_bare_wall() {
    // 3 cm outside each side of the outline (x 1.6..2.4, y 1.2..1.8 on the wall z = 0), and
    // further out; a light in front of the picture and one far off to the side. A framed
    // picture (a closed box 1 cm deep) shows the wall its lit sides: the wall reads as bare.
    // A single-sided quad 1 cm proud shows it its black back: at x from its edge it hides
    // ½(1 − x/√(x² + g²)) of the wall's hemisphere (a half-plane at height g), so the wall
    // reads the bare wall less that share of its inter-reflected light; its direct light is the
    // bare wall's (neither light's shadow of the edge reaches 3 cm).
    let points = [
        DVec3::new(1.57, 1.5, 0.0),
        DVec3::new(2.43, 1.5, 0.0),
        DVec3::new(2.0, 1.17, 0.0),
        DVec3::new(2.0, 1.83, 0.0),
        DVec3::new(1.3, 1.5, 0.0),
    ];
    let (mut failed, mut worst) = (Vec::new(), [0.0f64; 2]);
    for light in [DVec3::new(2.0, 1.5, 1.5), DVec3::new(3.5, 2.6, 4.0)] {
        let bare = contacts::bare_wall(0.5, light);
        let rb = run(&bare);
        for boxed in [false, true] {
            let room = contacts::picture_on_wall(0.5, 0.5, 0.01, boxed, light);
            let r = run(&room);
            for at in points {
                let (with, _) = wall_at(&room, &r, at);
                let (bare_total, bare_direct) = wall_at(&bare, &rb, at);
                let x = [at.x - 2.4, 1.6 - at.x, at.y - 1.8, 1.2 - at.y]
                    .into_iter()
                    .fold(f64::NEG_INFINITY, f64::max);
                let hidden = if boxed {
                    0.0
                } else {
                    0.5 * (1.0 - x / x.hypot(0.01))
                };
                let without = bare_total - hidden * (bare_total - bare_direct);
                let rel = with / without - 1.0;
                let name = format!("light {light}, boxed {boxed}, at {at}");
                eprintln!("contacts/picture {name}: {with:.2} vs {without:.2}: {rel:+.2e}");
                if at.x != 1.3 {
                    worst[boxed as usize] = worst[boxed as usize].max(rel.abs());
                }
                if rel.abs() > 0.03 {
                    failed.push(format!("{name}: {with} vs bare wall {without}"));
                }
            }
        }
    }
    eprintln!("oracle: contacts/picture-quad measured {:e}", worst[0]);
    eprintln!("oracle: contacts/picture-framed measured {:e}", worst[1]);
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn contacts_bake_alike_on_one_and_two_threads() {
    // Covers, seams and cuts are found in parallel: the output must not depend on it. The
    // framed picture (covers) and cubes on a floor (covers and seams along their sides).
    for room in [
        contacts::picture_on_wall(0.5, 0.3, 0.01, true, DVec3::new(2.0, 1.5, 1.5)),
        contacts::cubes_on_floor(0.7, 0.0),
    ] {
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        let one = pool(1).install(|| run(&room));
        let two = pool(2).install(|| run(&room));
        assert!(
            one.summary.contacts.covers > 0,
            "{:?}",
            one.summary.contacts
        );
        assert_eq!(one.summary, two.summary);
        assert_eq!(one.surfaces.len(), two.surfaces.len());
        for (a, b) in one.surfaces.iter().zip(&two.surfaces) {
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(a.positions, b.positions);
            assert_eq!(a.triangles, b.triangles);
            assert_eq!(bits(&a.illuminance), bits(&b.illuminance));
        }
    }
}

#[test]
fn a_shelf_against_a_wall_covers_only_its_footprint() {
    // The plank (1.4 m × 3 cm, open at the back) meets the wall along two 1.4 m lines; the wall
    // is covered between them over the shelf's length, not across the wall triangle.
    use luxbake::contacts::{self as found, cut};
    use luxbake::visibility::{Occluder, OccluderOptions};
    let room = contacts::shelf_on_wall(0.5);
    let occ = Occluder::build(&room.scene, OccluderOptions::default());
    let c = found::find(&room.scene, 0.05, &occ);
    // The room's wall z = 0 (node `room_4`, facing +Z).
    let node = (room.scene.nodes.iter()).position(|n| n.name.as_deref() == Some("room_4"));
    let wall = room.scene.nodes[node.expect("room_4")].surfaces[0];
    let cut = c.cut(wall).expect("the wall is cut along the shelf");
    let mut covered = 0.0;
    for (t, m) in cut.triangles.iter().zip(&cut.covered) {
        let p = t.map(|v| cut.positions[v as usize]);
        if m & cut::FRONT == 0 {
            continue;
        }
        covered += (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
        let centre = (p[0] + p[1] + p[2]) / 3.0;
        assert!(
            (1.3..=2.7).contains(&centre.x) && (1.5..=1.53).contains(&centre.y),
            "covered beyond the shelf at {centre:?}"
        );
    }
    assert!((covered - 1.4 * 0.03).abs() < 1e-9, "covered {covered} m²");
}

#[test]
fn the_wall_at_a_shelfs_corners_reads_the_light_beside_it() {
    // The wall's vertices where the shelf's top meets it at its ends (x 1.3 and 2.7, y 1.53)
    // see the light over the shelf: direct I·cos/d² there, as beside them. The receiver steps off
    // the outline into the open 270° around it; stepping along the sum of its many thin
    // triangles' directions took the right one under the shelf (direct 0, total 7.7 against
    // 21 lx), a dark blotch over the wall's large triangles in every viewer. The scene is the
    // shelf_on_wall fixture as glTF (bench/shelf_scene.py): its quads' diagonals made the cut
    // that showed it.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/shelf/shelf.gltf");
    let scene = luxbake::import::load(&path, &Default::default()).expect("shelf.gltf");
    let r = bake(&scene, &Settings::default(), &Silent).expect("bake");
    let light = DVec3::new(2.0, 2.2, 2.5);
    let intensity = 1000.0 / (4.0 * std::f64::consts::PI);
    let mut corners = 0;
    for s in &r.surfaces {
        for (v, p) in s.positions.iter().enumerate() {
            // glTF positions are f32: within 10⁻⁶ m.
            let at_corner = [1.3, 2.7].iter().any(|x| (p.x - x).abs() < 1e-6)
                && (p.y - 1.53).abs() < 1e-6
                && p.z.abs() < 1e-6
                && s.normals[v].z > 0.9;
            if !at_corner || s.illuminance[v] == 0.0 {
                continue; // the covered side's twin reads 0
            }
            let d = light - *p;
            let want = intensity * d.z / d.length().powi(3);
            let got = s.illuminance_direct[v] as f64;
            eprintln!("corner {p}: direct {got:.3} lx, exact {want:.3} lx");
            assert!(
                (got - want).abs() < 0.02 * want,
                "corner {p}: {got} vs {want}"
            );
            corners += 1;
        }
    }
    assert_eq!(corners, 2, "both top corners on the wall");
}

#[test]
fn a_furnished_room_closes_energy() {
    // A desk on legs, a cabinet against a wall and a shelf on another. Issue 55 measured
    // −0.53 % / −0.90 % (ρ 0.5 / 0.8) and asks 0.5 % and a balance of 10⁻⁴. Measured now
    // −0.25 % / −0.20 % and 5·10⁻¹⁰; before the desk's corner vertices (under its legs' tops,
    // too small to cut along) stepped out from under them, −0.32 % / −0.53 %, and before the
    // balancing ended on a column step, a balance of 2.1·10⁻⁴.
    let mut worst = [0.0; 2];
    for rho in [0.5, 0.8] {
        let room = contacts::furnished_room(rho);
        check_closed(&format!("furnished ρ {rho}"), &room, rho, &mut worst);
    }
    assert!(worst[0] <= 1e-4, "balance error {:.2e}", worst[0]);
    assert!(worst[1] <= 0.005, "Σ(1 − ρ)·E·A off Φ by {:.2e}", worst[1]);
}

/// A desk leg's foot (2 × 2 cm under a 0.7 m leg) is a cover smaller than a quarter patch: the
/// floor is left uncut under it (no covered part on the floor), while the leg's own bottom face,
/// closing the solid with nothing in front of it but the floor, is covered, so every value the
/// leg shows comes from its lit sides (none reads the 0 lx of its foot).
#[test]
fn a_legs_foot_leaves_the_floor_uncut_and_covers_itself() {
    use luxbake::fixtures::SceneBuilder;
    let mut b = SceneBuilder::new();
    let grey = b.material("grey", 0.5);
    b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, grey);
    let (lo, hi) = (DVec3::new(2.0, 0.0, 2.0), DVec3::new(2.02, 0.7, 2.02));
    b.axis_box("leg", lo, hi, false, grey);
    b.point_light("lamp", DVec3::new(1.0, 2.5, 1.5), 10_000.0);
    let scene = b.build();
    let r = bake(&scene, &Settings::default(), &Silent).expect("bake");
    let named = |name: &str| {
        let node = scene
            .nodes
            .iter()
            .position(|n| n.name.as_deref() == Some(name));
        scene.nodes[node.unwrap_or_else(|| panic!("{name}"))].surfaces[0]
    };
    let floor = (0..6)
        .map(|k| named(&format!("room_{k}")))
        .find(|&s| scene.surfaces[s].positions.iter().all(|p| p.y == 0.0))
        .expect("the floor");
    let floor_parts: Vec<_> = r.surfaces.iter().filter(|s| s.surface == floor).collect();
    assert!(!floor_parts.is_empty());
    assert!(
        floor_parts.iter().all(|s| s.covered_from.is_none()),
        "the floor was cut under a 2 × 2 cm foot"
    );
    let legs: Vec<usize> = (0..6).map(|k| named(&format!("leg_{k}"))).collect();
    let foot = legs
        .iter()
        .copied()
        .find(|&s| scene.surfaces[s].positions.iter().all(|p| p.y == 0.0))
        .expect("the leg's bottom face");
    let foot_parts: Vec<_> = r.surfaces.iter().filter(|s| s.surface == foot).collect();
    assert!(
        !foot_parts.is_empty() && foot_parts.iter().all(|s| s.covered_from.is_some()),
        "the leg's foot is not covered"
    );
    let shown = r
        .surfaces
        .iter()
        .filter(|s| legs.contains(&s.surface) && s.covered_from.is_none());
    let least = shown
        .flat_map(|s| s.illuminance.iter().copied())
        .fold(f32::INFINITY, f32::min);
    assert!(
        least.is_finite() && least > 1.0,
        "the leg's minimum {least} lx"
    );
}
