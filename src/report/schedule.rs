//! The luminaire schedule: the run summary's sources grouped into lines a designer orders from.
//!
//! Input: the run summary's `sources` (`summary::SourceRecord`, with `LuminaireRecord` for
//! luminaires) and the output's nodes (a luminaire node's `extras.power_W`, W, and its
//! `LUXBAKE_luminaire.maintenanceFactor`). Output: one [`ScheduleRow`] per kind, profile,
//! multiplier, maintenance factor and power, in order of first appearance: count, rated lamp flux
//! of one luminaire as its profile states it (lm), light output ratio, maintenance factor,
//! flux emitted by one and by all (lm), power of one and of all (W) when every member gives it.
//! A source's node is the `/nodes/N` its `source` pointer starts with (outputs keep the input's
//! node order).

use crate::readback::BakedOutput;
use crate::summary::{SourceKind, SourceRecord};

/// One line of the schedule.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ScheduleRow {
    /// `luminaire`, `point`, `spot`, `directional`, `profiledSurface`.
    pub kind: SourceKind,
    /// The photometric profile's name (luminaires), else the first member's name.
    pub profile: Option<String>,
    pub count: usize,
    /// Members' names, in order.
    pub names: Vec<String>,
    /// Rated lamp flux of one luminaire as its profile states it (lm); `None`: absolute
    /// photometry or not a luminaire.
    pub rated_lamp_lm: Option<f64>,
    /// The input's multiplier (dimming) of one luminaire, maintenance factor excluded.
    pub multiplier: f64,
    pub light_output_ratio: Option<f64>,
    /// `LUXBAKE_luminaire.maintenanceFactor` (1 when not given).
    pub maintenance_factor: f64,
    /// Flux emitted by one (lm: rated × multiplier × LOR × MF for a luminaire) and by all.
    pub emitted_lm: f64,
    pub emitted_total_lm: f64,
    /// Power of one and of all (W), from the node's `extras.power_W`, when every member gives it.
    pub power_w: Option<f64>,
    pub power_total_w: Option<f64>,
}

/// The schedule of `sources` (the bake's order).
pub(crate) fn schedule(input: &BakedOutput, sources: &[SourceRecord]) -> Vec<ScheduleRow> {
    let mut rows: Vec<ScheduleRow> = Vec::new();
    for s in sources {
        let node = node_of(&s.source).filter(|&n| n < input.nodes.len());
        let info = node.map(|n| &input.nodes[n]);
        let mf = info.and_then(|i| i.maintenance_factor).unwrap_or(1.0);
        let power = info.and_then(|i| i.power_w);
        let name = s.name.clone().unwrap_or_else(|| s.source.clone());
        let (profile, multiplier, rated, lor) = match &s.luminaire {
            Some(l) => {
                // The summary's multiplier and rated flux include the maintenance factor.
                let m = l.multiplier / if mf > 0.0 { mf } else { 1.0 };
                let rated = l
                    .rated_lamp_lm
                    .map(|r| r / l.multiplier.max(f64::MIN_POSITIVE));
                (l.profile.clone(), m, rated, l.light_output_ratio)
            }
            None => (Some(name.clone()), 1.0, None, None),
        };
        let same = |r: &ScheduleRow| {
            r.kind == s.kind
                && r.profile == profile
                && r.multiplier == multiplier
                && r.maintenance_factor == mf
                && r.rated_lamp_lm == rated
                && r.power_w == power
        };
        match rows.iter_mut().find(|r| same(r)) {
            Some(r) => {
                r.count += 1;
                r.names.push(name);
                r.emitted_total_lm += s.emitted_lm;
                r.power_total_w = r.power_w.map(|p| p * r.count as f64);
            }
            None => rows.push(ScheduleRow {
                kind: s.kind,
                profile,
                count: 1,
                names: vec![name],
                rated_lamp_lm: rated,
                multiplier,
                light_output_ratio: lor,
                maintenance_factor: mf,
                emitted_lm: s.emitted_lm,
                emitted_total_lm: s.emitted_lm,
                power_w: power,
                power_total_w: power,
            }),
        }
    }
    for r in &mut rows {
        // One luminaire's flux: the group's mean (members differ only where the bake rounds).
        r.emitted_lm = r.emitted_total_lm / r.count as f64;
    }
    rows
}

/// `N` of a pointer `/nodes/N/…`.
fn node_of(pointer: &str) -> Option<usize> {
    let rest = pointer.strip_prefix("/nodes/")?;
    rest.split('/').next()?.parse().ok()
}

/// The kind in words (`luminaire`, `spot light`).
pub(crate) fn kind_name(k: SourceKind) -> &'static str {
    match k {
        SourceKind::Point => "point light",
        SourceKind::Spot => "spot light",
        SourceKind::Directional => "directional light",
        SourceKind::Luminaire => "luminaire",
        SourceKind::ProfiledSurface => "emitting surface",
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn node_pointer() {
        assert_eq!(
            super::node_of("/nodes/26/extensions/EXT_lights_ies"),
            Some(26)
        );
        assert_eq!(
            super::node_of("/extensions/KHR_lights_punctual/lights/0"),
            None
        );
    }
}
