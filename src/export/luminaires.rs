//! The output's photometric profiles and the luminaire extensions of its nodes.
//!
//! Input: the [`Scene`]'s profiles, luminaires and material emissions, and the [`Binary`] being
//! filled. Output: [`Profiles`]: the root `EXT_lights_ies` (`{"lights": [...]}`) and
//! `LUXBAKE_luminaire` (`{"profiles": [...]}`) objects, each node's luminaire extension objects,
//! and the output index of every profile an emitting material uses.
//! Rules: every profile is written as `{bufferView, mimeType, name}` with its bytes embedded in
//! the binary buffer (whatever the input did). A profile that came from `EXT_lights_ies` (its
//! `source_path` says so) goes back to `EXT_lights_ies.lights`, unless a material emission uses it
//! (`LUXBAKE_material.emission.profile` can only index `LUXBAKE_luminaire.profiles`); every other
//! profile goes to `LUXBAKE_luminaire.profiles`, whose `mimeType` is recognised from the bytes
//! (IES LM-63 files of every version have a `TILT=` line, EULUMDAT files have none). Both lists
//! keep scene order, so an imported file's indices come back unchanged.
//! A luminaire's node gets its `EXT_lights_ies` / `LUXBAKE_luminaire` objects as imported, with
//! `light` / `profile` set to the output index; when those objects do not fit the output list
//! of its profile (a scene built in code), they are made from the luminaire's values instead
//! (multiplier, colour scaled to a largest channel of 1, maintenance factor, opening), so that
//! importing the output gives the same luminaire. Neither extension is ever required.

use super::buffer::Binary;
use crate::scene::{Luminaire, Scene, luma};
use glam::DVec3;
use serde_json::{Map, Value, json};

pub const EXT_LIGHTS_IES: &str = "EXT_lights_ies";
pub const LUXBAKE_LUMINAIRE: &str = "LUXBAKE_luminaire";
const IES_MIME: &str = "application/x-ies-lm-63";
const EULUMDAT_MIME: &str = "application/x-eulumdat";

/// Where a scene profile goes in the output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Slot {
    /// `EXT_lights_ies.lights[k]`.
    Ies(usize),
    /// `LUXBAKE_luminaire.profiles[k]`.
    Luxbake(usize),
}

/// The profiles as written, and where each scene profile went.
#[derive(Debug, Default)]
pub struct Profiles {
    slots: Vec<Slot>,
    ies: Vec<Value>,
    luxbake: Vec<Value>,
}

/// Embed every profile of `scene` into `binary` and sort them into the two root lists.
pub(crate) fn profiles(scene: &Scene, binary: &mut Binary) -> Profiles {
    let mut out = Profiles::default();
    let emitting: Vec<usize> = scene
        .materials
        .iter()
        .filter_map(|m| m.emission.and_then(|e| e.profile))
        .collect();
    for (i, profile) in scene.profiles.iter().enumerate() {
        let from_ies = profile
            .source_path
            .starts_with(&format!("/extensions/{EXT_LIGHTS_IES}/"));
        let mime = if from_ies || is_ies(&profile.bytes) {
            IES_MIME
        } else {
            EULUMDAT_MIME
        };
        let mut entry = Map::new();
        entry.insert("bufferView".into(), json!(binary.blob(&profile.bytes)));
        entry.insert("mimeType".into(), json!(mime));
        if let Some(name) = &profile.name {
            entry.insert("name".into(), json!(name));
        }
        let slot = if from_ies && !emitting.contains(&i) {
            out.ies.push(Value::Object(entry));
            Slot::Ies(out.ies.len() - 1)
        } else {
            out.luxbake.push(Value::Object(entry));
            Slot::Luxbake(out.luxbake.len() - 1)
        };
        out.slots.push(slot);
    }
    out
}

/// IES LM-63 files (1986 to 2019) all have a `TILT=` line; EULUMDAT files never do.
fn is_ies(bytes: &[u8]) -> bool {
    bytes.split(|&b| b == b'\n').any(|line| {
        line.trim_ascii_start()
            .get(..5)
            .is_some_and(|s| s.eq_ignore_ascii_case(b"TILT="))
    })
}

impl Profiles {
    /// The output `LUXBAKE_luminaire.profiles` index of scene profile `profile`, if it has one.
    pub(crate) fn luxbake_index(&self, profile: usize) -> Option<usize> {
        match self.slots.get(profile)? {
            Slot::Luxbake(k) => Some(*k),
            Slot::Ies(_) => None,
        }
    }

