//! Luminaires with measured distributions against closed forms and brute force: CIE 171:2006
//! test 5.2 (a cosine point source), the near field of a 1.5 × 0.2 m opening, energy balance in a
//! closed room lit by an IES luminaire, and the office sample baked from IES and from EULUMDAT.

use glam::DVec3;
use luxbake::bake::bake;
use luxbake::direct::luminaire::Source;
use luxbake::fixtures::{SceneBuilder, box_faces};
use luxbake::photometry::{Format, Opening, OpeningShape};
use luxbake::progress::Silent;
use luxbake::result::BakeResult;
use luxbake::settings::{Quality, Settings};
use luxbake::visibility::{Occluder, OccluderOptions};
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// An IES LM-63-2002 file with absolute photometry for an axially symmetric distribution
/// I(γ) sampled every `step` degrees from 0 to 180.
fn ies_axial(step: f64, intensity: impl Fn(f64) -> f64) -> String {
    let n = (180.0 / step).round() as usize + 1;
    let gammas: Vec<f64> = (0..n).map(|k| k as f64 * step).collect();
    let values: Vec<String> = gammas
        .iter()
        .map(|g| format!("{:.6}", intensity(g.to_radians())))
        .collect();
    let angles: Vec<String> = gammas.iter().map(|g| format!("{g}")).collect();
    format!(
        "IESNA:LM-63-2002\r\n[TEST] luxbake analytic\r\nTILT=NONE\r\n1 -1 1 {n} 1 1 2 0 0 0\r\n1 1 0\r\n{}\r\n0\r\n{}\r\n",
        angles.join(" "),
        values.join(" ")
    )
}

/// The cosine (Lambertian) point source of CIE 171 test 5.2: I(γ) = 1000·cos γ below the horizon.
fn cosine_source() -> String {
    ies_axial(2.5, |g| {
        if g <= PI / 2.0 {
            1000.0 * g.cos().max(0.0)
        } else {
            0.0
        }
    })
}

/// A 1.5 × 0.2 m rectangular opening with [`cosine_source`]'s profile at the origin, pointing
/// down (−Y), its length along Z.
fn place_linear(b: &mut SceneBuilder) {
    place_opening(b, "linear", 1.5, 0.2);
}

/// A `length` × `width` m rectangular opening with [`cosine_source`]'s profile at the origin,
/// pointing down (−Y), its length along Z.
fn place_opening(b: &mut SceneBuilder, name: &str, length: f64, width: f64) {
    let opening = Opening {
        length,
        width,
        height: 0.0,
        shape: OpeningShape::Rectangular,
    };
    b.luminaire(
        name,
        cosine_source().as_bytes(),
        Format::Ies,
        DVec3::ZERO,
        -DVec3::Y,
        DVec3::Z,
        1.0,
        Some(opening),
    );
}

/// CIE 171:2006 test 5.2: cosine source 3 m above the centre of a 4 × 4 m plane; E = I₀h²/d⁴.
#[test]
fn cie_171_test_5_2_cosine_point_source() {
    // The published table, from the formula (docs/ANALYTIC.md §1 Inverse square).
    let formula = |x: f64, y: f64| 1000.0 * 9.0 / (9.0 + x * x + y * y).powi(2);
    for (x, y, e) in [(0.0, 0.0, 111.11), (1.0, 0.5, 85.66), (1.5, 1.5, 49.38)] {
        assert!(rel(formula(x, y), e) < 5e-4);
    }
    let mut b = SceneBuilder::new();
    let floor = b.material("plane", 0.0);
    b.floor("plane", 2.0, 0.0, floor);
    let ies = cosine_source();
    b.luminaire(
        "cosine source",
        ies.as_bytes(),
        Format::Ies,
        DVec3::new(0.0, 3.0, 0.0),
        -DVec3::Y,
        DVec3::X,
        1.0,
        None,
    );
    let r = bake(&b.build(), &Settings::default(), &Silent).unwrap();
    let mut worst = 0.0f64;
    for (v, p) in r.surfaces[0].positions.iter().enumerate() {
        worst = worst.max(rel(r.surfaces[0].illuminance[v] as f64, formula(p.x, p.z)));
    }
    eprintln!(
        "CIE 5.2 worst {worst:.2e} over {} vertices",
        r.surfaces[0].positions.len()
    );
    eprintln!("oracle: cie5.2 measured {worst:.3e}");
    assert!(worst < 1e-3, "worst {worst}");
    // The profile's flux is π·I₀.
    let emitted = r.summary.sources[0].emitted_lm;
    assert!(rel(emitted, PI * 1000.0) < 5e-3, "{emitted}");
}

