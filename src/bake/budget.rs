//! Limits checked before a bake allocates anything large.
//!
//! Input: the scene, the validated settings and the patch size the quality or `--patch-size`
//! gives. Output: a [`Budget`] — the patch size to use, the estimates, and a warning when the
//! quality's patch size was raised — or an [`Error::Input`] (exit 1) naming the surface or the
//! option, the number, the limit and what to change.
//!
//! Estimates: patches per surface as `patches::refine` meshes its triangles at `h` (uniform
//! patches; both sides of a double-sided material; the adaptive mesh is usually smaller), probes
//! of `--probe-grid` and `--working-plane` from the scene's extent (+Y up: a grid over x and z),
//! and peak memory at per-item sizes measured on the open-plan floors
//! (see [`BYTES_PER_PATCH`]).
//!
//! Limits: by default what [`RAM_SHARE`] of the machine's memory (physical RAM, or the cgroup's
//! limit if lower) holds at those sizes; `--max-patches` and `--max-probes` set others. When the
//! quality sets the patch size and a sliver (a triangle kilometres long, a stray vertex) would
//! mesh into far more patches than the quality asks for, the patch size is raised instead, with
//! a warning naming the surface; a `--patch-size` given is never changed. When one surface (a
//! ground plane kilometres wide) holds over 99 % of the area, so the default patch size follows
//! it alone, a warning names it and the `--patch-size` the rest would get ([`dominant_surface`]).
//!
//! Invariant: time linear in the input's triangles (a few passes), memory constant.

use crate::error::{Error, Result};
use crate::patches::refine::triangle_patches;
use crate::scene::Scene;
use crate::settings::Settings;

/// Peak resident bytes per *estimated* patch (links, tree, receivers, output) and of the rest of
/// a run, from measured peaks, rounded up so the estimate errs high (`bench/results/limits.md`).
pub const BYTES_PER_PATCH: f64 = 6.0 * 1024.0;
pub const BYTES_BASE: f64 = 64.0 * 1024.0 * 1024.0;
/// Peak resident bytes per probe (the probe, its results, its output node), measured likewise.
pub const BYTES_PER_PROBE: f64 = 32.0 * 1024.0;
/// The share of the machine's memory the default limits allow a bake.
pub const RAM_SHARE: f64 = 0.75;
/// The quality's patch size is raised when the scene would mesh into more than this many times
/// the patches it asks for (its target, or one per triangle and side when that is more).
pub const OVERSHOOT: f64 = 16.0;

/// What a bake may use, and what it is estimated to.
#[derive(Debug, Clone)]
pub struct Budget {
    /// The patch size to mesh at (m).
    pub patch_size: f64,
    /// Estimated patches (uniform meshing at `patch_size`, every side).
    pub patches: f64,
    /// Estimated probes (grid points before any is skipped, node and explicit probes).
    pub probes: f64,
    /// Estimated peak resident memory (bytes).
    pub bytes: f64,
    /// Set when the quality's patch size was raised (names the surface).
    pub warning: Option<String>,
}

/// The patch and probe limits for `settings` on this machine.
pub(crate) fn limits(settings: &Settings) -> (f64, f64) {
    let free = (crate::machine::memory() * RAM_SHARE - BYTES_BASE).max(BYTES_PER_PATCH);
    (
        settings
            .max_patches
            .map_or((free / BYTES_PER_PATCH).floor(), |n| n as f64),
        settings
            .max_probes
            .map_or((free / BYTES_PER_PROBE).floor(), |n| n as f64),
    )
}

/// Patches of the whole scene at `h`, and the surface with the most (index, count).
fn patches_at(scene: &Scene, h: f64) -> (f64, usize, f64) {
    let (mut total, mut worst, mut most) = (0.0, 0, -1.0);
    for (s, surface) in scene.surfaces.iter().enumerate() {
        let sides = if scene.materials[surface.material].double_sided {
            2.0
        } else {
            1.0
        };
        let n: f64 = (surface.triangles.iter())
            .map(|t| triangle_patches(t.map(|v| surface.positions[v as usize]), h).1)
            .sum::<f64>()
            * sides;
        total += n;
        if n > most {
            (worst, most) = (s, n);
        }
    }
    (total, worst, most)
}

