//! Direct light at the receivers, computed at each receiver itself (never interpolated from
//! patches): lights and luminaires by the inverse-square cosine law with shadow rays (luminaires
//! split into sub-sources near their openings), emitting surfaces through the gather interface on
//! the tree of emitting patches.

use crate::direct::sources::DirectSource;
use crate::patches::PatchMesh;
use crate::progress::Progress;
use crate::transport::{
    gather::Gatherer,
    tree::{NodeField, PatchTree},
};
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// Direct illuminance (lx, RGB) at every receiver of `mesh`.
pub fn direct_at_receivers(
    sources: &[DirectSource],
    mesh: &PatchMesh,
    occ: &Occluder,
    emitter_tree: &PatchTree,
    exitance: &[DVec3],
    tau: f64,
    progress: &dyn Progress,
) -> Vec<DVec3> {
    let node_exitance = emitter_tree.node_field(exitance);
    let gatherer = Gatherer {
        mesh,
        tree: emitter_tree,
        occluder: occ,
        tau,
    };
    mesh.receivers
        .par_chunks(256)
        .flat_map_iter(|chunk| {
            let out: Vec<DVec3> = chunk
                .iter()
                .map(|r| direct_at(sources, occ, &gatherer, &node_exitance, r.point, r.normal))
                .collect();
            progress.advance(chunk.len() as u64);
            out
        })
        .collect()
}

/// Direct illuminance (lx, RGB) at point `p` with unit normal `n`.
pub fn direct_at(
    sources: &[DirectSource],
    occ: &Occluder,
    emitters: &Gatherer,
    node_exitance: &NodeField,
    p: DVec3,
    n: DVec3,
) -> DVec3 {
    let mut e = DVec3::ZERO;
    for source in sources {
        e += source.color() * source.illuminance(occ, p, n);
    }
    let mut links = Vec::new();
    emitters.links(p, n, &mut links);
    e + node_exitance.gather(&links)
}