/// Illuminance on an upward (+Y) plane at `p` from the 1.5 × 0.2 m opening at the origin (long
/// side along Z) of `source`, brute force: `n` = (along, across) elements, each emitting the
/// distribution scaled by its share of the area, where `seen(element)`.
fn brute_opening(
    source: &Source,
    p: DVec3,
    n: (usize, usize),
    seen: impl Fn(DVec3) -> bool,
) -> f64 {
    brute_sized(source, p, n, (1.5, 0.2), seen)
}

/// [`brute_opening`] for a `(length, width)` m opening (length along Z).
fn brute_sized(
    source: &Source,
    p: DVec3,
    n: (usize, usize),
    (length, width): (f64, f64),
    seen: impl Fn(DVec3) -> bool,
) -> f64 {
    let (nl, nw) = n;
    let mut e = 0.0;
    for i in 0..nl {
        for j in 0..nw {
            let q = DVec3::new(
                ((j as f64 + 0.5) / nw as f64 - 0.5) * width,
                0.0,
                ((i as f64 + 0.5) / nl as f64 - 0.5) * length,
            );
            let d = q - p;
            let cos = DVec3::Y.dot(d);
            if cos > 0.0 && seen(q) {
                let dist = d.length();
                e += source.intensity(-d / dist) / (nl * nw) as f64 * cos / (dist * dist * dist);
            }
        }
    }
    e
}

/// The near field of a 1.5 × 0.2 m luminaire: the split of its opening against a fine
/// brute-force integration over the opening (each element emits the distribution scaled by its
/// share of the area), at 0.3, 1 and 3 m.
#[test]
fn near_field_of_a_linear_luminaire_matches_brute_force() {
    let mut b = SceneBuilder::new();
    place_linear(&mut b);
    let scene = b.build();
    let occ = Occluder::build(&scene, OccluderOptions::default());
    let source = Source::new(&scene, &scene.luminaires[0]);
    let mut worst = 0.0f64;
    for h in [0.3, 1.0, 3.0] {
        // Below the centre, below one end, and off to the side, facing up.
        for p in [
            DVec3::new(0.0, -h, 0.0),
            DVec3::new(0.0, -h, 0.7),
            DVec3::new(0.4, -h, 0.3),
        ] {
            let got = source.illuminance(&occ, p, DVec3::Y);
            let far =
                source.intensity(p.normalize()) * DVec3::Y.dot(-p.normalize()) / p.length_squared();
            let want = brute_opening(&source, p, (1500, 200), |_| true);
            eprintln!(
                "near field h {h} p {p}: split {got:.4} brute {want:.4} point {far:.4} err {:.2e}",
                rel(got, want)
            );
            worst = worst.max(rel(got, want));
        }
    }
    eprintln!("oracle: near-field measured {worst:.3e}");
    assert!(worst < 0.005, "worst near-field error {worst}");
}

fn mean_and_balance(r: &BakeResult) -> (f64, f64) {
    let (mut sum, mut total) = (0.0, 0.0);
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
            for &v in t {
                sum += s.illuminance[v as usize] as f64 * a / 3.0;
                total += a / 3.0;
            }
        }
    }
    (sum / total, r.summary.energy.balance_error_relative)
}

