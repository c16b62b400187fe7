//! The links stage: every vertex's view of the patch hierarchy, gathered once and kept as the
//! rows the solver applies (see `transport::links`).
//!
//! Input: the meshed scene, the occluder, and the direct light (at each vertex, and as flux into
//! each patch: what estimates the light where vertices share gathers, `transport::sharing`).
//! Output: [`Rows`]: the tree of all patches, each patch's reflectance, the black nodes nobody
//! gathers from, and the vertices' rows.

use super::meshing::Meshed;
use crate::patches::PatchMesh;
use crate::scene::Scene;
use crate::settings::Settings;
use crate::transport::covered::CoveredField;
use crate::transport::sharing::{self, Part, Sharing};
use crate::transport::{gather::Gatherer, links::ReceiverLinks, tree::PatchTree};
use crate::visibility::Occluder;
use glam::DVec3;

pub struct Rows {
    pub tree: PatchTree,
    /// Linear RGB reflectance of each patch.
    pub rho: Vec<DVec3>,
    /// Per tree node, when some are: all its patches are [`black`].
    pub dark: Option<Vec<bool>>,
    pub links: ReceiverLinks,
    /// Rays [`PatchTree::mark_walled`] traced (counted with the links stage's).
    pub marking_rays: u64,
}

/// Patch `p` reflects nothing and emits nothing into the patch field: its exitance stays zero,
/// so nobody gathers from nodes of such patches alone (only what they cover counts).
pub(crate) fn black(rho: &[DVec3], exitance: &[DVec3], p: usize) -> bool {
    rho[p] == DVec3::ZERO && exitance[p] == DVec3::ZERO
}

/// What the links stage reads: the meshed scene, the occluder, and the direct light (at each
/// vertex, and as flux into each patch).
pub struct Inputs<'s> {
    pub scene: &'s Scene,
    pub settings: &'s Settings,
    /// Far-field acceptance ratio.
    pub tau: f64,
    pub meshed: &'s Meshed<'s>,
    pub occluder: &'s Occluder,
    pub vertex_direct: &'s [DVec3],
    pub light_flux: &'s [DVec3],
}

/// Every receiver's row.
pub(crate) fn stage(i: &Inputs) -> Rows {
    gathered(i, None).0
}

/// The rows of the receivers of `subset` (ascending, whole groups), as [`stage`] would make
/// them, to be assembled with the other parts' by [`assembled`] (a distributed bake's task).
/// Also the rays spent marking walls: every task and the merge trace them again (the same
/// rays), so a task's own rays are the rest.
pub(crate) fn part(i: &Inputs, subset: &[u32]) -> (Part, u64) {
    let (rows, part) = gathered(i, Some(subset));
    (part.expect("a part was asked for"), rows.marking_rays)
}

/// All rows (`subset` `None`), or the [`Part`] of `subset`.
fn gathered(i: &Inputs, subset: Option<&[u32]>) -> (Rows, Option<Part>) {
    let (tree, rho, dark, marking_rays) = setup(i.scene, i.settings, i.meshed, i.occluder);
    let mesh: &PatchMesh = &i.meshed.mesh;
    let covered = CoveredField::of(mesh);
    let covered = covered.as_ref().map(|c| c.gatherer(i.occluder, i.tau));
    let gatherer = Gatherer {
        mesh,
        tree: &tree,
        occluder: i.occluder,
        tau: i.tau,
        split_leaves: false,
        fronts_only: false,
        dark: dark.as_deref(),
        covered: covered.as_ref(),
    };
    let black = dark.as_ref().is_some_and(|d| d[0]);
    let first_bounce = match black {
        true => Vec::new(),
        false => first_bounce(i.meshed, &rho, i.light_flux),
    };
    let sharing = Sharing {
        tolerance: tolerance(i.settings),
        direct: i.vertex_direct,
        first_bounce: &first_bounce,
    };
    let (links, part) = match (black, subset) {
        // Black throughout: nothing is reflected, so there is nothing to gather.
        (true, None) => (
            ReceiverLinks::none(mesh.receivers.len(), tree.nodes.len()),
            None,
        ),
        (true, Some(s)) => (
            ReceiverLinks::empty(false),
            Some(Part::nothing(dark.is_some(), s)),
        ),
        (false, None) if sharing.tolerance > 0.0 => {
            (sharing::build(&gatherer, &mesh.receivers, &sharing), None)
        }
        (false, None) => (ReceiverLinks::build(&gatherer, &mesh.receivers), None),
        (false, Some(s)) => (
            ReceiverLinks::empty(false),
            Some(sharing::part(&gatherer, &mesh.receivers, s, &sharing)),
        ),
    };
    let rows = Rows {
        tree,
        rho,
        dark,
        links,
        marking_rays,
    };
    (rows, part)
}

/// The [`Rows`] of [`part`]s that together cover every receiver once: the same as [`stage`]'s.
pub(crate) fn assembled(
    scene: &Scene,
    settings: &Settings,
    meshed: &Meshed,
    occ: &Occluder,
    parts: Vec<Part>,
) -> Rows {
    let (tree, rho, dark, marking_rays) = setup(scene, settings, meshed, occ);
    let n = meshed.mesh.receivers.len();
    let links = match dark.as_ref().is_some_and(|d| d[0]) {
        true => ReceiverLinks::none(n, tree.nodes.len()),
        false => sharing::assemble(parts, n, tree.nodes.len()),
    };
    Rows {
        tree,
        rho,
        dark,
        links,
        marking_rays,
    }
}

/// Smallest space, in patch sizes, in which walls are looked for ([`PatchTree::mark_walled`]):
/// 2.95 m on the building sample at default quality, 2.0 m on the small open plan.
const WALL_ROOM: f64 = 3.5;

/// The tree of all patches (walls marked, `PatchTree::mark_walled`), each patch's reflectance,
/// and the black nodes (when skipped).
fn setup(
    scene: &Scene,
    settings: &Settings,
    meshed: &Meshed,
    occ: &Occluder,
) -> (PatchTree, Vec<DVec3>, Option<Vec<bool>>, u64) {
    let mesh: &PatchMesh = &meshed.mesh;
    let mut tree = PatchTree::build(mesh, (0..mesh.patches.len() as u32).collect());
    let rho: Vec<DVec3> = mesh
        .patches
        .iter()
        .map(|p| scene.materials[mesh.groups[p.group as usize].material].reflectance)
        .collect();
    let dark = match settings.gather_black {
        true => None,
        false => tree.nodes_where(|p| black(&rho, &meshed.exitance, p)),
    };
    // A scene that sends nothing on has no sources to wall off (and traces no ray).
    let before = occ.rays_traced();
    if !dark.as_ref().is_some_and(|d| d[0]) {
        tree.mark_walled(occ, WALL_ROOM * meshed.patch_size());
    }
    (tree, rho, dark, occ.rays_traced() - before)
}

fn tolerance(settings: &Settings) -> f64 {
    settings
        .receiver_tolerance
        .unwrap_or(settings.quality.receiver_tolerance())
}

/// First-bounce exitance of each patch (lm/m², RGB): emitted plus reflected direct light.
fn first_bounce(meshed: &Meshed, rho: &[DVec3], light_flux: &[DVec3]) -> Vec<DVec3> {
    let patches = &meshed.mesh.patches;
    (0..patches.len())
        .map(|p| meshed.exitance[p] + rho[p] * light_flux[p] / patches[p].area)
        .collect()
}
