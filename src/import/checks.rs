//! The last step of every import: the numbers of the scene are ones a bake can use.
//!
//! Input: a [`Scene`] as a format importer built it. Output: the same scene with triangles that
//! have no area dropped (each affected primitive named in a warning; a primitive left with none,
//! or placed by a singular transform, is dropped; a scene left with none is an error), or an [`Error::Input`] naming the file, the
//! element and the value when a number is not finite or beyond what a room can hold: a world
//! coordinate beyond ±[`MAX_COORDINATE`], a photometric amount (cd, cd/m², lm, lx) above
//! [`MAX_PHOTOMETRIC`] (also a luminaire's peak intensity × multiplier and its flux), a probe
//! flag that is not `true`/`false`/an object. Probes outside the box of every surface get a
//! warning. Invariants: a scene without dropped triangles is returned unchanged; the checks do
//! not depend on the input format.

use crate::scene::{EmissionAmount, LightKind, ReflectanceSource, Scene, Surface};
use crate::{Error, Result};
use glam::DVec3;
use serde_json::Value;

pub use crate::photometry::MAX_PHOTOMETRIC;
pub use crate::scene::MAX_COORDINATE;
/// A triangle whose doubled area is at most this fraction of its longest edge squared is taken
/// as having no area (its corners are collinear to rounding).
const DEGENERATE: f64 = 1e-12;

/// Check `scene` and drop its triangles without area (see the module documentation).
pub(crate) fn finish(scene: &mut Scene) -> Result<()> {
    let file = scene.source_file.clone();
    let err = |at: &str, message: String| Error::input(&file, at, message);
    for node in &scene.nodes {
        let m = node.world_from_local;
        if !m.is_finite() {
            return Err(err(
                &node.source_path,
                "its world transform is not finite (a translation, rotation or scale overflows)"
                    .into(),
            ));
        }
        coordinate(m.w_axis.truncate()).map_err(|(axis, v)| {
            err(
                &node.source_path,
                format!(
                    "lies at {axis} = {v:e} m in world space (glTF is +Y up), beyond \
                     ±{MAX_COORDINATE:e} m; check its translation and the units"
                ),
            )
        })?;
        if let Some(extras) = &node.extras {
            probe_flag(extras)
                .map_err(|(at, m)| err(&format!("{}/extras{at}", node.source_path), m))?;
        }
    }
    for s in &scene.surfaces {
        if let Some((axis, v)) = s.positions.iter().find_map(|&p| coordinate(p).err()) {
            let node = &scene.nodes[s.node];
            return Err(err(
                &s.source_path,
                format!(
                    "a vertex of node {} ({}) lies at {axis} = {v:e} m in world space, beyond \
                     ±{MAX_COORDINATE:e} m; check the node's scale and the units",
                    node.name.as_deref().unwrap_or("(unnamed)"),
                    node.source_path
                ),
            ));
        }
    }
    emitters(scene).map_err(|(at, m)| err(&at, m))?;
    drop_degenerate(scene)?;
    warn_default_material(scene);
    warn_far_probes(scene);
    Ok(())
}

/// `Err((axis, value))` when a coordinate is not finite or beyond [`MAX_COORDINATE`].
fn coordinate(p: DVec3) -> std::result::Result<(), (&'static str, f64)> {
    for (axis, v) in [("x", p.x), ("y", p.y), ("z", p.z)] {
        if !(v.is_finite() && v.abs() <= MAX_COORDINATE) {
            return Err((axis, v));
        }
    }
    Ok(())
}

