use luxbake::{
    bake::bake,
    fixtures,
    progress::Silent,
    settings::{Quality, Settings},
};
fn main() {
    let which = std::env::args().nth(1).unwrap_or("box".into());
    let q = match std::env::args().nth(2).as_deref() {
        Some("draft") => Quality::Draft,
        Some("high") => Quality::High,
        _ => Quality::Default,
    };
    let rho: f64 = std::env::args()
        .nth(3)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.9);
    let scene = match which.as_str() {
        "cie" => fixtures::cie_5_8(rho),
        "furnace" => fixtures::furnace(glam::DVec3::new(2.0, 3.0, 5.0), rho, 100.0),
        _ => fixtures::closed_box_with_panel(glam::DVec3::new(3.0, 2.5, 4.0), rho, 0.6, 2000.0),
    };
    let t = std::time::Instant::now();
    let r = bake(
        &scene,
        &Settings {
            quality: q,
            record_timings: true,
            ..Default::default()
        },
        &Silent,
    )
    .unwrap();
    eprintln!(
        "total {:.2}s {}",
        t.elapsed().as_secs_f64(),
        r.summary["counts"]
    );
    eprintln!("energy {}", r.summary["energy"]);
}
