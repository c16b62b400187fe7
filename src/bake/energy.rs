//! The energy stage: emitted = absorbed + escaped, checked, not assumed; and what the summary
//! says about each source.
//!
//! Input: the meshed scene, the occluder, the direct flux into the patches and the solved
//! [`Radiosity`]. Output: [`EnergyBalance`] (lm), and a [`SourceRecord`] per source.
//!
//! Each term is measured on its own: emitted flux from the lights' definitions and the emitting
//! areas; absorbed flux from the solution, (1 − ρ)·E·A summed over patches, plus what lands on the
//! back faces of single-sided surfaces; escaped flux from a fixed pattern of rays that leave the
//! scene (stratified over the sphere for point and spot lights, cosine-weighted over the
//! hemisphere for light leaving surfaces that are not enclosed). Their difference is the balance error: it
//! collects the solver's residual, the balancing tolerance and the error of the escape estimates
//! (in a closed room the transport operator is balanced to conserve flux, see
//! `transport::operator`). A relative error above [`WARN_BALANCE`] (10⁻³) is reported as a
//! warning ([`warning`]).

use super::direct::PatchFlux;
use super::meshing::Meshed;
use super::solve::Radiosity;
use crate::direct::sources::DirectSource;
use crate::scene::{LightKind, Scene, luma};
use crate::summary::{EnergyBalance, LuminaireRecord, SourceKind, SourceRecord};
use crate::transport::escape;
use crate::visibility::Occluder;
use glam::DVec3;

/// `flux`: what the lights and luminaires sent into the patches (its per-patch part may be
/// spent: only the back faces' and each source's totals are read).
pub(crate) fn balance(
    meshed: &Meshed,
    occ: &Occluder,
    flux: &PatchFlux,
    solved: &Radiosity,
) -> EnergyBalance {
    let mesh = &meshed.mesh;
    let mut lights = 0.0;
    let mut lights_escaped = 0.0;
    let sources = meshed.lights.sources.iter();
    for ((source, received), escaped) in sources.zip(&flux.per_source).zip(&flux.escaped) {
        match source.emitted_flux() {
            // A directional light emits what the scene intercepts.
            None => lights += received,
            Some(emitted) => {
                lights += emitted;
                lights_escaped += escaped;
            }
        }
    }
    let surfaces: f64 = mesh
        .patches
        .iter()
        .zip(&meshed.exitance)
        .map(|(p, m)| p.area * luma(*m))
        .sum();
    let mut direct_received = luma(flux.back);
    let mut reflected = 0.0;
    let mut to_back = 0.0;
    let mut surfaces_escaped = 0.0;
    let mut absorbed_front = 0.0;
    let open = open_fractions(meshed, occ, solved);
    for (k, p) in mesh.patches.iter().enumerate() {
        let back =
            p.v.iter()
                .map(|&v| solved.back[v as usize] as f64)
                .sum::<f64>()
                / 3.0;
        let open = open[k];
        let emitted_here = p.area * luma(meshed.exitance[k]);
        let out = emitted_here + p.area * luma(solved.reflected[k]);
        reflected += p.area * luma(solved.reflected[k]);
        to_back += out * back;
        surfaces_escaped += out * open;
        direct_received += p.area * luma(solved.direct_patch[k]) + emitted_here * back;
        let e = solved.direct_patch[k] + solved.indirect_patch[k];
        absorbed_front += p.area * luma((DVec3::ONE - solved.rho[k]) * e);
    }
    let emitted = lights + surfaces;
    let absorbed = absorbed_front + luma(flux.back) + to_back;
    let escaped = lights_escaped + surfaces_escaped;
    let error = emitted - absorbed - escaped;
    EnergyBalance {
        emitted_lm: emitted,
        emitted_by_lights_lm: lights,
        emitted_by_surfaces_lm: surfaces,
        direct_received_lm: direct_received,
        reflected_lm: reflected,
        absorbed_lm: absorbed,
        escaped_lm: escaped,
        escaped_from_lights_lm: lights_escaped,
        escaped_from_surfaces_lm: surfaces_escaped,
        balance_error_lm: error,
        balance_error_relative: if emitted > 0.0 {
            error.abs() / emitted
        } else {
            0.0
        },
    }
}

