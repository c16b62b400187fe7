//! Which light sources `bake fit` dims together, and the scenes it lights with them.
//!
//! A source is a luminaire (`Scene::luminaires`), a punctual light (`Scene::lights`) or an
//! emitting material with a `LUXBAKE_material` emission. A [`Group`] is a set of sources that
//! take one dimming factor. Groups come from `NAME=PATTERN,...` specs (glob patterns, `*` and
//! `?`, matched against a source's names: its node's name, its own name, its profile's name,
//! and `material:NAME` for a material), or by default one group per luminaire profile, one per
//! punctual light and one per emitting material. Sources no group takes keep their light as it
//! is (the fixed part of the fit). Invariant: no source is in two groups.
//!
//! [`lit_by`] makes the scene in which only some sources emit (the others at zero); [`scaled`]
//! the scene with each group's sources scaled by its factor (multipliers for luminaires,
//! intensity for lights, the emitted amount for materials, in the scene and in what the exporter
//! writes of it).

use crate::scene::{EmissionAmount, Scene};
use crate::{Error, Result};
use serde_json::{Value, json};

/// One source of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum SourceId {
    Light(usize),
    Luminaire(usize),
    Material(usize),
}

/// Sources dimmed together.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub name: String,
    pub sources: Vec<SourceId>,
}

/// How to group sources when no spec is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GroupBy {
    /// Luminaires sharing a profile together; each light and emitting material alone.
    #[default]
    Profile,
    /// Every source alone.
    Source,
    /// All sources as one group.
    All,
}

/// Every source of `scene`, with the names patterns match against.
pub(crate) fn sources(scene: &Scene) -> Vec<(SourceId, Vec<String>)> {
    let node_name = |n: usize| scene.nodes[n].name.clone();
    let mut out = Vec::new();
    for (i, l) in scene.lights.iter().enumerate() {
        let names = [node_name(l.node), l.name.clone()];
        out.push((SourceId::Light(i), names.into_iter().flatten().collect()));
    }
    for (i, l) in scene.luminaires.iter().enumerate() {
        let profile = scene.profiles[l.profile].name.clone();
        let names = [node_name(l.node), l.name.clone(), profile];
        out.push((
            SourceId::Luminaire(i),
            names.into_iter().flatten().collect(),
        ));
    }
    for (i, m) in scene.materials.iter().enumerate() {
        if m.emission.is_some() {
            let name = m.name.clone().unwrap_or_else(|| i.to_string());
            out.push((SourceId::Material(i), vec![format!("material:{name}")]));
        }
    }
    out
}

/// A source's name for messages and default group names.
pub(crate) fn describe(scene: &Scene, id: SourceId) -> String {
    let node = |n: usize| scene.nodes[n].name.clone();
    match id {
        SourceId::Light(i) => (node(scene.lights[i].node).or(scene.lights[i].name.clone()))
            .unwrap_or_else(|| format!("light {i}")),
        SourceId::Luminaire(i) => (node(scene.luminaires[i].node))
            .or(scene.luminaires[i].name.clone())
            .unwrap_or_else(|| format!("luminaire {i}")),
        SourceId::Material(i) => format!(
            "material:{}",
            scene.materials[i].name.clone().unwrap_or(i.to_string())
        ),
    }
}

/// The default groups of `scene`.
pub fn default_groups(scene: &Scene, by: GroupBy) -> Vec<Group> {
    let all: Vec<SourceId> = sources(scene).into_iter().map(|(id, _)| id).collect();
    match by {
        GroupBy::All => vec![Group {
            name: "all".into(),
            sources: all,
        }],
        GroupBy::Source => (all.iter())
            .map(|&id| Group {
                name: describe(scene, id),
                sources: vec![id],
            })
            .collect(),
        GroupBy::Profile => {
            let mut groups: Vec<Group> = Vec::new();
            let mut by_profile: Vec<Option<usize>> = vec![None; scene.profiles.len()];
            for id in all {
                if let SourceId::Luminaire(i) = id {
                    let p = scene.luminaires[i].profile;
                    if let Some(g) = by_profile[p] {
                        groups[g].sources.push(id);
                        continue;
                    }
                    by_profile[p] = Some(groups.len());
                    let name =
                        (scene.profiles[p].name.clone()).unwrap_or_else(|| format!("profile {p}"));
                    groups.push(Group {
                        name,
                        sources: vec![id],
                    });
                } else {
                    groups.push(Group {
                        name: describe(scene, id),
                        sources: vec![id],
                    });
                }
            }
            groups
        }
    }
}

