//! Luminaires placed by nodes (`EXT_lights_ies`, `LUXBAKE_luminaire`) → world-space
//! [`Luminaire`]s.
//!
//! Inputs: each node's `extensions.EXT_lights_ies` (`{light, multiplier, color}`) and
//! `extensions.LUXBAKE_luminaire` (`{profile, multiplier, color, maintenanceFactor, opening}`)
//! objects, its `world_from_local`, and how many profiles each root list holds. Output: one
//! [`Luminaire`] per node of the imported scene carrying either extension, in node index order.
//! Rules:
//! - The profile comes from `EXT_lights_ies.light` or `LUXBAKE_luminaire.profile`, exactly one of
//!   them: a node may add `LUXBAKE_luminaire` *without* `profile` to an `EXT_lights_ies` light
//!   (for its maintenance factor or opening); both giving a profile, or neither, is an error at
//!   `/nodes/N`.
//! - `multiplier` = the product of the given multipliers (default 1) × Y(raw colour) ×
//!   maintenance factor, where the raw colour is the per-channel product of the given colours
//!   (default [1, 1, 1]; each channel in [0, 1], as EXT_lights_ies requires) and
//!   Y = 0.2126 R + 0.7152 G + 0.0722 B. `color` = the raw colour normalised to Y = 1.
//! - `position` = the node's world translation. `world_from_photometric` is orthonormal and
//!   right-handed, node scale removed: its Z column is the node's world +Z normalised (so the
//!   nadir, photometric −Z, is exactly the node's world −Z direction), its X column (C = 0°) the
//!   node's world +X made perpendicular to that, and its Y column (C = 90°) = Z × X. Under a
//!   mirroring node transform (negative determinant) that Y column is the *opposite* of the node's
//!   +Y: the distribution itself is never mirrored (C still increases counter-clockwise seen from
//!   above the luminaire), only placed and aimed by the node.
//! - `opening` from `LUXBAKE_luminaire.opening` (rectangular, metres); `extensions` keeps both
//!   objects as given.
//!
//! Invariants: every index, number and colour is checked; a problem is an error at the JSON
//! pointer of the offending member (e.g. `/nodes/3/extensions/LUXBAKE_luminaire/multiplier`).

use super::document::{EXT_LIGHTS_IES, LUXBAKE_LUMINAIRE};
use super::luxbake_ext::{index, number, only_keys, triple};
use super::profiles::{Counts, Sources};
use crate::Result;
use crate::import::context::Ctx;
use crate::photometry::{Opening, OpeningShape};
use crate::scene::{Luminaire, Node, luma, normalise_color};
use glam::{DMat3, DMat4, DVec3};
use serde_json::{Map, Value};

/// The luminaires of the nodes in `reachable` (the imported scene), in node index order.
pub(super) fn luminaires(
    ctx: &Ctx,
    raw: &Value,
    nodes: &[Node],
    reachable: &[usize],
    sources: &Sources,
) -> Result<Vec<Luminaire>> {
    let mut order = reachable.to_vec();
    order.sort_unstable();
    let mut out = Vec::new();
    for i in order {
        let ies = raw.pointer(&format!("/nodes/{i}/extensions/{EXT_LIGHTS_IES}"));
        let lux = raw.pointer(&format!("/nodes/{i}/extensions/{LUXBAKE_LUMINAIRE}"));
        if ies.is_none() && lux.is_none() {
            continue;
        }
        let mut luminaire = luminaire(i, nodes[i].world_from_local, ies, lux, sources.counts)
            .map_err(|(at, message)| ctx.err(at, message))?;
        luminaire.name = nodes[i]
            .name
            .clone()
            .or_else(|| sources.sources[luminaire.profile].name.clone());
        out.push(luminaire);
    }
    Ok(out)
}

/// An error: (JSON pointer, message).
type Fail = (String, String);

