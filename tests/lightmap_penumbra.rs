//! Lightmapped penumbrae from an area source are smooth and right (issue 57): the Cornell box
//! (samples/cornell-box, +Y up) baked with `--lightmaps` at default quality (7.7 mm texels).
//! On the floor beside the short block, where its left side's penumbra falls, and over the whole
//! red wall (the tall block's shadow), every texel's direct illuminance is compared with the
//! analytic value at its centre — the light's quad minus the blocks' shadows on it (each
//! block's prism projected from the texel onto the light's plane, clipped to the quad), through
//! Lambert's polygon formula: within 1 % of the local value (or 0.2 % of the unshadowed value
//! where that is larger, at the umbra's edge). Profiles across the floor's edge, read as a
//! viewer reads the lightmap (bilinear), rise monotonically away from the block (no step back
//! above 1 % of the local value). Before (c495214): texels 0 lx where 50 lx are seen (a far
//! group of the light's patches taken as hidden when two rays to it were), then steps of 1.4 %.

mod support;

use glam::{DVec2, DVec3};
use luxbake::geom::lambert;
use std::f64::consts::PI;
use support::cli::{bake_lightmapped, repo_file};

/// The light's quad (y = 0.5488, facing −y) and its luminance Y (cd/m²): the sample's
/// `Ke 13615.9 9611.2 3203.7` through 0.2126 R + 0.7152 G + 0.0722 B.
const LIGHT_Y: f64 = 0.5488;
const LIGHT: [[f64; 2]; 4] = [
    [0.343, 0.227],
    [0.343, 0.332],
    [0.213, 0.332],
    [0.213, 0.227],
];
const LUMINANCE: f64 = 0.2126 * 13615.9 + 0.7152 * 9611.2 + 0.0722 * 3203.7;

/// The blocks: footprint (x, z) and height (m), from the sample's OBJ.
const BLOCKS: [([[f64; 2]; 4], f64); 2] = [
    (
        [[0.13, 0.065], [0.082, 0.225], [0.24, 0.272], [0.29, 0.114]],
        0.165,
    ),
    (
        [
            [0.423, 0.247],
            [0.265, 0.296],
            [0.314, 0.456],
            [0.472, 0.406],
        ],
        0.33,
    ),
];

