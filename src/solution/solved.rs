//! A solved scene: what every receiver reads light from after the solve.
//!
//! Input: the parts the bake's stages made (patch mesh, occluder, direct light, the patch tree
//! with the solved reflected exitance, the vertices' light). Output: light at any receiver
//! ([`Solution::light_at`]): direct light from every source at the point, inter-reflected light
//! gathered over the patch hierarchy with visibility, through the same [`Gatherer`] as the
//! vertices' rows; what the vertices received (the solve's own receivers); and, in `sight`,
//! what a point sees along a direction.

use super::direct::DirectLight;
use super::receivers::{PlaneLight, Receiver};
use crate::patches::PatchMesh;
use crate::scene::{Scene, luma};
use crate::transport::covered::CoveredField;
use crate::transport::{
    field::NodeField,
    gather::{Gatherer, SharedRays},
    links,
    tree::PatchTree,
};
use crate::visibility::Occluder;
use glam::DVec3;
use std::sync::OnceLock;

/// The reflected exitance of every patch, and how receivers gather it.
pub struct Reflected {
    /// The tree of all patches.
    pub tree: PatchTree,
    /// Reflected exitance per patch (lm/m², RGB).
    pub exitance: Vec<DVec3>,
    /// Per tree node, when some are: all its patches are black (`Gatherer::dark`).
    pub dark: Option<Vec<bool>>,
    /// Far-field acceptance ratio of the gathers.
    pub tau: f64,
}

pub struct Solution<'a> {
    scene: &'a Scene,
    mesh: PatchMesh,
    occluder: Occluder,
    lights: DirectLight<'a>,
    reflected: Reflected,
    /// The reflected exitance summarised on the tree, built on first use: a bake without probes
    /// never reads it (its normal distributions, one per inner node, are large on large scenes).
    node_reflected: OnceLock<NodeField>,
    /// The covered parts' own mesh (`transport::covered`), built on the first gather.
    covered: OnceLock<Option<CoveredField>>,
    /// All emitted exitance per patch, profiled emitters included (for luminance).
    emitted: Vec<DVec3>,
    /// What each vertex of the mesh received.
    vertices: Vec<PlaneLight>,
    /// Cuttle's first reflected flux (lm, photometric): Σ ρ × direct flux onto each patch.
    first_reflected_flux: f64,
    /// Closest-hit index over the front patches and the patch of each of its triangles, built on
    /// first use (`sight`).
    pub(super) surface_index: OnceLock<(Occluder, Vec<usize>)>,
}

/// What a solved scene is made of.
pub struct Parts<'a> {
    pub scene: &'a Scene,
    pub mesh: PatchMesh,
    pub occluder: Occluder,
    pub lights: DirectLight<'a>,
    pub reflected: Reflected,
    pub emitted: Vec<DVec3>,
    pub vertices: Vec<PlaneLight>,
    pub first_reflected_flux: f64,
}

impl<'a> Solution<'a> {
    pub(crate) fn new(p: Parts<'a>) -> Self {
        Solution {
            scene: p.scene,
            mesh: p.mesh,
            occluder: p.occluder,
            lights: p.lights,
            reflected: p.reflected,
            node_reflected: OnceLock::new(),
            covered: OnceLock::new(),
            emitted: p.emitted,
            vertices: p.vertices,
            first_reflected_flux: p.first_reflected_flux,
            surface_index: OnceLock::new(),
        }
    }

    pub(crate) fn scene(&self) -> &'a Scene {
        self.scene
    }

    pub fn mesh(&self) -> &PatchMesh {
        &self.mesh
    }

    pub(crate) fn occluder(&self) -> &Occluder {
        &self.occluder
    }

    pub(crate) fn lights(&self) -> &DirectLight<'a> {
        &self.lights
    }

    /// What vertex `v` of the mesh received.
    pub fn vertex(&self, v: usize) -> PlaneLight {
        self.vertices[v]
    }

    /// All exitance patch `p` emits (lm/m², RGB).
    pub(crate) fn emitted(&self, p: usize) -> DVec3 {
        self.emitted[p]
    }

    /// Illuminance on each plane of `r`: direct and inter-reflected (the latter normalised like
    /// a vertex's row when the point is enclosed).
    pub fn light_at(&self, r: &Receiver) -> Vec<PlaneLight> {
        let direct = self.lights.at(&self.mesh, &self.occluder, r);
        let normals = r.planes.as_slice();
        // Planes through one point share their shadow rays; one plane alone has nothing to share.
        let mut shared = (normals.len() > 1).then(SharedRays::default);
        normals
            .iter()
            .zip(direct)
            .map(|(n, direct)| PlaneLight {
                direct,
                indirect: self.gather(r.point, *n, shared.as_mut()),
            })
            .collect()
    }

    /// The inter-reflected illuminance on the plane through `point` with unit normal `n`
    /// (lx, RGB): what [`Solution::light_at`] gathers, without the direct light.
    pub(crate) fn indirect_at(&self, point: DVec3, n: DVec3) -> DVec3 {
        self.gather(point, n, None)
    }

    fn gather(&self, point: DVec3, n: DVec3, shared: Option<&mut SharedRays>) -> DVec3 {
        let covered = self.covered.get_or_init(|| CoveredField::of(&self.mesh));
        let covered = covered
            .as_ref()
            .map(|c| c.gatherer(&self.occluder, self.reflected.tau));
        let gatherer = Gatherer {
            mesh: &self.mesh,
            tree: &self.reflected.tree,
            occluder: &self.occluder,
            tau: self.reflected.tau,
            split_leaves: false,
            fronts_only: false,
            dark: self.reflected.dark.as_deref(),
            covered: covered.as_ref(),
        };
        let field = self.node_reflected.get_or_init(|| {
            NodeField::new(&self.reflected.tree, &self.mesh, &self.reflected.exitance)
        });
        let row = links::gather_row_shared(&gatherer, point, n, shared);
        field.gather(row.links.iter().copied())
    }

    /// Cuttle's constant estimate of the indirect illuminance, FRF / (A·(1 − R)) (lx): the first
    /// reflected flux spread as in an integrating sphere of the room's area and mean reflectance.
    pub(crate) fn cuttle_indirect(&self) -> f64 {
        let (mut area, mut rho) = (0.0, 0.0);
        for p in &self.mesh.patches {
            let m = &self.scene.materials[self.mesh.groups[p.group as usize].material];
            area += p.area;
            rho += p.area * luma(m.reflectance);
        }
        if area <= 0.0 {
            return 0.0;
        }
        let r = rho / area;
        self.first_reflected_flux / (area * (1.0 - r))
    }
}