/// The luminaire of node `node` from its extension objects (at least one present). `name` is
/// left `None` for the caller.
pub(super) fn luminaire(
    node: usize,
    world: DMat4,
    ies: Option<&Value>,
    lux: Option<&Value>,
    counts: Counts,
) -> Result<Luminaire, Fail> {
    let at = Pointers::new(node);
    let ies = ies.map(|v| object(v, &at.ies)).transpose()?;
    let lux = lux.map(|v| object(v, &at.lux)).transpose()?;
    if let Some(lux) = lux {
        only_keys(
            lux,
            &[
                "profile",
                "multiplier",
                "color",
                "maintenanceFactor",
                "opening",
                "extensions",
                "extras",
            ],
            "the extension",
        )
        .map_err(|m| (at.lux.clone(), m))?;
    }
    let (profile, source_path) = profile(&at, ies, lux, counts)?;
    let (multiplier, raw_color) = multiplier_and_colour(&at, ies, lux)?;
    let color = normalise_color(raw_color).ok_or_else(|| {
        (
            at.node.clone(),
            format!(
                "the colours of {EXT_LIGHTS_IES} and {LUXBAKE_LUMINAIRE} multiply to [{}, {}, \
                 {}], which has no luminance",
                raw_color.x, raw_color.y, raw_color.z
            ),
        )
    })?;
    let maintenance_factor = maintenance_factor(&at, lux)?;
    let opening = lux
        .and_then(|l| l.get("opening"))
        .map(|o| opening(o, &format!("{}/opening", at.lux)))
        .transpose()?;
    let world_from_photometric = photometric_frame(world).ok_or_else(|| {
        (
            at.node.clone(),
            "the node's world transform collapses its X or Z axis, so the luminaire has no \
             orientation"
                .to_owned(),
        )
    })?;

    let mut extensions = Map::new();
    for (name, object) in [(EXT_LIGHTS_IES, ies), (LUXBAKE_LUMINAIRE, lux)] {
        if let Some(object) = object {
            extensions.insert(name.into(), Value::Object(object.clone()));
        }
    }
    Ok(Luminaire {
        name: None,
        source_path,
        node,
        profile,
        multiplier: multiplier * luma(raw_color) * maintenance_factor,
        maintenance_factor,
        color,
        position: world.transform_point3(DVec3::ZERO),
        world_from_photometric,
        opening,
        extensions,
    })
}

/// The JSON pointers of a luminaire node and of its two extension objects.
struct Pointers {
    node: String,
    ies: String,
    lux: String,
}

impl Pointers {
    fn new(node: usize) -> Pointers {
        let node_at = format!("/nodes/{node}");
        Pointers {
            ies: format!("{node_at}/extensions/{EXT_LIGHTS_IES}"),
            lux: format!("{node_at}/extensions/{LUXBAKE_LUMINAIRE}"),
            node: node_at,
        }
    }
}

/// An extension object, if given.
type Object<'v> = Option<&'v Map<String, Value>>;

/// The profile index and the luminaire's source path: from `EXT_lights_ies.light` or
/// `LUXBAKE_luminaire.profile`, exactly one of them.
fn profile(
    at: &Pointers,
    ies: Object,
    lux: Object,
    counts: Counts,
) -> Result<(usize, String), Fail> {
    let ies_profile = ies.map(|ies| ies_light(at, ies, counts)).transpose()?;
    let lux_profile = match lux.and_then(|l| l.get("profile")) {
        None => None,
        Some(p) => {
            let at = format!("{}/profile", at.lux);
            let p = index(p, "profile").map_err(|m| (at.clone(), m))?;
            Some(counts.luxbake_profile(p).ok_or_else(|| {
                (
                    at,
                    format!(
                        "refers to /extensions/{LUXBAKE_LUMINAIRE}/profiles/{p}, which does not \
                         exist (the file has {} there)",
                        counts.luxbake
                    ),
                )
            })?)
        }
    };
    match (ies_profile, lux_profile) {
        (Some(p), None) => Ok((p, at.ies.clone())),
        (None, Some(p)) => Ok((p, at.lux.clone())),
        (Some(_), Some(_)) => Err((
            at.node.clone(),
            format!(
                "the node gives its luminaire two profiles, {EXT_LIGHTS_IES}.light and \
                 {LUXBAKE_LUMINAIRE}.profile; keep one (a {LUXBAKE_LUMINAIRE} beside \
                 {EXT_LIGHTS_IES} must not have a profile)"
            ),
        )),
        (None, None) => Err((
            at.lux.clone(),
            format!(
                "the extension has no profile, and the node has no {EXT_LIGHTS_IES} light to \
                 take one from; give 'profile'"
            ),
        )),
    }
}

