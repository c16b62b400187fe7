//! The meshing stage: uniform patches, or (by default) adaptive ones.
//!
//! Input: the scene, the settings' patch size `h` (m) and the occluder. Output: [`Meshed`]: the
//! [`PatchMesh`] every later stage uses and what the summary says about it, what each patch
//! emits, and the direct light of the scene's sources on that mesh.
//!
//! First the contacts ([`contacts::find`], gap [`contact_gap`]): both the coarse and the final
//! mesh are built from surfaces cut along what covers them, covered parts kept aside.
//!
//! Adaptive meshing starts from patches of `COARSE × h`, estimates the light on them — direct
//! light from the scene's lights, luminaires and profiled emitters (Lambertian emitting surfaces
//! are not in the estimate: their light arrives through the patch field), plus Sumpner's mean
//! indirect illuminance at points that nothing covers within `CONTACT × h` (h/2) — and splits edges
//! where linear interpolation misses it (see [`patches::adapt`]), down to `h / 2`, and at sharp
//! edges of light on broad surfaces to `h / 4` (a luminaire's cut-off on a wall: vertex colours
//! would show the patches there as scallops). Shadow edges and steep gradients of direct light
//! get fine patches, and so do contact lines, where light from the room stops (a fitting on the
//! ceiling, a cabinet against a wall). Smooth regions keep patches 4× the area of the uniform
//! mesh's; steep gradients get patches a quarter of it, sharp edges a sixteenth.
//! `--uniform-patches` turns it off (the harness measures both).

use crate::contacts::{self, Contacts};
use crate::direct::cut::{Cut, CutSettings};
use crate::direct::targets::AtPoint;
use crate::direct::{bounds::ProfileBounds, emitters, sources::DirectSource};
use crate::patches::{self, PatchMesh, adapt::Adapt};
use crate::scene::Scene;
use crate::settings::Settings;
use crate::solution::DirectLight;
use crate::summary::{ContactsRecord, MeshingRecord};
use crate::transport::zones;
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// The adaptive mesh starts from patches this many times the uniform size.
pub const COARSE: f64 = 2.0;

/// A point with geometry nearer than this × h in front of it (along its normal) is covered:
/// under a fitting on the ceiling, behind a cabinet against a wall. Inter-reflected light does
/// not reach it. Half a patch rather than a whole one: at fine patch sizes a whole one also
/// counts as covered what hangs a few centimetres off a surface, and refines around it.
pub const CONTACT: f64 = 0.5;

/// Receivers per coarse group (at most) whose direct light sets the estimate's scale: the
/// scene's mean direct illuminance and Sumpner's indirect light. A scale needs a sample, not
/// every vertex of every chair frame against every luminaire.
const SAMPLED: usize = 128;

/// The largest gap between parallel faces that counts as contact for patch size `h` (m): a
/// quarter of it. Closer than that, the mesh cannot resolve the light between the faces (it
/// is a sliver's); relative to h, so a scene behaves alike at every scale.
pub(crate) fn contact_gap(h: f64) -> f64 {
    0.25 * h
}

/// The patch mesh and what lives on it before any light is computed.
pub struct Meshed<'a> {
    pub mesh: PatchMesh,
    /// `None` for uniform patches.
    pub adaptive: Option<MeshingRecord>,
    pub contacts: ContactsRecord,
    /// All exitance each patch emits (for the output's luminance), profiled emitters included.
    pub emitted: Vec<DVec3>,
    /// Its Lambertian part, which travels through the patch field (profiled emitters are direct
    /// sources instead).
    pub exitance: Vec<DVec3>,
    pub lights: DirectLight<'a>,
}

/// Mesh the scene for patch size `h` and set its light sources on the mesh (`tau_direct`: the
/// far-field ratio for emitting surfaces).
pub(crate) fn stage<'a>(
    scene: &'a Scene,
    settings: &Settings,
    h: f64,
    occluder: &Occluder,
    tau_direct: f64,
) -> Meshed<'a> {
    // Each profile's intensity bounds, built once for meshing and the direct stage.
    let bounds = ProfileBounds::new(scene);
    let contacts = contacts::find(scene, contact_gap(h), occluder);
    let (mut mesh, adaptive) = mesh(scene, settings, h, occluder, &bounds, &contacts);
    mesh.zone = zones::of(&mesh);
    let cut = cut_settings(settings);
    let (emitted, exitance, lights) = light(scene, &mesh, &bounds, (tau_direct, cut), |_| true);
    let contacts = ContactsRecord {
        gap_m: contacts.gap,
        covers: contacts.count(),
        covered_area_m2: (mesh.groups.iter())
            .filter_map(|g| g.covered.as_ref().map(|c| c.area()))
            .sum(),
    };
    Meshed {
        mesh,
        adaptive,
        contacts,
        emitted,
        exitance,
        lights,
    }
}