    /// The root extension objects that are not empty, by name.
    pub(crate) fn root_extensions(&self) -> Vec<(&'static str, Value)> {
        let mut out = Vec::new();
        if !self.ies.is_empty() {
            out.push((EXT_LIGHTS_IES, json!({ "lights": self.ies })));
        }
        if !self.luxbake.is_empty() {
            out.push((LUXBAKE_LUMINAIRE, json!({ "profiles": self.luxbake })));
        }
        out
    }

    /// The luminaire extension objects of each node (empty for nodes without a luminaire; the
    /// first luminaire of a node wins).
    pub(crate) fn node_extensions(&self, scene: &Scene) -> Vec<Vec<(&'static str, Value)>> {
        let mut out = vec![Vec::new(); scene.nodes.len()];
        for l in &scene.luminaires {
            let (Some(slot), Some(node)) = (self.slots.get(l.profile), out.get_mut(l.node)) else {
                continue;
            };
            if node.is_empty() {
                *node = luminaire_extensions(l, *slot);
            }
        }
        out
    }
}

/// The extension objects for luminaire `l` whose profile went to `slot`.
fn luminaire_extensions(l: &Luminaire, slot: Slot) -> Vec<(&'static str, Value)> {
    let given = |name: &str| match l.extensions.get(name) {
        Some(Value::Object(o)) => Some(o.clone()),
        _ => None,
    };
    let mut out = Vec::new();
    match slot {
        Slot::Ies(k) => match given(EXT_LIGHTS_IES) {
            Some(mut ies) => {
                ies.insert("light".into(), json!(k));
                out.push((EXT_LIGHTS_IES, Value::Object(ies)));
                if let Some(mut lux) = given(LUXBAKE_LUMINAIRE) {
                    lux.remove("profile");
                    out.push((LUXBAKE_LUMINAIRE, Value::Object(lux)));
                }
            }
            None => {
                let mut ies = Map::new();
                ies.insert("light".into(), json!(k));
                intensity(l, &mut ies);
                out.push((EXT_LIGHTS_IES, Value::Object(ies)));
                let lux = losses(l, Map::new());
                if !lux.is_empty() {
                    out.push((LUXBAKE_LUMINAIRE, Value::Object(lux)));
                }
            }
        },
        Slot::Luxbake(k) => match given(LUXBAKE_LUMINAIRE).filter(|o| o.contains_key("profile")) {
            Some(mut lux) => {
                lux.insert("profile".into(), json!(k));
                out.push((LUXBAKE_LUMINAIRE, Value::Object(lux)));
            }
            None => {
                let mut lux = Map::new();
                lux.insert("profile".into(), json!(k));
                intensity(l, &mut lux);
                out.push((LUXBAKE_LUMINAIRE, Value::Object(losses(l, lux))));
            }
        },
    }
    out
}

/// `multiplier` and `color` giving back `l.multiplier` and `l.color` on import: the colour
/// scaled to a largest channel of 1, the multiplier divided by its luminance and by the
/// maintenance factor (which is written separately).
fn intensity(l: &Luminaire, out: &mut Map<String, Value>) {
    let max = l.color.max_element();
    let color = if max.is_finite() && max > 0.0 && l.color.min_element() >= 0.0 {
        l.color / max
    } else {
        DVec3::ONE
    };
    let mf = if l.maintenance_factor > 0.0 {
        l.maintenance_factor
    } else {
        1.0
    };
    out.insert(
        "multiplier".into(),
        json!(l.multiplier / (luma(color) * mf)),
    );
    out.insert("color".into(), json!(color.to_array()));
}

/// `maintenanceFactor` (when not 1) and `opening` (when given) added to `out`.
fn losses(l: &Luminaire, mut out: Map<String, Value>) -> Map<String, Value> {
    if l.maintenance_factor != 1.0 {
        out.insert("maintenanceFactor".into(), json!(l.maintenance_factor));
    }
    if let Some(o) = &l.opening {
        out.insert(
            "opening".into(),
            json!({"length": o.length, "width": o.width, "height": o.height}),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ies_files_are_recognised_by_their_tilt_line() {
        assert!(is_ies(b"IESNA:LM-63-2002\n[TEST] x\nTILT=NONE\n1 1000 1"));
        assert!(is_ies(b"label\r\n  tilt=INCLUDE\r\n"));
        assert!(!is_ies(b"Company\n1\n1\n4\n90\n"));
    }
}