/// `extras.probe` must be a boolean or an object (`{"aligned": bool}`), `extras.toward` three
/// finite numbers; `Err((pointer below extras, message))`.
fn probe_flag(extras: &Value) -> std::result::Result<(), (String, String)> {
    match extras.get("probe") {
        None | Some(Value::Bool(_)) => {}
        Some(Value::Object(o)) => {
            if let Some(a) = o.get("aligned")
                && !a.is_boolean()
            {
                return Err((
                    "/probe/aligned".into(),
                    format!("must be true or false, got {a}"),
                ));
            }
        }
        Some(v) => {
            return Err((
                "/probe".into(),
                format!("must be true, false or an object such as {{\"aligned\": true}}, got {v}"),
            ));
        }
    }
    if extras
        .get("probe")
        .is_some_and(|p| p != &Value::Bool(false))
        && let Some(t) = extras.get("toward")
    {
        let ok = t.as_array().is_some_and(|a| {
            a.len() == 3
                && a.iter().all(|x| x.as_f64().is_some_and(f64::is_finite))
                && a.iter().any(|x| x.as_f64() != Some(0.0))
        });
        if !ok {
            return Err((
                "/toward".into(),
                format!("must be a non-zero direction [x, y, z] (glTF is +Y up), got {t}"),
            ));
        }
    }
    Ok(())
}

/// Every emitted amount finite, ≥ 0 and at most [`MAX_PHOTOMETRIC`].
fn emitters(scene: &Scene) -> std::result::Result<(), (String, String)> {
    let bounded = |v: f64| v.is_finite() && (0.0..=MAX_PHOTOMETRIC).contains(&v);
    for m in &scene.materials {
        let Some(e) = &m.emission else { continue };
        let (value, what) = match e.amount {
            EmissionAmount::Luminance(l) => (l, "luminance (cd/m²)"),
            EmissionAmount::LuminousFlux(f) => (f, "luminous flux (lm)"),
        };
        if !bounded(value) {
            return Err((
                m.source_path.clone(),
                format!(
                    "emission {what} {value:e} is not a finite amount in [0, {MAX_PHOTOMETRIC:e}]"
                ),
            ));
        }
    }
    for l in &scene.lights {
        let unit = match l.kind {
            LightKind::Directional => "lx",
            _ => "cd",
        };
        if !bounded(l.intensity) {
            return Err((
                l.source_path.clone(),
                format!(
                    "intensity {:e} {unit} is not a finite amount in [0, {MAX_PHOTOMETRIC:e}]",
                    l.intensity
                ),
            ));
        }
    }
    for l in &scene.luminaires {
        let Some(p) = scene.profiles.get(l.profile) else {
            continue;
        };
        let peak = p.photometry.max_intensity().0;
        let (intensity, flux) = (peak * l.multiplier, p.photometry.flux() * l.multiplier);
        if !bounded(intensity) || !bounded(flux) {
            return Err((
                l.source_path.clone(),
                format!(
                    "peak intensity {peak:e} cd × multiplier {:e} = {intensity:e} cd (flux \
                     {flux:e} lm) is not a finite amount in [0, {MAX_PHOTOMETRIC:e}]",
                    l.multiplier
                ),
            ));
        }
    }
    Ok(())
}

/// Whether triangle `t` of `positions` has no area (to rounding).
fn degenerate(positions: &[DVec3], t: [u32; 3]) -> bool {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    let longest = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    let doubled = (b - a).cross(c - a).length();
    !(doubled.is_finite() && longest > 0.0 && doubled > DEGENERATE * longest)
}

/// Whether a node's transform cannot be inverted (the output writes meshes in local space).
fn singular(world_from_local: glam::DMat4) -> bool {
    let det = world_from_local.determinant();
    !det.is_finite() || det.abs() < 1e-300 || !world_from_local.inverse().is_finite()
}