/// The smallest patch size in [lo, hi] (about: 1 % apart) at which the scene meshes into at most
/// `n` patches (`hi` when none does).
fn patch_size_for(scene: &Scene, n: f64, lo: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (lo.ln(), hi.ln());
    while hi - lo > 0.01 {
        let mid = (lo + hi) / 2.0;
        if patches_at(scene, mid.exp()).0 <= n {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi.exp()
}

/// `node 'desk' (mesh 'top')`, as far as the surface's node has names.
fn surface_name(scene: &Scene, s: usize) -> String {
    let node = &scene.nodes[scene.surfaces[s].node];
    let mut out = match &node.name {
        Some(n) => format!("node '{n}'"),
        None => format!("node {}", scene.surfaces[s].node),
    };
    if let Some(m) = &node.mesh_name {
        out += &format!(" (mesh '{m}')");
    }
    out
}

/// A count for messages: exact below a million, else 3 significant digits (`1.60e10`).
fn count(x: f64) -> String {
    if x < 1e6 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
    }
}

/// A length for messages (m): six decimals without trailing zeros, or exponent form below 1 µm.
fn metres(x: f64) -> String {
    if x < 1e-6 {
        return format!("{x:e}");
    }
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn gib(bytes: f64) -> String {
    format!("{:.1} GiB", bytes / (1024.0 * 1024.0 * 1024.0))
}

/// Check the scene against the limits at the patch size `h` (the quality's when
/// `settings.patch_size` is `None`), before meshing.
pub(crate) fn check(scene: &Scene, settings: &Settings, h: f64) -> Result<Budget> {
    let (max_patches, max_probes) = limits(settings);
    let memory = crate::machine::memory();
    let why = match settings.max_patches {
        Some(_) => "--max-patches".to_string(),
        None => format!(
            "what {:.0} % of this machine's {} holds at {:.0} KiB each",
            RAM_SHARE * 100.0,
            gib(memory),
            BYTES_PER_PATCH / 1024.0
        ),
    };
    let (mut h, mut warning) = (h, None);
    let (mut total, mut worst, mut most) = patches_at(scene, h);
    if settings.patch_size.is_none() {
        let triangles: f64 = (scene.surfaces.iter())
            .map(|s| {
                let sides = if scene.materials[s.material].double_sided {
                    2.0
                } else {
                    1.0
                };
                s.triangles.len() as f64 * sides
            })
            .sum();
        let asked = settings.params().target_patches.max(triangles);
        if total > OVERSHOOT * asked {
            let (before, name, at) = (
                most,
                surface_name(scene, worst),
                &scene.surfaces[worst].source_path,
            );
            let hi = scene_diagonal(scene).max(h);
            let raised = patch_size_for(scene, OVERSHOOT * asked, h, hi);
            (total, worst, most) = patches_at(scene, raised);
            warning = Some(format!(
                "{}: {at}: {name} would mesh into {} patches at the quality's patch size {} m \
                 (a sliver or a far vertex?); patch size raised to {} m ({} patches in all); \
                 give --patch-size to choose",
                scene.source_file.display(),
                count(before),
                metres(h),
                metres(raised),
                count(total),
            ));
            h = raised;
        }
    }
    if total > max_patches {
        let hi = scene_diagonal(scene).max(h);
        let fix = if patches_at(scene, hi).0 > max_patches {
            "raise the limit with --max-patches N (the scene has more triangles than that)".into()
        } else {
            let fits = patch_size_for(scene, max_patches, h, hi);
            format!(
                "use --patch-size {} or more, or raise the limit with --max-patches N",
                round_up(fits)
            )
        };
        let surface = &scene.surfaces[worst];
        return Err(Error::input(
            &scene.source_file,
            &surface.source_path,
            format!(
                "{} would mesh into {} patches at patch size {} m ({} in all); the limit is {} \
                 patches ({why}): {fix}",
                surface_name(scene, worst),
                count(most),
                metres(h),
                count(total),
                count(max_patches),
            ),
        ));
    }
    let probes = probes(scene, settings, max_probes)?;
    Ok(Budget {
        patch_size: h,
        patches: total,
        probes,
        bytes: BYTES_BASE + total * BYTES_PER_PATCH + probes * BYTES_PER_PROBE,
        warning,
    })
}

/// Two significant digits, rounded up (a length to suggest, m).
fn round_up(x: f64) -> String {
    let digits = x.log10().floor() - 1.0;
    let scale = 10f64.powf(digits);
    format!(
        "{:.*}",
        (-digits).max(0.0) as usize,
        (x / scale).ceil() * scale
    )
}

fn scene_diagonal(scene: &Scene) -> f64 {
    scene
        .bounds()
        .map_or(1.0, |(lo, hi)| (hi - lo).length().max(1e-9))
}

/// Probes the settings ask for, refused above `max`.
fn probes(scene: &Scene, settings: &Settings, max: f64) -> Result<f64> {
    let mut total = settings.extra_probes.len() as f64;
    total += (scene.nodes.iter())
        .filter(|n| n.extras.as_ref().is_some_and(|e| !e["probe"].is_null()))
        .count() as f64;
    let Some((lo, hi)) = scene.bounds() else {
        return Ok(total);
    };
    let grids = [
        ("--probe-grid", settings.probe_grid),
        ("--working-plane-spacing", settings.working_plane),
    ];
    for (flag, grid) in grids {
        let Some(g) = grid else { continue };
        let [nx, nz] = crate::probes::place::grid_counts(lo, hi, g.spacing);
        total += nx * nz;
        if total > max {
            let (w, d) = (hi.x - lo.x, hi.z - lo.z);
            let fits = (w * d / max).sqrt();
            let limit = if settings.max_probes.is_some() {
                "--max-probes".to_string()
            } else {
                format!(
                    "what {:.0} % of this machine's {} holds at {:.0} KiB each",
                    RAM_SHARE * 100.0,
                    gib(crate::machine::memory()),
                    BYTES_PER_PROBE / 1024.0
                )
            };
            return Err(Error::input(
                &scene.source_file,
                "",
                format!(
                    "{flag} {} m over the scene's {w:.1} × {d:.1} m (x by z, +Y up) would place \
                     {} probes; the limit is {} probes ({limit}): use a spacing of {} m or more, \
                     or raise the limit with --max-probes N",
                    metres(g.spacing),
                    count(nx * nz),
                    count(max),
                    round_up(fits),
                ),
            ));
        }
    }
    Ok(total)
}

/// A surface holding more than this share of the scene's area sets the default patch size
/// almost alone ([`dominant_surface`]).
pub const DOMINANT_SHARE: f64 = 0.99;

/// A warning when, with the patch size derived from the quality (`h`, m), one surface (a terrain,
/// a ground plane kilometres wide) holds more than [`DOMINANT_SHARE`] of the area, so the rest of
/// the scene gets patches over ten times larger than it would alone; `None` otherwise.
/// `areas` are the surfaces' areas (m²), in scene order.
pub(crate) fn dominant_surface(
    scene: &Scene,
    areas: &[f64],
    target_patches: f64,
    h: f64,
) -> Option<String> {
    let total: f64 = areas.iter().sum();
    let (k, &big) = areas.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    let rest = total - big;
    if !(big > DOMINANT_SHARE * total && rest > 0.0) {
        return None;
    }
    // The same rule as the default patch size, over the other surfaces only.
    let h_rest = super::default_patch_size(rest, target_patches);
    (h > 10.0 * h_rest).then(|| {
        format!(
            "{} ({}) holds {:.1} % of the scene's area ({:.0} m²), so the default patch size is \
             {} m where the rest of the scene alone would get {} m; give --patch-size {} to mesh \
             the rest finely (the large surface then gets more patches too)",
            surface_name(scene, k),
            scene.surfaces[k].source_path,
            100.0 * big / total,
            big,
            metres(h),
            metres(h_rest),
            metres(h_rest)
        )
    })
}
