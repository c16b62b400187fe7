//! The probes stage: cubic illuminance at every probe of the bake.
//!
//! Input: the [`Solution`] and the probes (placed by `probes::place`). Output: one
//! [`ProbeResult`] per probe, in order. A probe is a receiver with six planes, the faces of its
//! cube: each face's direct illuminance comes from every source at the probe with shadow rays,
//! its indirect part is gathered from the radiosity solution over the patch hierarchy with
//! visibility (like a vertex; not Cuttle's single constant, which is reported beside it). The
//! faces share their sub-sources, intensities and shadow rays. The exact scalar and cylindrical
//! illuminance come from an integration over the sphere (not for working-plane probes, which
//! only need their upward face). Deterministic: see `solution::receivers::map`.

use crate::probes::{CubicIlluminance, FACES, Probe, ProbeOrigin, ProbeResult, metrics};
use crate::progress::Progress;
use crate::scene::luma;
use crate::solution::{Planes, Receiver, Receivers, Solution, receivers, sphere};

/// Directions sampled by the exact sphere integration: `SPHERE_RINGS` × 2·`SPHERE_RINGS` cells.
pub const SPHERE_RINGS: usize = 64;

/// Probes as receivers: each its cube's six faces, turned as the probe is.
struct Cubes<'a>(&'a [Probe]);

impl Receivers for Cubes<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }

    fn receiver(&self, i: usize) -> Receiver {
        let p = &self.0[i];
        Receiver {
            point: p.position,
            planes: Planes::of(&FACES.map(|face| p.world_from_probe * face)),
        }
    }
}

pub fn measure(solution: &Solution, probes: &[Probe], progress: &dyn Progress) -> Vec<ProbeResult> {
    if probes.is_empty() {
        return Vec::new();
    }
    progress.stage("probes", probes.len() as u64);
    let cuttle = solution.cuttle_indirect();
    receivers::map(&Cubes(probes), progress, |i, r| {
        one(solution, &probes[i], r, cuttle)
    })
}

/// Measure one probe (`r`: its cube as a receiver).
fn one(solution: &Solution, probe: &Probe, r: &Receiver, cuttle: f64) -> ProbeResult {
    let mut cubic = CubicIlluminance::default();
    for (k, light) in solution.light_at(r).iter().enumerate() {
        cubic.direct[k] = luma(light.direct);
        cubic.indirect[k] = luma(light.indirect);
        cubic.total[k] = cubic.direct[k] + cubic.indirect[k];
    }
    let mut m = metrics::from_faces(&cubic.total, probe.toward);
    if probe.origin != ProbeOrigin::WorkingPlane {
        let up = probe.world_from_probe * glam::DVec3::Y;
        let s = sphere::integrate(solution, probe.position, up, &[], SPHERE_RINGS);
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
