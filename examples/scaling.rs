use luxbake::{bake::bake, fixtures, progress::Silent, settings::Settings};
fn main() {
    for ps in [0.4, 0.2, 0.1, 0.05] {
        let t = std::time::Instant::now();
        let r = bake(
            &fixtures::cie_5_8(0.5),
            &Settings {
                patch_size: Some(ps),
                always_trace: std::env::args().nth(1).is_some(),
                ..Default::default()
            },
            &Silent,
        )
        .unwrap();
        let c = &r.summary["counts"];
        println!(
            "h {ps}: patches {} receivers {} links {} ({:.0}/receiver) rays {} time {:.2}s {:?}",
            c["patches"],
            c["receivers"],
            c["links"],
            c["links"].as_f64().unwrap() / c["receivers"].as_f64().unwrap(),
            c["rays"],
            t.elapsed().as_secs_f64(),
            r.timings
        );
    }
}