/// How `settings` has direct light summed: the light cut's fraction and the direct-light
/// budget.
pub(crate) fn cut_settings(settings: &Settings) -> CutSettings {
    CutSettings {
        fraction: settings.light_cut,
        budget: settings.direct_budget(),
    }
}

/// What meshing made that lighting does not remake: a distributed bake's plan hands it to its
/// tasks and its merge ([`restore`]), so that meshing runs once.
pub struct Saved {
    pub mesh: PatchMesh,
    pub adaptive: Option<MeshingRecord>,
    pub contacts: ContactsRecord,
}

impl Meshed<'_> {
    /// The patch size h the mesh was made for (m; recovered from the contact gap it set).
    pub(crate) fn patch_size(&self) -> f64 {
        self.contacts.gap_m / contact_gap(1.0)
    }

    /// What [`restore`] needs (the light on the mesh is dropped).
    pub(crate) fn into_saved(self) -> Saved {
        Saved {
            mesh: self.mesh,
            adaptive: self.adaptive,
            contacts: self.contacts,
        }
    }
}

/// [`stage`]'s result from a [`Saved`] mesh of `scene`: the same sources set on it the same way.
pub(crate) fn restore<'a>(
    scene: &'a Scene,
    settings: &Settings,
    saved: Saved,
    tau_direct: f64,
) -> Meshed<'a> {
    let bounds = ProfileBounds::new(scene);
    let cut = cut_settings(settings);
    let mut mesh = saved.mesh;
    mesh.zone = zones::of(&mesh);
    let lit = light(scene, &mesh, &bounds, (tau_direct, cut), |_| true);
    let (emitted, exitance, lights) = lit;
    Meshed {
        mesh,
        adaptive: saved.adaptive,
        contacts: saved.contacts,
        emitted,
        exitance,
        lights,
    }
}

/// `base`'s mesh lit by the sources of `scene` instead: a scene with the same surfaces and
/// materials whose sources differ (`bake fit` lights one mesh by one group of sources at a
/// time). Punctual lights of zero intensity are left out (they would cost rays for nothing).
/// `cut`: the light cut's fraction and the direct-light budget (`direct::cut`).
pub(crate) fn relight<'a>(
    base: &Meshed,
    scene: &'a Scene,
    tau_direct: f64,
    cut: CutSettings,
) -> Meshed<'a> {
    let mesh = base.mesh.clone();
    let bounds = ProfileBounds::new(scene);
    let lit = |s: &DirectSource| !matches!(s, DirectSource::Punctual(l) if l.intensity == 0.0);
    let (emitted, exitance, lights) = light(scene, &mesh, &bounds, (tau_direct, cut), lit);
    Meshed {
        mesh,
        adaptive: base.adaptive.clone(),
        contacts: base.contacts,
        emitted,
        exitance,
        lights,
    }
}

/// What each patch of `mesh` emits (all of it, and its Lambertian part) and the direct sources
/// on it that `keep` takes (`(tau_direct, cut)`: as for [`DirectLight::new`]).
fn light<'a>(
    scene: &'a Scene,
    mesh: &PatchMesh,
    bounds: &ProfileBounds,
    (tau_direct, cut): (f64, CutSettings),
    keep: impl Fn(&DirectSource) -> bool,
) -> (Vec<DVec3>, Vec<DVec3>, DirectLight<'a>) {
    let emitted = emitters::patch_exitance(scene, mesh);
    let exitance = emitters::diffuse_part(scene, mesh, &emitted);
    let mut sources = DirectSource::all(scene, mesh, &emitted, bounds);
    sources.retain(|s| keep(s));
    let lights = DirectLight::new(sources, mesh, &exitance, tau_direct, cut);
    (emitted, exitance, lights)
}

