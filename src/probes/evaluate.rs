//! Measuring the probes in a solved scene.
//!
//! Input: the [`Solution`] and the probes. Output: one [`ProbeResult`] per probe, in order.
//! Each face's direct illuminance comes from every source at the probe with shadow rays; its
//! indirect part is gathered from the radiosity solution over the patch hierarchy with
//! visibility (like a vertex: not Cuttle's single constant, which is reported beside it). The six
//! faces share their sub-sources, intensities and shadow rays (a ray toward one target is traced
//! once for all of them). The exact scalar and cylindrical illuminance come from
//! [`sphere::integrate`] (not for working-plane probes, which only need their upward face).
//! Probes are evaluated in parallel and collected in order: deterministic.

use super::{CubicIlluminance, FACES, Probe, ProbeOrigin, ProbeResult, metrics, sphere};
use crate::bake::Solution;
use crate::progress::Progress;
use crate::scene::luma;
use rayon::prelude::*;

/// Directions sampled by the exact sphere integration: `SPHERE_RINGS` × 2·`SPHERE_RINGS` cells.
pub const SPHERE_RINGS: usize = 64;

pub fn all(solution: &Solution, probes: &[Probe], progress: &dyn Progress) -> Vec<ProbeResult> {
    if probes.is_empty() {
        return Vec::new();
    }
    progress.stage("probes", probes.len() as u64);
    let cuttle = solution.cuttle_indirect();
    probes
        .par_iter()
        .map(|p| {
            let r = one(solution, p, cuttle);
            progress.advance(1);
            r
        })
        .collect()
}

/// Measure one probe.
pub fn one(solution: &Solution, probe: &Probe, cuttle: f64) -> ProbeResult {
    let mut cubic = CubicIlluminance::default();
    let normals = FACES.map(|face| probe.world_from_probe * face);
    let direct = solution.direct_at_faces(probe.position, &normals);
    let indirect = solution.indirect_at_faces(probe.position, &normals);
    for k in 0..normals.len() {
        cubic.direct[k] = luma(direct[k]);
        cubic.indirect[k] = luma(indirect[k]);
        cubic.total[k] = cubic.direct[k] + cubic.indirect[k];
    }
    let mut m = metrics::from_faces(&cubic.total, probe.toward);
    if probe.origin != ProbeOrigin::WorkingPlane {
        let s = sphere::integrate(
            solution,
            probe.position,
            probe.world_from_probe * glam::DVec3::Y,
            &[],
            SPHERE_RINGS,
        );
        m.exact_scalar = Some(s.scalar);
        m.exact_cylindrical = Some(s.cylindrical);
    }
    m.cuttle_indirect = Some(cuttle);
    ProbeResult {
        probe: probe.clone(),
        cubic,
        metrics: m,
    }
}
