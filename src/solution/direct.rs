//! Direct light at any receiver, computed at the receiver itself (never interpolated from
//! patches): lights and luminaires by the inverse-square cosine law with shadow rays (luminaires
//! split into sub-sources near their openings, far groups of them proved seen or hidden, or
//! within the direct-light budget given two rays' answer: `direct::cut`),
//! Lambertian emitting surfaces through the [`Gatherer`] on the tree of emitting patches.
//!
//! Input: the direct sources, the emitting patches and their exitance. Output: a [`DirectLight`]
//! that the bake reads at the mesh vertices before the solve and the [`super::Solution`] keeps
//! for every receiver after it.

use super::receivers::Receiver;
use crate::direct::cut::{Cut, CutSettings};
use crate::direct::targets::AtPoint;
use crate::direct::{groups::Groups, sources::DirectSource};
use crate::patches::PatchMesh;
use crate::transport::{field::NodeField, gather::Gatherer, tree::PatchTree};
use crate::visibility::Occluder;
use glam::DVec3;

/// Every source of direct light of a bake.
pub struct DirectLight<'a> {
    /// Lights, luminaires and profiled emitting surfaces.
    pub sources: Vec<DirectSource<'a>>,
    /// The luminaires among `sources`, grouped for shared visibility.
    pub groups: Groups,
    /// The light cut over `groups` (`direct::cut`; fraction 0: every luminaire summed), with
    /// the direct-light budget (0: every group's visibility traced or proved).
    pub cut: Cut,
    /// The Lambertian emitting patches, and their exitance summarised on it.
    emitter_tree: PatchTree,
    emitters: NodeField,
    /// Far-field acceptance ratio for emitting surfaces.
    tau: f64,
}

impl<'a> DirectLight<'a> {
    /// `exitance`: the Lambertian exitance of every patch of `mesh` (lm/m², RGB; zero for patches
    /// that emit none); `cut`: the light cut's fraction and the direct-light budget.
    pub(crate) fn new(
        sources: Vec<DirectSource<'a>>,
        mesh: &PatchMesh,
        exitance: &[DVec3],
        tau: f64,
        cut: CutSettings,
    ) -> Self {
        let emitting: Vec<u32> = (0..mesh.patches.len() as u32)
            .filter(|&p| exitance[p as usize] != DVec3::ZERO)
            .collect();
        let emitter_tree = PatchTree::build(mesh, emitting);
        let emitters = NodeField::new(&emitter_tree, mesh, exitance);
        let groups = DirectSource::groups(&sources);
        DirectLight {
            cut: Cut::new(&sources, &groups, cut.fraction).with_budget(cut.budget),
            groups,
            sources,
            emitter_tree,
            emitters,
            tau,
        }
    }

    /// No source and no emitting surface.
    pub(crate) fn is_dark(&self) -> bool {
        self.sources.is_empty() && self.emitter_tree.is_empty()
    }

    /// Some surface emits Lambertian light into the patch field.
    pub(crate) fn has_emitting_surfaces(&self) -> bool {
        !self.emitter_tree.is_empty()
    }

    /// Direct illuminance (lx, RGB) on each plane of `r`, sharing what the sources can share
    /// between the planes (sub-sources, intensities, shadow rays).
    pub(crate) fn at(&self, mesh: &PatchMesh, occ: &Occluder, r: &Receiver) -> Vec<DVec3> {
        let (p, normals) = (r.point, r.planes.as_slice());
        // A sub-source's ray leaves `p` pulled off the first plane that faces it: a group's query
        // starts from every such point.
        let starts: Vec<DVec3> = normals.iter().map(|n| p + *n * occ.epsilon).collect();
        let settle = |lo: DVec3, hi: DVec3, _n: DVec3| occ.settle(&starts, lo, hi);
        let mut at = AtPoint::new(&self.sources, occ, p, normals);
        self.cut
            .run(&self.sources, &self.groups, p, normals, settle, &mut at);
        let mut e = at.rgb;
        let gatherer = Gatherer {
            mesh,
            tree: &self.emitter_tree,
            occluder: occ,
            tau: self.tau,
            split_leaves: true,
            fronts_only: true,
            dark: None,
            covered: None,
        };
        let mut links = Vec::new();
        for (e, n) in e.iter_mut().zip(normals) {
            links.clear();
            gatherer.links(p, *n, &mut links);
            *e += self.emitters.gather(links.iter().copied());
        }
        e
    }
}