/// Build the patch mesh for patch size `h`.
fn mesh(
    scene: &Scene,
    settings: &Settings,
    h: f64,
    occluder: &Occluder,
    bounds: &ProfileBounds,
    contacts: &Contacts,
) -> (PatchMesh, Option<MeshingRecord>) {
    if settings.uniform_patches {
        return (patches::build_cut(scene, h, None, contacts), None);
    }
    let coarse = patches::build_cut(scene, COARSE * h, None, contacts);
    let emitted = emitters::patch_exitance(scene, &coarse);
    let sources = DirectSource::all(scene, &coarse, &emitted, bounds);
    if sources.is_empty() {
        // Nothing to adapt to (emitting surfaces only): the uniform mesh.
        return (patches::build_cut(scene, h, None, contacts), None);
    }
    // The estimate the edges are judged by: direct light, plus the room's mean indirect light
    // where nothing covers the point. The ceiling around a fitting mounted on it gets no direct
    // light from downlights, yet its inter-reflected light drops to zero under the fitting: a
    // coarse patch with a covered corner would take a third of the light it receives away.
    let groups = DirectSource::groups(&sources);
    let settled = cut_settings(settings);
    let cut = Cut::new(&sources, &groups, settled.fraction).with_budget(settled.budget);
    let direct = |p: DVec3, n: DVec3| -> f64 {
        let starts = [p + n * occluder.epsilon];
        let settle = |lo: DVec3, hi: DVec3, _n: DVec3| occluder.settle(&starts, lo, hi);
        let normals = [n];
        let mut at = AtPoint::new(&sources, occluder, p, &normals);
        at.soft_shadows = false;
        cut.run(&sources, &groups, p, &normals, settle, &mut at);
        at.luma[0]
    };
    // Each group's mean direct light from at most `SAMPLED` of its receivers, evenly spaced in
    // its order: the estimate needs the scene's levels, not every vertex of every chair.
    let picked: Vec<Vec<usize>> = coarse
        .groups
        .iter()
        .map(|g| {
            let step = g.receivers.len().div_ceil(SAMPLED).max(1);
            g.receivers.clone().step_by(step).collect()
        })
        .collect();
    let points: Vec<(DVec3, DVec3)> = picked
        .iter()
        .flatten()
        .map(|&r| (coarse.receivers[r].point, coarse.receivers[r].normal))
        .collect();
    let values: Vec<f64> = points.par_iter().map(|(p, n)| direct(*p, *n)).collect();
    let mut at = 0;
    let group_means: Vec<f64> = picked
        .iter()
        .map(|k| {
            let m = values[at..at + k.len()].iter().sum::<f64>() / k.len().max(1) as f64;
            at += k.len();
            m
        })
        .collect();
    // The mean over all receivers (each group's mean weighted by its receiver count; the
    // groups' ranges cover the receivers once).
    let mean = coarse
        .groups
        .iter()
        .zip(&group_means)
        .map(|(g, m)| g.receivers.len() as f64 * m)
        .sum::<f64>()
        / coarse.receivers.len().max(1) as f64;
    let indirect = indirect_estimate(scene, &coarse, &group_means);
    let contact = h * CONTACT;
    // Nothing lies within `contact` in front of the point: the room's light reaches it.
    let is_open = |p: DVec3, n: DVec3| occluder.clear(p, n, p + n * contact, DVec3::ZERO);
    let probe = |q: &[(DVec3, DVec3)]| -> Vec<f64> {
        q.par_iter()
            .map(|&(p, n)| direct(p, n) + if is_open(p, n) { indirect } else { 0.0 })
            .collect()
    };
    let open =
        |q: &[(DVec3, DVec3)]| -> Vec<bool> { q.par_iter().map(|&(p, n)| is_open(p, n)).collect() };
    let adapt = Adapt {
        probe: &probe,
        open: Some(&open),
        min_edge: h / 4.0,
        sharp_below: h / 2.0,
        levels: 3,
        mean,
    };
    let mesh = patches::build_cut(scene, COARSE * h, Some(&adapt), contacts);
    let record = MeshingRecord {
        coarse_patch_size: COARSE * h,
        smallest_patch_size: h / 4.0,
        coarse_patches: coarse.patches.len(),
        relative: patches::adapt::RELATIVE,
        absolute: patches::adapt::ABSOLUTE,
        contact_distance: contact,
        indirect_estimate_lx: indirect,
    };
    (mesh, Some(record))
}

