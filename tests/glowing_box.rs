//! Direct light from an emitting box (every face glows: a window panel drawn as a 2 mm slab on
//! a wall) is not proved hidden by its own faces. The panel (x 0–0.002, y 0.9–2.1, z 1.7–3.3 m,
//! +Y up) emits 3 000 cd/m² from all its faces, in a black room with a black desk (x 1.4–2.6,
//! y 0–0.75, z 2.6–3.3): nothing stands between the desk's top and the panel's front and bottom
//! faces (its others face away), so each desk-top vertex's direct illuminance is π·L times
//! their form factors by Lambert's polygon formula, within 1 %. A proof that took the panel's
//! box, drawn in from its rim, to lie behind its own bottom face gave 0 lx there.

mod support;

use glam::DVec3;
use luxbake::fixtures::SceneBuilder;
use luxbake::geom::lambert;
use std::f64::consts::PI;
use support::cli::bake;

const LUMINANCE: f64 = 3000.0;

#[test]
fn a_glowing_box_lights_a_desk_as_lamberts_formula_says() {
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    let glow = b.emitter("glow", 0.1, LUMINANCE);
    let p = DVec3::new;
    b.axis_box("room", p(0.0, 0.0, 0.0), p(4.0, 3.0, 5.0), true, black);
    b.axis_box("desk", p(1.4, 0.0, 2.6), p(2.6, 0.75, 3.3), false, black);
    b.axis_box("panel", p(0.0, 0.9, 1.7), p(0.002, 2.1, 3.3), false, glow);
    let (input, out) = support::in_out("glowing-box");
    let source = input.join("scene.gltf");
    luxbake::export::write_scene(&source, &b.build()).unwrap();
    let lit = out.join("lit.gltf");
    let run = bake([source.as_os_str(), "-o".as_ref(), lit.as_os_str()]);
    assert!(run.ok(), "{run:?}");

    let baked = luxbake::readback::read(&lit).unwrap();
    // The desk's six faces are nodes desk_0 … desk_5.
    let on_desk =
        |node: usize| (baked.nodes[node].name.as_deref()).is_some_and(|n| n.starts_with("desk"));
    let front = [
        p(0.002, 0.9, 1.7),
        p(0.002, 0.9, 3.3),
        p(0.002, 2.1, 3.3),
        p(0.002, 2.1, 1.7),
    ];
    let bottom = [
        p(0.0, 0.9, 1.7),
        p(0.0, 0.9, 3.3),
        p(0.002, 0.9, 3.3),
        p(0.002, 0.9, 1.7),
    ];
    let (mut count, mut worst) = (0, (0.0f64, DVec3::ZERO, 0.0, 0.0));
    for prim in baked.primitives.iter().filter(|q| on_desk(q.node)) {
        for (k, &q) in prim.positions.iter().enumerate() {
            // The top, 3 cm in from its edges (receivers on an outline read just off it).
            let inside = q.x > 1.43 && q.x < 2.57 && q.z > 2.63 && q.z < 3.27;
            if (q.y - 0.75).abs() > 1e-6 || !inside {
                continue;
            }
            let ff = |quad: &[DVec3; 4]| lambert::form_factor(q, DVec3::Y, quad).abs();
            let want = PI * LUMINANCE * (ff(&front) + ff(&bottom));
            let got = f64::from(prim.illuminance_direct[k]);
            let rel = (got - want).abs() / want;
            count += 1;
            if rel > worst.0 {
                worst = (rel, q, got, want);
            }
        }
    }
    eprintln!(
        "{count} desk-top vertices; worst {:.3} % at {} ({:.1} lx, Lambert {:.1} lx)",
        100.0 * worst.0,
        worst.1,
        worst.2,
        worst.3
    );
    assert!(count >= 4, "{count}");
    assert!(worst.0 <= 0.01, "{worst:?}");
}