/// Fraction of each patch's outgoing (cosine-distributed) flux that leaves the scene
/// ([`escape::open_fractions`], rays shared in proportion to what each patch sends): 0 for
/// patches whose receivers are all enclosed and for patches that send nothing out (the fraction
/// is only ever multiplied by what they send). Its own ray pattern ([`ESCAPE_SALT`]), apart
/// from the one the balancing used, so this check does not grade an estimate against itself.
fn open_fractions(meshed: &Meshed, occ: &Occluder, solved: &Radiosity) -> Vec<f64> {
    let mesh = &meshed.mesh;
    let sent: Vec<f64> = (mesh.patches.iter().enumerate())
        .map(
            |(k, p)| match p.v.iter().all(|&v| solved.closed[v as usize]) {
                true => 0.0,
                false => p.area * luma(meshed.exitance[k] + solved.reflected[k]),
            },
        )
        .collect();
    escape::open_fractions(mesh, occ, &sent, ESCAPE_SALT)
}

/// Keeps the report's ray pattern apart from others drawn from patch indices.
const ESCAPE_SALT: u64 = 0x5E5C_A9E0_0000_0000;

/// What the summary says about a source, given the flux it put onto surfaces (lm) and the
/// closure factor applied to it (`bake::direct::closure`).
pub(crate) fn source_record(
    source: &DirectSource,
    scene: &Scene,
    received: f64,
    closure: f64,
) -> SourceRecord {
    let (kind, name, path) = match source {
        DirectSource::Punctual(l) => (
            match l.kind {
                LightKind::Point => SourceKind::Point,
                LightKind::Spot { .. } => SourceKind::Spot,
                LightKind::Directional => SourceKind::Directional,
            },
            l.name.clone(),
            l.source_path.clone(),
        ),
        DirectSource::Luminaire(s) => {
            (SourceKind::Luminaire, s.name.clone(), s.source_path.clone())
        }
        DirectSource::Profiled(s) => (
            SourceKind::ProfiledSurface,
            s.name.clone(),
            s.source_path.clone(),
        ),
    };
    let luminaire = match source {
        DirectSource::Luminaire(s) => {
            let profile = &scene.profiles[s.profile];
            // Lamp lumens (× the multiplier) and the light output ratio of the profile.
            Some(LuminaireRecord {
                profile: profile.name.clone(),
                multiplier: s.scale,
                rated_lamp_lm: profile.photometry.rated_lumens().map(|r| r * s.scale),
                light_output_ratio: profile.photometry.light_output_ratio(),
            })
        }
        _ => None,
    };
    SourceRecord {
        kind,
        name,
        source: path,
        emitted_lm: source.emitted_flux().unwrap_or(received),
        reached_surfaces_lm: received,
        closure,
        luminaire,
    }
}

/// A relative balance error above this is reported as a warning.
pub const WARN_BALANCE: f64 = 1e-3;

/// The warning for an energy balance error above [`WARN_BALANCE`] (or one that is not finite).
pub(crate) fn warning(e: &EnergyBalance) -> Option<String> {
    let r = e.balance_error_relative;
    if r.is_finite() && r <= WARN_BALANCE {
        return None;
    }
    let (lost, verb) = if e.balance_error_lm >= 0.0 {
        (e.balance_error_lm, "unaccounted for")
    } else {
        (-e.balance_error_lm, "too many")
    };
    Some(format!(
        "energy balance error {r:.1e} (above {WARN_BALANCE:.0e}): of {:.1} lm emitted, {:.1} lm \
         absorbed and {:.1} lm escaped leave {lost:.1} lm {verb}; illuminances may be off by \
         about that fraction (it collects the solver's residual, light lost where surfaces touch and \
         the error of the escaped-light estimate; --quality high reduces it)",
        e.emitted_lm, e.absorbed_lm, e.escaped_lm
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warns_above_a_thousandth_and_on_non_finite_errors() {
        let balance = |error: f64| EnergyBalance {
            emitted_lm: 1000.0,
            absorbed_lm: 1000.0 - error,
            balance_error_lm: error,
            balance_error_relative: error.abs() / 1000.0,
            ..EnergyBalance::default()
        };
        assert_eq!(warning(&balance(0.9)), None);
        let w = warning(&balance(100.0)).expect("10 % must warn");
        assert!(
            w.contains("1.0e-1") && w.contains("100.0 lm unaccounted for"),
            "{w}"
        );
        let w = warning(&balance(-2.0)).expect("0.2 % too much must warn");
        assert!(w.contains("2.0 lm too many"), "{w}");
        assert!(warning(&balance(f64::NAN)).is_some());
    }
}
