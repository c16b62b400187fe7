use luxbake::{bake::bake, fixtures, progress::Silent, settings::Settings};
fn main() {
    let (l, rho) = (100.0, 0.9);
    let r = bake(
        &fixtures::furnace(glam::DVec3::new(2.0, 3.0, 5.0), rho, l),
        &Settings::default(),
        &Silent,
    )
    .unwrap();
    let want = std::f64::consts::PI * l / (1.0 - rho);
    let mut worst = Vec::new();
    for s in &r.surfaces {
        for (v, &lum) in s.luminance.iter().enumerate() {
            worst.push((
                (std::f64::consts::PI * lum as f64 / want - 1.0),
                s.positions[v],
                s.illuminance_direct[v],
            ));
        }
    }
    worst.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
    for w in &worst[..8] {
        println!("{:+.3e} at {:?} Edir {}", w.0, w.1, w.2);
    }
    println!("{}", r.summary["counts"]);
}
