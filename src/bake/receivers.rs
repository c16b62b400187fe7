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
    direct_at_faces(sources, occ, emitters, node_exitance, p, &[n])[0]
}

/// [`direct_at`] on several planes through `p` (a probe's faces), sharing what the sources can
/// share between them.
pub fn direct_at_faces(
    sources: &[DirectSource],
    occ: &Occluder,
    emitters: &Gatherer,
    node_exitance: &NodeField,
    p: DVec3,
    normals: &[DVec3],
) -> Vec<DVec3> {
    let mut e = vec![DVec3::ZERO; normals.len()];
    let mut each = vec![0.0; normals.len()];
    for source in sources {
        each.fill(0.0);
        source.illuminance_faces(occ, p, normals, &mut each);
        for (e, x) in e.iter_mut().zip(&each) {
            *e += source.color() * *x;
        }
    }
    let mut links = Vec::new();
    for (e, n) in e.iter_mut().zip(normals) {
        links.clear();
        emitters.links(p, *n, &mut links);
        *e += node_exitance.gather(&links);
    }
    e
}