/// A closed 4 × 3 × 5 m room of reflectance 0.8 lit by an IES luminaire with a large opening
/// hanging below the ceiling: the energy balance closes and the mean illuminance is Φ/(S(1−ρ)).
#[test]
fn energy_balances_with_an_ies_luminaire() {
    let rho = 0.8;
    let mut b = SceneBuilder::new();
    let walls = b.material("walls", rho);
    let size = DVec3::new(4.0, 3.0, 5.0);
    for (i, f) in box_faces(DVec3::ZERO, size).iter().enumerate() {
        b.quad(&format!("face_{i}"), *f, walls);
    }
    let ies = ies_axial(5.0, |g| 800.0 * g.cos().max(0.0).powf(1.5) + 50.0);
    let opening = Opening {
        length: 1.2,
        width: 0.3,
        height: 0.0,
        shape: OpeningShape::Rectangular,
    };
    b.luminaire(
        "fitting",
        ies.as_bytes(),
        Format::Ies,
        DVec3::new(2.0, 2.7, 2.5),
        -DVec3::Y,
        DVec3::Z,
        1.0,
        Some(opening),
    );
    let r = bake(&b.build(), &Settings::default(), &Silent).unwrap();
    let phi = r.summary.sources[0].emitted_lm;
    let s = 2.0 * (4.0 * 3.0 + 4.0 * 5.0 + 3.0 * 5.0);
    let (mean, balance) = mean_and_balance(&r);
    let want = phi / (s * (1.0 - rho));
    eprintln!(
        "IES room: Φ {phi:.1} lm, mean {mean:.3} vs {want:.3} ({:.2e}), balance {balance:.2e}",
        rel(mean, want)
    );
    eprintln!("oracle: ies-room/mean measured {:.3e}", rel(mean, want));
    eprintln!("oracle: ies-room/balance measured {balance:.3e}");
    assert!(balance < 5e-3, "balance error {balance}");
    assert!(rel(mean, want) < 5e-3);
    let reached = r.summary.sources[0].reached_surfaces_lm;
    assert!(
        rel(reached, phi) < 2e-3,
        "all of the luminaire's flux lands in a closed room: {reached} vs {phi}"
    );
}

/// The office sample's luminaires given as IES (EXT_lights_ies) and as EULUMDAT
/// (LUXBAKE_luminaire) give the same illuminance everywhere within 0.1 %.
#[test]
fn office_from_ies_and_from_ldt_agree() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/office");
    let load = |name: &str| luxbake::import::load(&root.join(name), &Default::default()).unwrap();
    let settings = Settings {
        quality: Quality::Draft,
        ..Default::default()
    };
    let a = bake(&load("office.gltf"), &settings, &Silent).unwrap();
    let b = bake(&load("office-ldt.gltf"), &settings, &Silent).unwrap();
    let mut worst = 0.0f64;
    let peak = a
        .surfaces
        .iter()
        .flat_map(|s| s.illuminance.iter())
        .fold(0.0f32, |m, e| m.max(*e)) as f64;
    for (sa, sb) in a.surfaces.iter().zip(&b.surfaces) {
        assert_eq!(sa.illuminance.len(), sb.illuminance.len());
        for (ea, eb) in sa.illuminance.iter().zip(&sb.illuminance) {
            // Relative to the value, with a floor of 10⁻⁴ of the peak for dark corners.
            worst = worst.max((ea - eb).abs() as f64 / (*ea as f64).max(1e-4 * peak));
        }
    }
    eprintln!("office IES vs LDT worst {worst:.2e}");
    eprintln!("oracle: ies-ldt/illuminance measured {worst:.3e}");
    assert!(worst < 1e-3, "{worst}");
}

/// An emitting surface whose material carries a profile emits that distribution: with the
/// cosine profile it must light a floor exactly like the same Lambertian panel (Lambert's
/// formula), and the flux it emits is the material's.
#[test]
fn profiled_emitting_surface_with_a_cosine_profile_is_lambertian() {
    use luxbake::scene::{Emission, EmissionAmount};
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", 0.0);
    let profile = b.profile("cosine", cosine_source().as_bytes(), Format::Ies);
    let lamp = b.material_full(
        "panel",
        DVec3::ZERO,
        Some(Emission {
            amount: EmissionAmount::Luminance(1000.0),
            color: DVec3::ONE,
            profile: Some(profile),
        }),
        false,
    );
    b.floor("floor", 3.0, 0.0, floor);
    let panel = [
        DVec3::new(-0.5, 2.0, -0.25),
        DVec3::new(0.5, 2.0, -0.25),
        DVec3::new(0.5, 2.0, 0.25),
        DVec3::new(-0.5, 2.0, 0.25),
    ];
    b.quad("panel", panel, lamp);
    let r = bake(&b.build(), &Settings::default(), &Silent).unwrap();
    let floor = &r.surfaces[0];
    let mut worst = 0.0f64;
    for (v, p) in floor.positions.iter().enumerate() {
        let want = PI * 1000.0 * luxbake::geom::lambert::form_factor(*p, DVec3::Y, &panel);
        worst = worst.max(rel(floor.illuminance[v] as f64, want));
    }
    eprintln!("profiled panel worst {worst:.2e}");
    eprintln!("oracle: profiled-panel measured {worst:.3e}");
    assert!(worst < 5e-3, "{worst}");
    let emitted = r.summary.energy.emitted_lm;
    assert!(rel(emitted, PI * 1000.0 * 0.5) < 1e-3, "{emitted}");
}

