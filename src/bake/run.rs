//! What a bake measures about itself while it runs: wall-clock seconds per stage and shadow rays
//! per stage (the occluder counts rays across stages; they are read between them).

use crate::summary::{RaysByStage, StageSeconds};
use crate::visibility::Occluder;
use std::time::Instant;

/// The stages whose wall-clock time is recorded.
#[derive(Debug, Clone, Copy)]
pub enum Stage {
    Mesh,
    Direct,
    Links,
    Solve,
    Energy,
    Probes,
    Output,
    Lightmaps,
}

/// The stages whose shadow rays are counted.
#[derive(Debug, Clone, Copy)]
pub enum RayStage {
    Meshing,
    DirectAtReceivers,
    DirectIntoPatches,
    Links,
    Energy,
}

#[derive(Debug, Clone, Default)]
pub struct Run {
    pub seconds: StageSeconds,
    pub rays: RaysByStage,
    /// The occluder's ray count when rays were last attributed to a stage.
    counted: u64,
}

impl Run {
    /// Run `work`, adding its wall-clock time to `stage`.
    pub(crate) fn time<T>(&mut self, stage: Stage, work: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let out = work();
        let s = &mut self.seconds;
        *match stage {
            Stage::Mesh => &mut s.mesh,
            Stage::Direct => &mut s.direct,
            Stage::Links => &mut s.links,
            Stage::Solve => &mut s.solve,
            Stage::Energy => &mut s.energy,
            Stage::Probes => &mut s.probes,
            Stage::Output => &mut s.output,
            Stage::Lightmaps => &mut s.lightmaps,
        } += start.elapsed().as_secs_f64();
        out
    }

    /// Attribute the rays `occ` traced since the last call to `stage`.
    pub(crate) fn rays(&mut self, stage: RayStage, occ: &Occluder) {
        let now = occ.rays_traced();
        let r = &mut self.rays;
        *match stage {
            RayStage::Meshing => &mut r.meshing,
            RayStage::DirectAtReceivers => &mut r.direct_at_receivers,
            RayStage::DirectIntoPatches => &mut r.direct_into_patches,
            RayStage::Links => &mut r.links,
            RayStage::Energy => &mut r.energy,
        } += now - self.counted;
        self.counted = now;
    }
}
