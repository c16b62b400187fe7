//! Direct light at the receivers, computed at each receiver itself (never interpolated from
//! patches): lights and luminaires by the inverse-square cosine law with shadow rays (luminaires
//! split into sub-sources near their openings), emitting surfaces through the gather interface on
//! the tree of emitting patches.

use crate::direct::{groups::Groups, sources::DirectSource};
use crate::patches::PatchMesh;
use crate::progress::Progress;
use crate::transport::{field::NodeField, gather::Gatherer, tree::PatchTree};
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

/// The direct sources and the luminaires among them grouped for shared visibility.
#[derive(Clone, Copy)]
pub struct Lights<'s, 'a> {
    pub sources: &'s [DirectSource<'a>],
    pub groups: &'s Groups,
}

/// Direct illuminance (lx, RGB) at every receiver of `mesh`.
pub fn direct_at_receivers(
    lights: Lights,
    mesh: &PatchMesh,
    occ: &Occluder,
    emitter_tree: &PatchTree,
    exitance: &[DVec3],
    tau: f64,
    progress: &dyn Progress,
) -> Vec<DVec3> {
    let node_exitance = NodeField::new(emitter_tree, mesh, exitance);
    let gatherer = Gatherer {
        mesh,
        tree: emitter_tree,
        occluder: occ,
        tau,
        dark: None,
    };
    mesh.receivers
        .par_chunks(256)
        .flat_map_iter(|chunk| {
            let out: Vec<DVec3> = chunk
                .iter()
                .map(|r| {
                    let normals = [r.normal];
                    direct_at_faces(lights, occ, &gatherer, &node_exitance, r.point, &normals)[0]
                })
                .collect();
            progress.advance(chunk.len() as u64);
            out
        })
        .collect()
}

/// Direct illuminance (lx, RGB) at `p` on planes with the unit `normals` (one for a vertex, six
/// for a probe), sharing what the sources can share between them.
pub fn direct_at_faces(
    lights: Lights,
    occ: &Occluder,
    emitters: &Gatherer,
    node_exitance: &NodeField,
    p: DVec3,
    normals: &[DVec3],
) -> Vec<DVec3> {
    let mut e = vec![DVec3::ZERO; normals.len()];
    let mut each = vec![0.0; normals.len()];
    let clear = |q: DVec3, n: DVec3| occ.clear(p, n, q, DVec3::ZERO);
    lights.groups.visit(p, normals, clear, |k, known| {
        let source = &lights.sources[k];
        each.fill(0.0);
        source.illuminance_faces(occ, p, normals, &mut each, known);
        for (e, x) in e.iter_mut().zip(&each) {
            *e += source.color() * *x;
        }
    });
    let mut links = Vec::new();
    for (e, n) in e.iter_mut().zip(normals) {
        links.clear();
        emitters.links(p, *n, &mut links);
        *e += node_exitance.gather(&links);
    }
    e
}