/// 576 luminaire positions on a 2.5 m grid at height `h` (glTF +Y up), x and z from −28.75 to
/// 28.75 m.
fn lamp_grid(h: f64) -> Vec<DVec3> {
    (0..576)
        .map(|k| {
            let (i, j) = ((k / 24) as f64, (k % 24) as f64);
            DVec3::new(2.5 * i - 28.75, h, 2.5 * j - 28.75)
        })
        .collect()
}

/// A cosine luminaire (`cosine_source`) aimed down at each of `lamps`.
fn place_cosine_luminaires(b: &mut SceneBuilder, lamps: &[DVec3]) {
    let ies = cosine_source();
    let profile = b.profile("cosine", ies.as_bytes(), Format::Ies);
    for (k, q) in lamps.iter().enumerate() {
        b.place_luminaire(
            &format!("l{k}"),
            profile,
            *q,
            -DVec3::Y,
            DVec3::X,
            1.0,
            None,
        );
    }
}

/// 576 cosine luminaires on a 2.5 m grid 3 m above a black floor (glTF +Y up), a 60 × 60 m
/// ceiling of them: far ones are grouped and their visibility settled by one query a group
/// ([`luxbake::direct::groups`]), their intensities still evaluated one by one. Without a
/// blocker every luminaire is seen and the floor gets exactly the inverse-square cosine sum
/// Σ I₀·h²/d⁴; with a black screen at y = 2.5 over x ∈ [4.3, 40] m (seen from below, it hides
/// the luminaires behind it), the sum over those the screen does not hide; both within 10⁻⁵
/// (the profile is tabulated every 2.5°; illuminance is stored in f32). The screen's shadow edge
/// falls between two columns of luminaires for every vertex here: the test below crosses them.
/// With the light cut on (`--light-cut-fraction`), each vertex must stay within the cut's bound.
#[test]
fn grouped_luminaires_give_the_inverse_square_sum() {
    let h = 3.0;
    let lamps = lamp_grid(h);
    let screen_y = 2.5;
    let behind_screen = |p: DVec3, q: DVec3| {
        let c = p + (q - p) * ((screen_y - p.y) / (q.y - p.y));
        (4.3..=40.0).contains(&c.x) && (-40.0..=40.0).contains(&c.z)
    };
    for screen in [false, true] {
        let mut b = SceneBuilder::new();
        let black = b.material("black", 0.0);
        b.floor("floor", 2.0, 0.0, black);
        if screen {
            let corners = [
                DVec3::new(4.3, screen_y, -40.0),
                DVec3::new(40.0, screen_y, -40.0),
                DVec3::new(40.0, screen_y, 40.0),
                DVec3::new(4.3, screen_y, 40.0),
            ];
            b.quad("screen", corners, black);
        }
        place_cosine_luminaires(&mut b, &lamps);
        let scene = b.build();
        // Exactly (`--exact-direct`), with the light cut at f = 1 %, and with the direct-light
        // budget at b = 1 % (the default): every vertex is within its stated bound, f or b of
        // the full sum (`direct::cut`), besides the 10⁻⁵ above.
        for (cut, budget) in [(0.0, 0.0), (0.01, 0.0), (0.0, 0.01)] {
            let settings = Settings {
                light_cut: cut,
                direct_budget: Some(budget),
                ..Default::default()
            };
            let r = bake(&scene, &settings, &Silent).unwrap();
            let floor = &r.surfaces[0];
            let mut worst = 0.0f64;
            for (v, p) in floor.positions.iter().enumerate() {
                let p = *p;
                let want: f64 = lamps
                    .iter()
                    .filter(|q| !(screen && behind_screen(p, **q)))
                    .map(|q| 1000.0 * h * h / (*q - p).length_squared().powi(2))
                    .sum();
                worst = worst.max(rel(floor.illuminance[v] as f64, want));
            }
            let key = match (screen, cut > 0.0, budget > 0.0) {
                (false, false, false) => "open",
                (true, false, false) => "screen",
                (false, true, _) => "open-cut",
                (true, true, _) => "screen-cut",
                (false, false, true) => "open-budget",
                (true, false, true) => "screen-budget",
            };
            eprintln!("oracle: grouped/{key} measured {worst:.3e}");
            assert!(
                worst < cut + budget + 1e-5,
                "screen {screen}, cut {cut}, budget {budget}: worst {worst}"
            );
        }
    }
}