/// The scene's mean indirect illuminance by Sumpner's balance for a closed room, ρ̄Φ/(S(1 − ρ̄)),
/// from each coarse group's mean direct illuminance (per side) and the area-weighted reflectance
/// (luminance of the linear RGB): the scale of the light that reaches open surfaces but not
/// covered ones. (`Solution::cuttle_indirect` is the same balance from the solved
/// first-reflected flux; here nothing is solved yet.)
fn indirect_estimate(scene: &Scene, coarse: &PatchMesh, group_means: &[f64]) -> f64 {
    let (mut flux, mut area, mut reflected) = (0.0, 0.0, 0.0);
    for (g, e) in coarse.groups.iter().zip(group_means) {
        let rho = crate::scene::luma(scene.materials[g.material].reflectance);
        flux += e * g.area;
        area += g.area;
        reflected += rho * g.area;
    }
    let rho = (reflected / area.max(1e-300)).min(0.99);
    rho * flux / (area.max(1e-300) * (1.0 - rho))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::scene::LightKind;
    use crate::visibility::OccluderOptions;

    /// Areas of the ceiling's patches (y = 3 m, facing down) by whether their centroid lies
    /// within 0.15 m outside the edge of the square [1.7, 2.3]² (the fitting's footprint) or
    /// more than 0.8 m from it.
    fn ceiling_areas(mesh: &PatchMesh) -> (Vec<f64>, Vec<f64>) {
        let (mut near, mut far) = (Vec::new(), Vec::new());
        for p in &mesh.patches {
            let c = p.corners(&mesh.receivers).iter().sum::<DVec3>() / 3.0;
            if p.normal.y > -0.99 || (c.y - 3.0).abs() > 1e-9 {
                continue;
            }
            let dx = (c.x - 2.0).abs() - 0.3;
            let dz = (c.z - 2.0).abs() - 0.3;
            let outside = dx.max(0.0).hypot(dz.max(0.0));
            if dx.max(dz) > 0.0 && outside < 0.15 {
                near.push(p.area);
            } else if outside > 0.8 {
                far.push(p.area);
            }
        }
        (near, far)
    }

    #[test]
    fn a_fitting_on_an_unlit_ceiling_is_outlined_by_fine_patches() {
        // A 4 × 3 × 4 m room; a 0.6 × 0.05 × 0.6 m fitting on the ceiling; a spot under it
        // pointing down, so the ceiling gets no direct light at all and only the contact line
        // (the room's inter-reflected light stops under the fitting) can refine it.
        let mut b = SceneBuilder::new();
        let white = b.material("white", 0.7);
        b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, white);
        let (lo, hi) = (DVec3::new(1.7, 2.95, 1.7), DVec3::new(2.3, 3.0, 2.3));
        b.axis_box("fitting", lo, hi, false, white);
        let spot = LightKind::Spot {
            inner_cone_angle: 0.5,
            outer_cone_angle: 0.7,
        };
        b.light("spot", spot, DVec3::new(2.0, 2.85, 2.0), -DVec3::Y, 1000.0);
        let scene = b.build();
        let occluder = Occluder::build(&scene, OccluderOptions::default());
        let bounds = ProfileBounds::new(&scene);
        let none = Contacts::none();
        let (mesh, _) = mesh(&scene, &Settings::default(), 0.2, &occluder, &bounds, &none);
        let (near, mut far) = ceiling_areas(&mesh);
        assert!(!near.is_empty() && !far.is_empty());
        let smallest_near = near.iter().copied().fold(f64::INFINITY, f64::min);
        far.sort_by(f64::total_cmp);
        let median_far = far[far.len() / 2];
        // Edges along the contact line are halved down to h/2 (a quarter of the coarse 2h);
        // away from it the ceiling keeps its coarse patches.
        assert!(
            smallest_near < median_far / 8.0,
            "near the fitting {smallest_near} m², far from it {median_far} m²"
        );
        assert!(median_far > 0.03, "far from the fitting: {median_far} m²");
    }
}