/// The profile `EXT_lights_ies.light` names (required in that object).
fn ies_light(at: &Pointers, ies: &Map<String, Value>, counts: Counts) -> Result<usize, Fail> {
    let light_at = format!("{}/light", at.ies);
    let light = ies
        .get("light")
        .ok_or_else(|| (at.ies.clone(), "the extension has no 'light' index".into()))?;
    let light = index(light, "light").map_err(|m| (light_at.clone(), m))?;
    counts.ies_light(light).ok_or_else(|| {
        (
            light_at,
            format!(
                "refers to /extensions/{EXT_LIGHTS_IES}/lights/{light}, which does not \
                 exist (the file has {} there)",
                counts.ies
            ),
        )
    })
}

/// The product of both objects' multipliers, and of their raw colours.
fn multiplier_and_colour(at: &Pointers, ies: Object, lux: Object) -> Result<(f64, DVec3), Fail> {
    let mut multiplier = 1.0;
    let mut raw_color = DVec3::ONE;
    for (object, at) in [(ies, &at.ies), (lux, &at.lux)] {
        let Some(object) = object else { continue };
        if let Some(m) = object.get("multiplier") {
            let m_at = format!("{at}/multiplier");
            let m = number(m, "multiplier").map_err(|e| (m_at.clone(), e))?;
            if !(m.is_finite() && m >= 0.0) {
                return Err((m_at, format!("multiplier {m} must be finite and ≥ 0")));
            }
            multiplier *= m;
        }
        if let Some(c) = object.get("color") {
            raw_color *= color(c, &format!("{at}/color"))?;
        }
    }
    Ok((multiplier, raw_color))
}

/// `LUXBAKE_luminaire.maintenanceFactor`, in (0, 1]; 1 when not given.
fn maintenance_factor(at: &Pointers, lux: Object) -> Result<f64, Fail> {
    match lux.and_then(|l| l.get("maintenanceFactor")) {
        None => Ok(1.0),
        Some(f) => {
            let at = format!("{}/maintenanceFactor", at.lux);
            let f = number(f, "maintenanceFactor").map_err(|e| (at.clone(), e))?;
            if !(f > 0.0 && f <= 1.0) {
                return Err((at, format!("maintenanceFactor {f} must be in (0, 1]")));
            }
            Ok(f)
        }
    }
}

fn object<'v>(v: &'v Value, at: &str) -> Result<&'v Map<String, Value>, Fail> {
    v.as_object()
        .ok_or_else(|| (at.to_owned(), "the extension must be a JSON object".into()))
}

/// A raw colour: three numbers, each in [0, 1], with a positive luminance.
fn color(v: &Value, at: &str) -> Result<DVec3, Fail> {
    let c = triple(v, "color").map_err(|m| (at.to_owned(), m))?;
    if c.to_array().iter().any(|x| !(0.0..=1.0).contains(x)) || luma(c) <= 0.0 {
        return Err((
            at.to_owned(),
            format!(
                "color [{}, {}, {}] must have every channel in [0, 1] and a positive luminance \
                 (0.2126 R + 0.7152 G + 0.0722 B)",
                c.x, c.y, c.z
            ),
        ));
    }
    Ok(c)
}

