//! Whether and how lightmaps are compared: what the asked mode becomes and a note saying why.
//!
//! Vertices mode with lightmaps in both bakes (and [`Options::lightmaps`]) becomes texels when
//! the layouts are the same — the same atlases (numbers and sizes), each matched primitive in
//! the same atlas with its TEXCOORD_1 within 10⁻⁶ of the other's — and samples otherwise.
//! `--mode texels` insists on the same layout and `--mode samples` on lightmaps in both (a
//! [`Mismatch`] saying what differs otherwise). With lightmaps in one bake only, vertices stay
//! vertices (paired by place when the layout re-indexed them: `super::by_position`); means are
//! taken over texels only when both bakes have them.

use super::matching::{Matched, has_lightmaps};
use super::{BakedOutput, Mismatch, Mode, Options};
use glam::DVec2;

/// The largest difference of a TEXCOORD_1 component still taken for the same layout.
const SAME_UV: f64 = 1e-6;

/// What is compared, and how lightmaps were taken (`None` when neither bake has any).
pub(super) struct Plan {
    pub mode: Mode,
    /// Means taken over texels.
    pub texel_means: bool,
    pub note: Option<String>,
}

/// Decide what `options.mode` compares for A and B (matched as `m`).
pub(super) fn plan(
    a: &BakedOutput,
    b: &BakedOutput,
    m: &Matched,
    options: &Options,
) -> Result<Plan, Mismatch> {
    let (in_a, in_b) = (has_lightmaps(a), has_lightmaps(b));
    let plan = |mode, texel_means, note: Option<String>| {
        Ok(Plan {
            mode,
            texel_means,
            note,
        })
    };
    let which = match (in_a, in_b) {
        (true, true) => "both bakes have lightmaps",
        (true, false) => "only A has lightmaps",
        (false, true) => "only B has lightmaps",
        (false, false) => "",
    };
    let forced = matches!(options.mode, Mode::Texels | Mode::Samples);
    if forced && !(in_a && in_b) {
        let which = if which.is_empty() {
            "neither bake has lightmaps"
        } else {
            which
        };
        return Err(Mismatch(format!(
            "{which}; {} needs them in both",
            options.mode.describe()
        )));
    }
    if which.is_empty() {
        return plan(options.mode, false, None);
    }
    let both = in_a && in_b && options.lightmaps;
    let ignored = if options.lightmaps {
        ""
    } else {
        " (not compared: asked not to)"
    };
    match options.mode {
        Mode::Probes => plan(Mode::Probes, false, Some(format!("{which}; not compared"))),
        Mode::Means => {
            let how = if both {
                "means over texels"
            } else {
                "means over vertices"
            };
            plan(Mode::Means, both, Some(format!("{which}{ignored}: {how}")))
        }
        Mode::Vertices if !both => plan(
            Mode::Vertices,
            false,
            Some(format!("{which}{ignored}: compared vertex by vertex")),
        ),
        mode => match (same_layout(a, b, m), mode) {
            (Ok(()), Mode::Vertices | Mode::Texels) => plan(
                Mode::Texels,
                false,
                Some(format!("{which} of the same layout")),
            ),
            (Err(why), Mode::Texels) => Err(Mismatch(format!("lightmap layouts differ: {why}"))),
            (layout, _) => {
                let why = match layout {
                    Ok(()) => "of the same layout (sampled as asked)".to_string(),
                    Err(why) => format!("of other layouts ({why})"),
                };
                plan(Mode::Samples, false, Some(format!("{which} {why}")))
            }
        },
    }
}

/// `mismatch` (of matching for `mode`), with a word on lightmaps in one bake only.
pub(super) fn explain(
    mismatch: Mismatch,
    a: &BakedOutput,
    b: &BakedOutput,
    mode: Mode,
) -> Mismatch {
    let which = match (has_lightmaps(a), has_lightmaps(b)) {
        (true, false) => "A",
        (false, true) => "B",
        _ => return mismatch,
    };
    if !mode.by_vertex() {
        return mismatch;
    }
    Mismatch(format!("{mismatch} (only {which} has lightmaps)"))
}

/// `Ok` when A's and B's lightmap layouts are the same, else the first difference.
fn same_layout(a: &BakedOutput, b: &BakedOutput, m: &Matched) -> Result<(), String> {
    if a.lightmaps.len() != b.lightmaps.len() {
        return Err(format!(
            "{} atlases in A, {} in B",
            a.lightmaps.len(),
            b.lightmaps.len()
        ));
    }
    for (la, lb) in a.lightmaps.iter().zip(&b.lightmaps) {
        if (la.atlas, la.width, la.height) != (lb.atlas, lb.width, lb.height) {
            return Err(format!(
                "atlas {} is {} × {} texels in A, atlas {} {} × {} in B",
                la.atlas, la.width, la.height, lb.atlas, lb.width, lb.height
            ));
        }
    }
    for np in &m.nodes {
        for (j, (&ia, &ib)) in np.prims_a.iter().zip(&np.prims_b).enumerate() {
            let at = format!("node {} primitive {j}", np.name);
            let (pa, pb) = (&a.primitives[ia], &b.primitives[ib]);
            let (la, lb) = match (&pa.lightmap, &pb.lightmap) {
                (None, None) => continue,
                (Some(la), Some(lb)) => (la, lb),
                (la, _) => {
                    let (with, without) = if la.is_some() { ("A", "B") } else { ("B", "A") };
                    return Err(format!("{at} is lightmapped in {with}, not in {without}"));
                }
            };
            let (ka, kb) = (
                a.lightmaps[la.lightmap].atlas,
                b.lightmaps[lb.lightmap].atlas,
            );
            if ka != kb {
                return Err(format!("{at} is in atlas {ka} in A, {kb} in B"));
            }
            let far = (la.uv.iter().zip(&lb.uv))
                .position(|(p, q)| !(*p - *q).abs().cmple(DVec2::splat(SAME_UV)).all());
            if let Some(v) = far {
                let d = (la.uv[v] - lb.uv[v]).abs().max_element();
                return Err(format!("{at}: TEXCOORD_1 of vertex {v} differs by {d:.3e}"));
            }
        }
    }
    Ok(())
}