/// Drop triangles without area, then surfaces without triangles (renumbering `node.surfaces`).
fn drop_degenerate(scene: &mut Scene) -> Result<()> {
    let before = scene.surfaces.len();
    let mut dropped_any = false;
    let mut keep = vec![true; before];
    for (k, s) in scene.surfaces.iter_mut().enumerate() {
        let node = &scene.nodes[s.node];
        let singular = singular(node.world_from_local);
        let flat: Vec<bool> = (s.triangles.iter())
            .map(|&t| singular || degenerate(&s.positions, t))
            .collect();
        let bad = flat.iter().filter(|&&f| f).count();
        if bad == 0 {
            continue;
        }
        dropped_any = true;
        let whose = format!(
            "{}: {} (node {} {})",
            scene.source_file.display(),
            s.source_path,
            node.name.as_deref().unwrap_or("(unnamed)"),
            node.source_path
        );
        if singular {
            scene.warnings.push(format!(
                "{whose}: the node's transform is singular (a scale of 0?), so the output could \
                 not place its mesh; the primitive is dropped"
            ));
            keep[k] = false;
        } else if bad == s.triangles.len() {
            scene.warnings.push(format!(
                "{whose}: none of its {bad} triangles has an area; the primitive is dropped"
            ));
            keep[k] = false;
        } else {
            scene.warnings.push(format!(
                "{whose}: {bad} of its {} triangles have no area and are dropped",
                s.triangles.len()
            ));
            compact(s, &flat);
        }
    }
    if !dropped_any {
        return Ok(());
    }
    let mut new_index = vec![None; before];
    let mut next = 0;
    for (k, &kept) in keep.iter().enumerate() {
        if kept {
            new_index[k] = Some(next);
            next += 1;
        }
    }
    let mut k = 0;
    scene.surfaces.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    for node in &mut scene.nodes {
        node.surfaces = node.surfaces.iter().filter_map(|&s| new_index[s]).collect();
    }
    if scene.surfaces.is_empty() {
        return Err(Error::input(
            &scene.source_file,
            "",
            "nothing is left to bake: every triangle of the scene has no area",
        ));
    }
    Ok(())
}

/// Keep the triangles not marked `flat` and the vertices they use (in their order).
fn compact(s: &mut Surface, flat: &[bool]) {
    let triangles: Vec<[u32; 3]> = (s.triangles.iter().zip(flat))
        .filter(|(_, f)| !**f)
        .map(|(t, _)| *t)
        .collect();
    let mut remap = vec![u32::MAX; s.positions.len()];
    let mut used = Vec::new();
    for t in &triangles {
        for &i in t {
            if remap[i as usize] == u32::MAX {
                remap[i as usize] = used.len() as u32;
                used.push(i as usize);
            }
        }
    }
    s.positions = pick(&s.positions, &used);
    s.normals = pick(&s.normals, &used);
    s.uv0 = s.uv0.as_deref().map(|v| pick(v, &used));
    s.uv1 = s.uv1.as_deref().map(|v| pick(v, &used));
    s.triangles = triangles
        .into_iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
}

/// The elements of `v` at `used`, in that order.
fn pick<T: Copy>(v: &[T], used: &[usize]) -> Vec<T> {
    used.iter().map(|&i| v[i]).collect()
}

/// One warning naming the primitives that have no material (they reflect the default 0.5).
fn warn_default_material(scene: &mut Scene) {
    let default = scene
        .materials
        .iter()
        .position(|m| m.reflectance_source == ReflectanceSource::Default);
    let Some(default) = default else { return };
    let users: Vec<&str> = scene
        .surfaces
        .iter()
        .filter(|s| s.material == default)
        .map(|s| s.source_path.as_str())
        .collect();
    if let Some(first) = users.first() {
        scene.warnings.push(format!(
            "{}: {} primitive(s) have no material (first: {first}); they reflect the default \
             0.5 and emit nothing",
            scene.source_file.display(),
            users.len()
        ));
    }
}

/// Warn about probe nodes outside the box of every surface (grown by a tenth of its size).
fn warn_far_probes(scene: &mut Scene) {
    let Some((lo, hi)) = scene.bounds() else {
        return;
    };
    let grow = (hi - lo).max_element() * 0.1;
    let (lo, hi) = (lo - DVec3::splat(grow), hi + DVec3::splat(grow));
    for node in &scene.nodes {
        let flagged = node
            .extras
            .as_ref()
            .and_then(|e| e.get("probe"))
            .is_some_and(|p| p.as_bool().unwrap_or(true));
        let at = node.world_from_local.w_axis.truncate();
        if flagged && (at.cmplt(lo).any() || at.cmpgt(hi).any()) {
            scene.warnings.push(format!(
                "{}: probe {} ({}) at [{:.3}, {:.3}, {:.3}] m lies outside the scene's geometry; \
                 it sees no surface",
                scene.source_file.display(),
                node.name.as_deref().unwrap_or("(unnamed)"),
                node.source_path,
                at.x,
                at.y,
                at.z
            ));
        }
    }
}