/// `{length, width, height}` in metres, each finite and ≥ 0.
fn opening(v: &Value, at: &str) -> Result<Opening, Fail> {
    let o = v
        .as_object()
        .ok_or_else(|| (at.to_owned(), "opening must be a JSON object".into()))?;
    only_keys(o, &["length", "width", "height"], "opening").map_err(|m| (at.to_owned(), m))?;
    let mut size = [0.0; 3];
    for (value, key) in size.iter_mut().zip(["length", "width", "height"]) {
        let member_at = format!("{at}/{key}");
        let x = o.get(key).ok_or_else(|| {
            (
                at.to_owned(),
                format!("opening needs length, width and height (m); '{key}' is missing"),
            )
        })?;
        let x = number(x, key).map_err(|m| (member_at.clone(), m))?;
        if !(x.is_finite() && x >= 0.0) {
            return Err((member_at, format!("{key} {x} m must be finite and ≥ 0")));
        }
        *value = x;
    }
    Ok(Opening {
        length: size[0],
        width: size[1],
        height: size[2],
        shape: OpeningShape::Rectangular,
    })
}

/// The orthonormal, right-handed frame of a node (see the module docs): Z = node +Z, X = node +X
/// made perpendicular to Z, Y = Z × X. `None` when either axis collapses.
pub(super) fn photometric_frame(world: DMat4) -> Option<DMat3> {
    let m = DMat3::from_mat4(world);
    let z = m.z_axis.normalize_or_zero();
    let x = (m.x_axis - z * m.x_axis.dot(z)).normalize_or_zero();
    if z == DVec3::ZERO || x == DVec3::ZERO || !(x.is_finite() && z.is_finite()) {
        return None;
    }
    Some(DMat3::from_cols(x, z.cross(x), z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;
    use serde_json::json;

    const COUNTS: Counts = Counts { ies: 2, luxbake: 1 };

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).abs().max_element() < 1e-12
    }

    #[test]
    fn frame_follows_the_node_without_its_scale() {
        // Aim the node's −Z at `down` with its +X along `c0`.
        let down = DVec3::new(1.0, -2.0, 0.5).normalize();
        let c0 = down.any_orthonormal_vector();
        let rotation = DQuat::from_mat3(&DMat3::from_cols(c0, (-down).cross(c0), -down));
        let world = DMat4::from_scale_rotation_translation(
            DVec3::new(3.0, 0.5, 2.0),
            rotation,
            DVec3::new(1.0, 2.0, 3.0),
        );
        let l = luminaire(0, world, Some(&json!({"light": 1})), None, COUNTS).unwrap();
        let f = l.world_from_photometric;
        assert!(close(f * DVec3::NEG_Z, down));
        assert!(close(f * DVec3::X, c0));
        assert!((f.determinant() - 1.0).abs() < 1e-12);
        assert!(close(f.transpose() * f * DVec3::ONE, DVec3::ONE));
        assert!(close(l.position, DVec3::new(1.0, 2.0, 3.0)));
        assert_eq!(l.profile, 1);
        assert_eq!(l.source_path, "/nodes/0/extensions/EXT_lights_ies");
    }

    #[test]
    fn mirrored_node_keeps_a_right_handed_frame() {
        let world = DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0));
        let f = photometric_frame(world).unwrap();
        assert!(close(f * DVec3::NEG_Z, DVec3::NEG_Z));
        assert!(close(f * DVec3::X, DVec3::X));
        assert!(close(f * DVec3::Y, DVec3::Y));
        // Mirrored along Z: the nadir follows the node (world +Z), the frame stays right-handed.
        let f = photometric_frame(DMat4::from_scale(DVec3::new(1.0, 1.0, -2.0))).unwrap();
        assert!(close(f * DVec3::NEG_Z, DVec3::Z));
        assert!((f.determinant() - 1.0).abs() < 1e-12);
        assert!(photometric_frame(DMat4::from_scale(DVec3::new(1.0, 1.0, 0.0))).is_none());
    }

    #[test]
    fn multiplier_colour_and_maintenance() {
        let ies = json!({"light": 0, "multiplier": 2.0, "color": [1.0, 0.5, 0.25]});
        let lux = json!({"multiplier": 3.0, "maintenanceFactor": 0.8, "color": [0.5, 1.0, 1.0],
            "opening": {"length": 1.2, "width": 0.3, "height": 0.0}});
        let l = luminaire(4, DMat4::IDENTITY, Some(&ies), Some(&lux), COUNTS).unwrap();
        let raw = DVec3::new(0.5, 0.5, 0.25);
        let y = 0.2126 * 0.5 + 0.7152 * 0.5 + 0.0722 * 0.25;
        assert!((l.multiplier - 2.0 * 3.0 * y * 0.8).abs() < 1e-12);
        assert_eq!(l.maintenance_factor, 0.8);
        assert!(close(l.color, raw / y));
        let o = l.opening.unwrap();
        assert_eq!((o.length, o.width, o.height), (1.2, 0.3, 0.0));
        assert_eq!(o.shape, OpeningShape::Rectangular);
        assert_eq!(l.profile, 0);
        assert_eq!(l.extensions.len(), 2);
        assert_eq!(l.extensions[LUXBAKE_LUMINAIRE], lux);

        let l = luminaire(
            0,
            DMat4::IDENTITY,
            None,
            Some(&json!({"profile": 0})),
            COUNTS,
        )
        .unwrap();
        assert_eq!((l.profile, l.multiplier, l.color), (2, 1.0, DVec3::ONE));
        assert_eq!(l.opening, None);
        assert_eq!(l.source_path, "/nodes/0/extensions/LUXBAKE_luminaire");
    }

    #[test]
    fn errors_name_the_member() {
        let lux_at = "/nodes/7/extensions/LUXBAKE_luminaire";
        let ies_at = "/nodes/7/extensions/EXT_lights_ies";
        let cases = [
            (Some(json!({"light": 2})), None, format!("{ies_at}/light")),
            (Some(json!({"light": -1})), None, format!("{ies_at}/light")),
            (Some(json!({})), None, ies_at.to_owned()),
            (Some(json!(3)), None, ies_at.to_owned()),
            (
                Some(json!({"light": 0, "multiplier": -1})),
                None,
                format!("{ies_at}/multiplier"),
            ),
            (
                Some(json!({"light": 0, "color": [1.5, 1, 1]})),
                None,
                format!("{ies_at}/color"),
            ),
            (
                Some(json!({"light": 0, "color": [0, 0, 0]})),
                None,
                format!("{ies_at}/color"),
            ),
            (
                Some(json!({"light": 0, "color": [1, 1]})),
                None,
                format!("{ies_at}/color"),
            ),
            (
                Some(json!({"light": 0, "color": [1, 0, 0]})),
                Some(json!({"color": [0, 1, 0]})),
                "/nodes/7".to_owned(),
            ),
            (
                Some(json!({"light": 0})),
                Some(json!({"profile": 0})),
                "/nodes/7".to_owned(),
            ),
            (None, Some(json!({"multiplier": 2})), lux_at.to_owned()),
            (
                None,
                Some(json!({"profile": 1})),
                format!("{lux_at}/profile"),
            ),
            (
                None,
                Some(json!({"profile": 0, "gain": 1})),
                lux_at.to_owned(),
            ),
            (
                None,
                Some(json!({"profile": 0, "maintenanceFactor": 0})),
                format!("{lux_at}/maintenanceFactor"),
            ),
            (
                None,
                Some(json!({"profile": 0, "maintenanceFactor": 1.1})),
                format!("{lux_at}/maintenanceFactor"),
            ),
            (
                None,
                Some(json!({"profile": 0, "opening": {"length": 1, "width": -0.1, "height": 0}})),
                format!("{lux_at}/opening/width"),
            ),
            (
                None,
                Some(json!({"profile": 0, "opening": {"length": 1, "width": 1}})),
                format!("{lux_at}/opening"),
            ),
        ];
        for (ies, lux, expected) in cases {
            let (at, message) =
                luminaire(7, DMat4::IDENTITY, ies.as_ref(), lux.as_ref(), COUNTS).unwrap_err();
            assert_eq!(at, expected, "{ies:?} {lux:?}: {message}");
        }
        let collapsed = DMat4::from_scale(DVec3::new(0.0, 1.0, 1.0));
        let (at, _) =
            luminaire(7, collapsed, Some(&json!({"light": 0})), None, COUNTS).unwrap_err();
        assert_eq!(at, "/nodes/7");
    }
}