/// Where two shadow rays a group cannot judge: the 576-luminaire ceiling of the test above (glTF
/// +Y up) over a 16 × 16 m black floor, half of it under a black table top at y = 0.75 m whose
/// edge runs slanted (x = 0.3 + 0.5·z). A vertex under it sees only luminaires far off (4 m out
/// for every metre it lies under the edge), and from it the boundary of what the edge hides
/// crosses columns and rows of luminaires inside far groups. Each vertex's direct light must
/// equal the sum of every luminaire traced on its own (`Source::illuminance`: the same
/// intensities and shadow rays, no grouping) to 10⁻¹², grouping being exact, and the
/// inverse-square sum over the luminaires the top does not hide to 2·10⁻⁵ (the profile is
/// tabulated every 2.5°).
#[test]
fn grouped_luminaires_across_a_slanted_table_edge() {
    let h = 3.0;
    let lamps = lamp_grid(h);
    let top_y = 0.75;
    let edge = |z: f64| 0.3 + 0.5 * z;
    let under_top = |p: DVec3, q: DVec3| {
        let c = p + (q - p) * ((top_y - p.y) / (q.y - p.y));
        (-40.0..=40.0).contains(&c.z) && c.x >= edge(c.z) && c.x <= 60.0
    };
    let mut b = SceneBuilder::new();
    let black = b.material("black", 0.0);
    b.floor("floor", 8.0, 0.0, black);
    let corners = [
        DVec3::new(edge(-40.0), top_y, -40.0),
        DVec3::new(60.0, top_y, -40.0),
        DVec3::new(60.0, top_y, 40.0),
        DVec3::new(edge(40.0), top_y, 40.0),
    ];
    b.quad("table top", corners, black);
    place_cosine_luminaires(&mut b, &lamps);
    let scene = b.build();
    // Exactly (`--exact-direct`: grouping alone, which is exact), then with the direct-light
    // budget at the default b = 1 %, which must keep every vertex within b of tracing each
    // luminaire.
    for budget in [0.0, 0.01] {
        slanted_edge_at(&scene, &lamps, budget, under_top);
    }
}