/// Groups from `NAME=PATTERN,PATTERN` specs (errors: a malformed spec, a pattern matching no
/// source, a source in two groups, an emitting material without a LUXBAKE_material emission).
pub fn parse_groups(scene: &Scene, specs: &[String]) -> Result<Vec<Group>> {
    let all = sources(scene);
    let mut taken: Vec<(SourceId, String)> = Vec::new();
    let mut groups = Vec::new();
    for spec in specs {
        let bad = |m: String| Error::Settings(format!("--group '{spec}': {m}"));
        let (name, patterns) = spec
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=PATTERN[,PATTERN...]".into()))?;
        let name = name.trim();
        if name.is_empty() {
            return Err(bad("the group has no name".into()));
        }
        let mut members = Vec::new();
        for pattern in patterns.split(',').map(str::trim) {
            let hits: Vec<SourceId> = (all.iter())
                .filter(|(_, names)| names.iter().any(|n| glob(pattern, n)))
                .map(|(id, _)| *id)
                .collect();
            if pattern.is_empty() || hits.is_empty() {
                return Err(bad(format!(
                    "'{pattern}' matches no light source (sources: {})",
                    (all.iter())
                        .map(|(id, _)| describe(scene, *id))
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
            members.extend(hits);
        }
        members.sort();
        members.dedup();
        for &id in &members {
            if let Some((_, other)) = taken.iter().find(|(t, _)| *t == id) {
                return Err(bad(format!(
                    "{} is already in group '{other}'",
                    describe(scene, id)
                )));
            }
            if let SourceId::Material(m) = id
                && !has_extension_emission(scene, m)
            {
                return Err(bad(format!(
                    "{} emits through its core emissiveFactor; give it a LUXBAKE_material \
                     emission to dim it",
                    describe(scene, id)
                )));
            }
            taken.push((id, name.to_owned()));
        }
        if groups.iter().any(|g: &Group| g.name == name) {
            return Err(bad(format!("two groups are named '{name}'")));
        }
        groups.push(Group {
            name: name.to_owned(),
            sources: members,
        });
    }
    Ok(groups)
}

/// The sources of `scene` that no group takes.
pub(crate) fn ungrouped(scene: &Scene, groups: &[Group]) -> Vec<SourceId> {
    (sources(scene).into_iter())
        .map(|(id, _)| id)
        .filter(|id| !groups.iter().any(|g| g.sources.contains(id)))
        .collect()
}

/// `scene` in which only `on` emit: other luminaires removed, other lights at zero intensity,
/// other materials without emission.
pub(crate) fn lit_by(scene: &Scene, on: &[SourceId]) -> Scene {
    let mut s = scene.clone();
    let mut k = 0;
    s.luminaires.retain(|_| {
        k += 1;
        on.contains(&SourceId::Luminaire(k - 1))
    });
    for (i, l) in s.lights.iter_mut().enumerate() {
        if !on.contains(&SourceId::Light(i)) {
            l.intensity = 0.0;
        }
    }
    for (i, m) in s.materials.iter_mut().enumerate() {
        if !on.contains(&SourceId::Material(i)) {
            m.emission = None;
        }
    }
    s
}

/// `scene` with group `g`'s sources scaled by `factors[g]`.
pub(crate) fn scaled(scene: &Scene, groups: &[Group], factors: &[f64]) -> Scene {
    let mut s = scene.clone();
    for (g, &x) in groups.iter().zip(factors) {
        for &id in &g.sources {
            match id {
                SourceId::Light(i) => s.lights[i].intensity *= x,
                SourceId::Luminaire(i) => scale_luminaire(&mut s.luminaires[i], x),
                SourceId::Material(i) => scale_emission(&mut s, i, x),
            }
        }
    }
    s
}

/// Scale a luminaire by `x`, in the scene and in the extension object the exporter writes
/// back (EXT_lights_ies's `multiplier` when it has one, else LUXBAKE_luminaire's: the import
/// multiplies both).
fn scale_luminaire(l: &mut crate::scene::Luminaire, x: f64) {
    l.multiplier *= x;
    let name = match l.extensions.contains_key("EXT_lights_ies") {
        true => "EXT_lights_ies",
        false => "LUXBAKE_luminaire",
    };
    if let Some(Value::Object(o)) = l.extensions.get_mut(name) {
        let m = o.get("multiplier").and_then(Value::as_f64).unwrap_or(1.0);
        o.insert("multiplier".into(), json!(m * x));
    }
}

fn has_extension_emission(scene: &Scene, m: usize) -> bool {
    let ext = scene.materials[m].display.luxbake_extension.as_ref();
    ext.and_then(|e| e.get("emission")).is_some()
}

/// Scale material `m`'s emitted amount by `x`, in the scene and in its LUXBAKE_material object.
fn scale_emission(s: &mut Scene, m: usize, x: f64) {
    let material = &mut s.materials[m];
    let Some(e) = material.emission.as_mut() else {
        return;
    };
    let (key, amount) = match &mut e.amount {
        EmissionAmount::Luminance(l) => ("luminance", l),
        EmissionAmount::LuminousFlux(f) => ("luminousFlux", f),
    };
    *amount *= x;
    let amount = *amount;
    if let Some(Value::Object(emission)) =
        (material.display.luxbake_extension.as_mut()).and_then(|ext| ext.get_mut("emission"))
    {
        emission.remove("luminance");
        emission.remove("luminousFlux");
        emission.insert(key.into(), json!(amount));
    }
}

/// Glob match: `*` any run of characters, `?` one character; case-sensitive.
pub(crate) fn glob(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    // Classic two-pointer match with one backtrack point for the last `*`.
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(s) = star {
            i = s + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|c| *c == '*')
}

#[cfg(test)]
mod tests {
    use super::glob;

    #[test]
    fn globs_match_like_a_shell() {
        assert!(glob("luminaire_*", "luminaire_1_light"));
        assert!(glob("*light", "luminaire_1_light"));
        assert!(glob("lum?naire*", "luminaire_2"));
        assert!(glob("*", ""));
        assert!(!glob("luminaire_*", "spotlight"));
        assert!(!glob("spot", "spotlight"));
        assert!(glob("a*b*c", "aXXbYYc"));
        assert!(!glob("a*b*c", "aXXbYY"));
    }
}