/// Convex hull (counter-clockwise) of points in the light's plane (x, z).
fn hull(mut p: Vec<DVec2>) -> Vec<DVec2> {
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut h: Vec<DVec2> = Vec::new();
    for pass in [false, true] {
        let start = h.len();
        let points: Vec<DVec2> = if pass {
            p.iter().rev().copied().collect()
        } else {
            p.clone()
        };
        for q in points {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

/// `poly` (convex, counter-clockwise) clipped to the convex counter-clockwise `clip`.
fn clip(poly: &[DVec2], clip: &[DVec2]) -> Vec<DVec2> {
    let mut out = poly.to_vec();
    for k in 0..clip.len() {
        let (a, b) = (clip[k], clip[(k + 1) % clip.len()]);
        let side = |q: DVec2| (b - a).perp_dot(q - a);
        let input = std::mem::take(&mut out);
        for i in 0..input.len() {
            let (p, q) = (input[i], input[(i + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
    }
    out
}

/// The block's shadow on the light's plane seen from `p`: its prism clipped to heights above
/// `p` (what lies lower cannot stand between `p` and a light above it), projected from `p`.
fn shadow(p: DVec3, block: &([[f64; 2]; 4], f64)) -> Vec<DVec2> {
    let (foot, top) = block;
    let low = p.y + 1e-6;
    if *top <= low {
        return Vec::new(); // wholly below the point: it hides nothing of a light above
    }
    let mut points = Vec::new();
    for [x, z] in foot {
        for y in [low.max(0.0), *top] {
            let c = DVec3::new(*x, y, *z);
            let s = (LIGHT_Y - p.y) / (c.y - p.y);
            let q = p + (c - p) * s;
            points.push(DVec2::new(q.x, q.z));
        }
    }
    hull(points)
}

/// Form factor from `p` (unit normal `n`) to a polygon of the light's plane.
fn form_factor(p: DVec3, n: DVec3, poly: &[DVec2]) -> f64 {
    if poly.len() < 3 {
        return 0.0;
    }
    let verts: Vec<DVec3> = poly.iter().map(|q| DVec3::new(q.x, LIGHT_Y, q.y)).collect();
    lambert::form_factor(p, n, &verts)
}

/// Direct illuminance (lx) at `p` (unit normal `n`) from the light past both blocks: the quad's
/// form factor less the parts each block hides (inclusion–exclusion over the convex shadows).
fn analytic(p: DVec3, n: DVec3) -> f64 {
    let light: Vec<DVec2> = hull(LIGHT.iter().map(|&[x, z]| DVec2::new(x, z)).collect());
    let [a, b] = BLOCKS.map(|blk| match shadow(p, &blk) {
        s if s.len() >= 3 => clip(&light, &s),
        _ => Vec::new(),
    });
    let both = if a.len() >= 3 {
        clip(&b, &a)
    } else {
        Vec::new()
    };
    let ff = |poly: &[DVec2]| form_factor(p, n, poly);
    let f = ff(&light) - ff(&a) - ff(&b) + ff(&both);
    PI * LUMINANCE * f
}

/// Every texel of `node`'s lightmap whose centre `keep` accepts against the analytic direct
/// illuminance: (texels compared, worst error over its tolerance with where and the values).
fn texels_against_analytic(
    baked: &luxbake::readback::BakedOutput,
    node: &str,
    keep: impl Fn(DVec3, f64) -> bool,
) -> (usize, (f64, DVec3, f64, f64)) {
    let index = (baked.nodes.iter())
        .position(|n| n.name.as_deref() == Some(node))
        .unwrap();
    let prim = (baked.primitives.iter()).find(|p| p.node == index).unwrap();
    let used = prim.lightmap.as_ref().expect("lightmapped");
    let map = &baked.lightmaps[used.lightmap];
    let unshadowed = analytic(DVec3::new(0.03, 0.0, 0.4), DVec3::Y);
    let mut worst = (0.0f64, DVec3::ZERO, 0.0, 0.0);
    let mut count = 0;
    for &t in &used.texels {
        // The texel reads its centre on the triangle holding it (`texel_point` clamps onto the
        // texel's main triangle, up to half a texel off where the centre lies in another).
        let [col, row] = map.col_row(t.index);
        let uv = DVec2::new(
            (f64::from(col) + 0.5) / f64::from(map.width),
            (f64::from(row) + 0.5) / f64::from(map.height),
        );
        let Some((q, n)) = on_triangle(prim, &used.uv, uv) else {
            continue; // an edge texel: it reads a point inside, not its centre
        };
        if !keep(q, map.texel_size) {
            continue;
        }
        count += 1;
        let (got, want) = (
            f64::from(map.illuminance_direct[t.index as usize]),
            analytic(q, n),
        );
        let err = (got - want).abs() / (0.01 * want).max(0.002 * unshadowed);
        if err > worst.0 {
            worst = (err, q, got, want);
        }
    }
    (count, worst)
}

/// The world point and unit normal of the primitive at `uv`, on the triangle whose layout
/// holds it.
fn on_triangle(
    prim: &luxbake::readback::Primitive,
    uvs: &[DVec2],
    uv: DVec2,
) -> Option<(DVec3, DVec3)> {
    prim.triangles.iter().find_map(|tri| {
        let [a, b, c] = tri.map(|v| uvs[v as usize]);
        let area = (b - a).perp_dot(c - a);
        if area.abs() < 1e-300 {
            return None;
        }
        let w1 = (uv - a).perp_dot(c - a) / area;
        let w2 = (b - a).perp_dot(uv - a) / area;
        let w0 = 1.0 - w1 - w2;
        if w0.min(w1).min(w2) < 0.0 {
            return None;
        }
        let [p0, p1, p2] = tri.map(|v| prim.positions[v as usize]);
        let n = (p1 - p0).cross(p2 - p0).normalize();
        Some((p0 * w0 + p1 * w1 + p2 * w2, n))
    })
}

#[test]
fn the_blocks_penumbrae_are_smooth_and_match_the_analytic_shadows() {
    let (_, out) = support::in_out("penumbra");
    let lit = out.join("lit.gltf");
    let obj = repo_file("samples/cornell-box/cornell-box.obj");
    bake_lightmapped(&obj, &lit);
    let baked = luxbake::readback::read(&lit).unwrap();

    // The floor strip left of the short block's left side (x ≈ 0.10–0.13 there): umbra,
    // penumbra and full light, at least two texels from the block's foot and the green wall.
    let strip = |q: DVec3, texel: f64| q.x > 2.0 * texel && q.x < 0.075 && q.z > 0.1 && q.z < 0.2;
    // The red wall (x ≈ 0.55), two texels in from its edges.
    let wall = |q: DVec3, texel: f64| {
        let m = 2.0 * texel;
        q.y > m && q.y < LIGHT_Y - m && q.z > m && q.z < 0.5592 - m
    };
    let mut results = Vec::new();
    for (node, keep) in [
        ("floor", &strip as &dyn Fn(DVec3, f64) -> bool),
        ("left_wall", &wall),
    ] {
        let (count, worst) = texels_against_analytic(&baked, node, keep);
        eprintln!(
            "{node}: {count} texels; worst {:.2} of the tolerance at {} ({:.1} lx, analytic {:.1} lx)",
            worst.0, worst.1, worst.2, worst.3
        );
        assert!(count > 50, "{node}: {count} texels");
        results.push((node, worst));
    }

    // Profiles across the floor's edge at five depths, every 0.5 mm from the block outwards.
    let surfaces = luxbake::view::surfaces::Surfaces::new(&baked, Vec::new());
    let mut worst_step = (0.0f64, DVec3::ZERO);
    for z in [0.12, 0.14, 0.16, 0.18, 0.2] {
        let mut last: Option<(f64, f64)> = None; // (lightmap, analytic)
        for k in 0..=120 {
            let q = DVec3::new(0.075 - 0.0005 * f64::from(k), 0.0, z);
            let h = surfaces.hit(q + DVec3::Y * 0.01, -DVec3::Y).unwrap();
            assert!((h.distance - 0.01).abs() < 1e-6);
            let (got, want) = (surfaces.direct_illuminance(&h), analytic(q, DVec3::Y));
            if let Some((before, before_want)) = last {
                assert!(
                    want >= before_want * (1.0 - 1e-9),
                    "the oracle rises at {q}"
                );
                let back = (before - got) / got.max(1e-9);
                if back > worst_step.0 {
                    worst_step = (back, q);
                }
            }
            last = Some((got, want));
        }
    }
    eprintln!(
        "worst step back: {:.3} % at {}",
        100.0 * worst_step.0,
        worst_step.1
    );
    for (node, worst) in results {
        assert!(worst.0 <= 1.0, "{node}: {worst:?}");
    }
    assert!(worst_step.0 <= 0.01, "{worst_step:?}");
}