/// [`grouped_luminaires_across_a_slanted_table_edge`] at direct-light budget `budget`.
fn slanted_edge_at(
    scene: &luxbake::scene::Scene,
    lamps: &[DVec3],
    budget: f64,
    under_top: impl Fn(DVec3, DVec3) -> bool,
) {
    let h = 3.0;
    let settings = Settings {
        patch_size: Some(0.25),
        direct_budget: Some(budget),
        ..Default::default()
    };
    let solved = luxbake::bake::solve(scene, &settings, &Silent).unwrap();
    let solution = &solved.solution;
    let occ = Occluder::build(scene, OccluderOptions::default());
    let sources: Vec<Source> = scene
        .luminaires
        .iter()
        .map(|l| Source::new(scene, l))
        .collect();
    let floor = solution.mesh().groups[0].receivers.clone();
    let (mut traced_err, mut analytic_err, mut oracle_err) = (Vec::new(), Vec::new(), Vec::new());
    let mut dim = 0;
    for v in floor {
        let r = &solution.mesh().receivers[v];
        let (p, n) = (r.point, r.normal);
        assert_eq!(n, DVec3::Y);
        let got = luxbake::scene::luma(solution.vertex(v).direct);
        let traced: f64 = sources.iter().map(|s| s.illuminance(&occ, p, n)).sum();
        // Shadow rays leave the floor pulled up by the occluder's ε (10⁻⁵ of the scene's
        // diagonal, 1.1 mm here): seen at a grazing angle under the top, that moves where they
        // cross the edge by centimetres, so the oracle's rays leave from there too.
        let from = p + n * occ.epsilon;
        let want: f64 = lamps
            .iter()
            .filter(|q| !under_top(from, **q))
            .map(|q| 1000.0 * h * h / (*q - p).length_squared().powi(2))
            .sum();
        // Vertices so deep under the top that almost nothing reaches them (below 0.1 lx; the
        // open floor gets about 500 lx) are judged against 0.1 lx.
        dim += (want < 0.1) as usize;
        traced_err.push((got - traced).abs() / traced.max(0.1));
        analytic_err.push((got - want).abs() / want.max(0.1));
        oracle_err.push((traced - want).abs() / want.max(0.1));
    }
    let stats = |e: &mut Vec<f64>| {
        e.sort_by(f64::total_cmp);
        let n = e.len();
        let over = |x: f64| e.iter().filter(|v| **v > x).count();
        (e[n - 1], e[(n * 99) / 100], over(0.01), over(0.1), n)
    };
    let (t_worst, t_p99, t_1, t_10, n) = stats(&mut traced_err);
    let (a_worst, a_p99, a_1, a_10, _) = stats(&mut analytic_err);
    let (o_worst, o_p99, ..) = stats(&mut oracle_err);
    eprintln!(
        "slanted table edge, budget {budget}, {n} vertices ({dim} below 0.1 lx): against tracing each luminaire \
         worst {t_worst:.2e} p99 {t_p99:.2e} ({t_1} over 1 %, {t_10} over 10 %); against the \
         inverse-square sum worst {a_worst:.2e} p99 {a_p99:.2e} ({a_1} over 1 %, {a_10} over \
         10 %); tracing each against the sum worst {o_worst:.2e} p99 {o_p99:.2e}"
    );
    if budget > 0.0 {
        eprintln!("oracle: grouped/slanted-budget measured {t_worst:.3e}");
        assert!(
            t_worst <= budget + 1e-9,
            "the budget moved a vertex by {t_worst} (p99 {t_p99})"
        );
        return;
    }
    eprintln!("oracle: grouped/slanted-traced measured {t_worst:.3e}");
    eprintln!("oracle: grouped/slanted measured {a_worst:.3e}");
    assert!(
        t_worst < 1e-12,
        "grouping changed a vertex by {t_worst} (p99 {t_p99})"
    );
    assert!(a_worst < 2e-5, "inverse-square sum: worst {a_worst}");
}

/// The soft shadow of a 1.5 × 0.2 m luminaire (long side along Z) cast by a straight edge: a
/// horizontal opaque sheet 0.5 m below the opening covers one side of a line, across the long side
/// (z < 0.1) or along it (x < 0.03); receivers 2 m below face up along a line across the penumbra.
/// Against a brute-force integration over the opening in which each element is seen when its
/// segment to the receiver passes the sheet's edge (geometry, not the tracer). With one ray per
/// near-field sub-source (a row of 8 here) the first penumbra came in steps of 1/8, off by up to
/// 6.2 % of the unshadowed light (15 % of its own), and the second was a single step.
#[test]
fn soft_shadow_of_a_linear_luminaire_matches_brute_force() {
    let results = [false, true].map(soft_shadow);
    for (along, (worst_open, worst_own, lit)) in [false, true].into_iter().zip(results) {
        assert!(
            lit >= 8,
            "along {along}: the line crosses the penumbra ({lit} points in it)"
        );
        assert!(
            worst_open < 0.01,
            "along {along}: worst soft-shadow error {worst_open} of the open light"
        );
        assert!(
            worst_own < 0.03,
            "along {along}: worst soft-shadow error {worst_own} of its own light"
        );
    }
}

