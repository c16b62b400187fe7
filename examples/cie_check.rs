use luxbake::{
    bake::bake,
    fixtures,
    progress::Silent,
    settings::{Quality, Settings},
};
fn main() {
    let rho: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.2);
    for (q, ps, ff) in [
        (Quality::Default, None, Some(0.3)),
        (Quality::Default, None, None),
        (Quality::Default, None, Some(0.1)),
        (Quality::Default, None, Some(0.05)),
    ] {
        let t = std::time::Instant::now();
        let r = bake(
            &fixtures::cie_5_8(rho),
            &Settings {
                quality: q,
                patch_size: ps,
                far_field: ff,
                ..Default::default()
            },
            &Silent,
        )
        .unwrap();
        let (mut sum, mut tot, mut sd, mut sum_all) = (0.0, 0.0, 0.0, 0.0);
        for s in &r.surfaces {
            for t in &s.triangles {
                let p = t.map(|v| s.positions[v as usize]);
                let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
                for &v in t {
                    let v = v as usize;
                    sum += (s.illuminance[v] - s.illuminance_direct[v]) as f64 * a / 3.0;
                    sd += s.illuminance_direct[v] as f64 * a / 3.0;
                    sum_all += s.illuminance[v] as f64 * a / 3.0;
                    tot += a / 3.0;
                }
            }
        }
        let want = rho * 10000.0 / (96.0 * (1.0 - rho));
        println!(
            "{q:?} {ps:?} {ff:?}: patches {} mean ind {:.4} ({:+.3}%) mean dir {:.4} ({:+.3}%) total {:+.3}% time {:.2}s",
            r.summary["counts"]["patches"],
            sum / tot,
            100.0 * (sum / tot / want - 1.0),
            sd / tot,
            100.0 * (sd / tot / (10000.0 / 96.0) - 1.0),
            100.0 * (sum_all / tot / (10000.0 / 96.0 / (1.0 - rho)) - 1.0),
            t.elapsed().as_secs_f64()
        );
    }
}