/// The worst errors (of the unshadowed light, of the point's own in the penumbra) and the number
/// of points in the penumbra, for the sheet's edge across or along the fitting.
fn soft_shadow(along: bool) -> (f64, f64, usize) {
    // The sheet covers the points where `side(point) < edge`.
    let (edge, side): (f64, fn(DVec3) -> f64) = match along {
        false => (0.1, |p| p.z),
        true => (0.03, |p| p.x),
    };
    let mut b = SceneBuilder::new();
    let sheet = b.material("sheet", 0.0);
    let corners = match along {
        false => [(-20.0, -20.0), (-20.0, edge), (20.0, edge), (20.0, -20.0)],
        true => [(-20.0, -20.0), (-20.0, 20.0), (edge, 20.0), (edge, -20.0)],
    };
    b.quad("sheet", corners.map(|(x, z)| DVec3::new(x, -0.5, z)), sheet);
    place_linear(&mut b);
    let scene = b.build();
    let occ = Occluder::build(&scene, OccluderOptions::default());
    let source = Source::new(&scene, &scene.luminaires[0]);
    // Seen when the segment from p to q crosses the sheet's plane beyond its edge.
    let brute = |p: DVec3, shadowed: bool| {
        brute_opening(&source, p, (3000, 200), |q: DVec3| {
            let d = q - p;
            !shadowed || side(p + d * ((-0.5 - p.y) / d.y)) >= edge
        })
    };
    let (mut worst_open, mut worst_own, mut lit) = (0.0f64, 0.0f64, 0);
    let (from, step) = match along {
        false => (-2.6, 0.25),
        true => (-0.45, 0.05),
    };
    for k in 0..=24 {
        let t = from + step * k as f64;
        let p = match along {
            false => DVec3::new(0.03, -2.0, t),
            true => DVec3::new(t, -2.0, 0.1),
        };
        let got = source.illuminance(&occ, p, DVec3::Y);
        let (want, open) = (brute(p, true), brute(p, false));
        let err = (got - want).abs();
        eprintln!(
            "soft shadow along {along} at {t:+.2}: got {got:.4} brute {want:.4} open {open:.4} err/open {:.2e}",
            err / open
        );
        worst_open = worst_open.max(err / open);
        if want > 0.1 * open && want < 0.99 * open {
            lit += 1;
            worst_own = worst_own.max(err / want);
        }
    }
    eprintln!(
        "soft shadow (edge along the fitting: {along}): worst {worst_open:.3e} of the open light, {worst_own:.3e} of its own ({lit} points in the penumbra)"
    );
    let key = if along { "along" } else { "across" };
    eprintln!("oracle: soft-shadow/{key} measured {worst_open:.3e}");
    (worst_open, worst_own, lit)
}

#[test]
fn a_linear_fitting_in_a_closed_room_puts_all_its_flux_on_the_patches_and_none_in_an_open_one() {
    // A 1.5 m louvred linear fitting (the office sample's Miral profile) 3 cm under the ceiling
    // of a closed 4 × 3 × 5 m box (ρ 0.5): every lumen lands on a patch. Integrated patch by
    // patch, its opening split finer for near patches than for far ones, the patches receive
    // +2.3·10⁻³ of its flux; the closure scales that back and the energy report sees it close. Without the floor most of it escapes: no closure.
    use luxbake::fixtures::openplan::LINEAR_IES;
    let scene = |closed: bool| {
        let mut b = SceneBuilder::new();
        let walls = b.material("walls", 0.5);
        for (i, f) in box_faces(DVec3::ZERO, DVec3::new(4.0, 3.0, 5.0))
            .iter()
            .enumerate()
        {
            if closed || f.iter().any(|p| p.y > 0.1) {
                b.quad(&format!("face_{i}"), *f, walls);
            }
        }
        let p = b.ies_light("linear", LINEAR_IES);
        let at = DVec3::new(2.0, 2.97, 2.5);
        b.place_luminaire("linear", p, at, -DVec3::Y, DVec3::X, 1.0, None);
        b.build()
    };
    let r = bake(&scene(true), &Settings::default(), &Silent).expect("bake");
    let s = &r.summary.sources[0];
    let integrated = s.reached_surfaces_lm / s.emitted_lm - 1.0;
    let balance = r.summary.energy.balance_error_relative;
    eprintln!(
        "closed: integrated {integrated:+.2e}, closure {:.5}, balance {balance:.1e}",
        s.closure
    );
    assert!(
        integrated.abs() > 5e-4,
        "the integration's error is what is closed"
    );
    assert!((s.closure * s.reached_surfaces_lm / s.emitted_lm - 1.0).abs() < 1e-12);
    assert!(balance < 1e-5, "balance {balance:.2e}");
    let r = bake(&scene(false), &Settings::default(), &Silent).expect("bake");
    let s = &r.summary.sources[0];
    let energy = &r.summary.energy;
    eprintln!(
        "open: closure {}, escaped {:.1} of {:.1} lm",
        s.closure, energy.escaped_from_lights_lm, s.emitted_lm
    );
    assert_eq!(s.closure, 1.0);
    assert!(energy.escaped_from_lights_lm > 0.0);
}

/// The soft shadow of a small opening (a 15 × 15 cm downlight, 2.5 m above the receivers: one
/// near-field sub-source) cast by a straight edge running diagonally across it, so that near the
/// penumbra's ends the edge cuts off one corner of the opening and leaves the centre and the
/// other three alone. A horizontal sheet 0.5 m below the opening covers x ∓ z < 0 (+Y up);
/// receivers facing up cross the penumbra. Against brute-force integration over the opening.
/// Unsplit openings once cast hard shadows (the centre's ray alone: up to half the light wrong),
/// and checking two opposite corners missed an edge cutting off one of the other two.
#[test]
fn soft_shadow_of_a_small_opening_matches_brute_force_whichever_corner_the_edge_cuts() {
    let h = 0.075;
    for sign in [1.0, -1.0] {
        // The sheet covers the points where x + sign·z < 0.
        let side = move |p: DVec3| p.x + sign * p.z;
        let mut b = SceneBuilder::new();
        let sheet = b.material("sheet", 0.0);
        // The half plane x + sign·z < 0 at y = −0.5, as a large quad: along its edge, then away.
        let along = DVec3::new(1.0, 0.0, -sign) * 30.0;
        let away = DVec3::new(-1.0, 0.0, -sign) * 30.0;
        let y = DVec3::new(0.0, -0.5, 0.0);
        let half = [y - along, y + along, y + along + away, y - along + away];
        b.quad("sheet", half, sheet);
        place_opening(&mut b, "downlight", 2.0 * h, 2.0 * h);
        let scene = b.build();
        let occ = Occluder::build(&scene, OccluderOptions::default());
        let source = Source::new(&scene, &scene.luminaires[0]);
        // Seen when the segment from p to q crosses the sheet's plane on its open side.
        let brute = |p: DVec3, shadowed: bool| {
            brute_sized(&source, p, (400, 400), (2.0 * h, 2.0 * h), |q: DVec3| {
                let d = q - p;
                !shadowed || side(p + d * ((-0.5 - p.y) / d.y)) >= 0.0
            })
        };
        let (mut worst, mut lit) = (0.0f64, 0);
        for k in 0..=32 {
            // side(p) from −0.8 to 0.8 m: the penumbra spans about ±0.6 m of it.
            let t = -0.8 + 0.05 * k as f64;
            let p = DVec3::new(t / 2.0, -2.5, sign * t / 2.0);
            let got = source.illuminance(&occ, p, DVec3::Y);
            let (want, open) = (brute(p, true), brute(p, false));
            eprintln!(
                "small opening, sign {sign}, at {t:+.2}: got {got:.4} brute {want:.4} open {open:.4}"
            );
            worst = worst.max((got - want).abs() / open);
            lit += (want > 0.02 * open && want < 0.98 * open) as usize;
        }
        eprintln!("oracle: soft-shadow/small-opening/{sign} measured {worst:.3e}");
        assert!(
            lit >= 12,
            "sign {sign}: the line crosses the penumbra ({lit} points in it)"
        );
        assert!(
            worst < 0.01,
            "sign {sign}: worst soft-shadow error {worst} of the open light"
        );
    }
}
