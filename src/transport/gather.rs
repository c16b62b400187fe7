//! Gathering at one receiver point: the list of sources it sees, with exact or far-field form
//! factors and sampled visibility. This is the one interface through which every receiver —
//! vertices now, lightmap texels and probe faces later — reads light from a patch field.
//!
//! Input: a point `p` with unit normal `n`, a [`PatchTree`], the [`Occluder`].
//! Output: links `(tree node, coefficient)` such that E(p) = Σ coefficient × (area-mean exitance of
//! the node's patches), and the total coverage (the fraction of the cosine-weighted hemisphere that
//! geometry covers, counting back faces, which reflect nothing).
//!
//! Traversal from the root: nodes entirely behind the receiver's plane are skipped; a leaf patch
//! gets Lambert's exact point-to-polygon form factor (clipped to the hemisphere); an inner node is
//! accepted as one source when its bounding radius over its distance is below `tau` and it lies
//! wholly above the receiver's plane. When its normal cone shows the receiver only front faces or
//! only back faces it gets the second-order expansion of `geom::farfield`; when it shows both
//! and is curved clutter (a chair across the room) it is a cluster whose intensity follows its
//! normal distribution (`geom::sh`), less what it hides from itself (`silhouette`; see
//! [`Link`]); other two-sided nodes are refined.
//! Visibility is the only sampled part: a fixed pattern of points on the patch (1, 4 or 16 by
//! its angular size) or two representative patches of a node, one shadow ray each (for a
//! cluster, its own patches do not block); a node whose two rays disagree is refined instead of
//! accepted, so shadow boundaries get leaf resolution. A one-sided node with a form factor below
//! 10⁻³ gets one ray (its visibility cannot move the sum by more than that). A far node that is
//! refined for its geometry (it crosses the receiver's plane, or shows both sides without being
//! clutter) is first tested with two rays: skipped whole when both are blocked, and when both get
//! through (and it is not clutter, whose own patches may hide each other) its patches are
//! gathered without rays of their own — of a node showing both sides, those facing the
//! receiver (its representatives faced it; the backs behind them are traced). Such a node whose
//! form factor is below 10⁻³ however its patches turn gets one ray, to its median patch. When
//! its representatives all lie below the receiver's plane (a node the plane cuts near its top),
//! the target is a point on one of its patches above the plane, found by a short search down its
//! subtree.
//! Direct light from emitting surfaces ([`Gatherer::split_leaves`]) samples nothing above the
//! leaves: a node's visibility is proved ([`crate::visibility::Occluder::settle`]: wholly seen,
//! its patches taken without rays; wholly hidden, skipped) or the node is refined, so a
//! penumbra is resolved by the leaves' adaptive splitting, not by where two rays fall.
//! A far node crossing the receiver's plane whose part above it cannot have a form factor of
//! 10⁻⁵ ([`HORIZON`]: a sliver of something far away on the horizon) is skipped.
//! Black nodes ([`Gatherer::dark`]: nothing reflected, nothing emitted into the field) are
//! visited like any other, for what they cover, but get no link.

mod sight;

use super::link::Link;
use super::tree::{NodeBounds, PatchTree};
use crate::geom::lambert;
use crate::patches::PatchMesh;
use crate::visibility::Occluder;
use glam::DVec3;
use sight::Sight;
use std::collections::HashMap;

/// What the two rays of a far ancestor ([`Gatherer::sight`]) said of a node's patches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Seen {
    /// Nothing: its patches' visibility is traced.
    No,
    /// The ancestor showed the receiver one side: all its patches are visible.
    All,
    /// The ancestor showed both sides: its patches facing the receiver are visible (its
    /// representatives faced it); the backs behind them are traced.
    Front,
}

impl Seen {
    /// Are patches facing the receiver (`front`) or turning their backs known to be visible?
    fn covers(self, front: bool) -> bool {
        match self {
            Seen::No => false,
            Seen::All => true,
            Seen::Front => front,
        }
    }
}

/// How much of a receiver's cosine-weighted hemisphere geometry covers (after visibility).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Coverage {
    /// All geometry, front and back faces.
    pub total: f64,
    /// Back faces of single-sided patches (they absorb what reaches them).
    pub back: f64,
    /// Front faces of black nodes ([`Gatherer::dark`]): covered, but linked to nothing.
    pub dark: f64,
}

#[derive(Clone, Copy)]
pub struct Gatherer<'a> {
    pub mesh: &'a PatchMesh,
    pub tree: &'a PatchTree,
    pub occluder: &'a Occluder,
    /// Far-field acceptance: bounding radius / distance below which a node is one source.
    pub tau: f64,
    /// Leaf patches' visible form factor by adaptive splitting ([`super::lit`]) instead of a
    /// fixed sample pattern, and inner nodes' visibility proved or refined, never sampled: for
    /// direct light from emitting surfaces, whose shadows are as sharp as a luminaire's (a panel
    /// seen past a chair's back), not for the smooth reflected field.
    pub split_leaves: bool,
    /// Only what faces the receiver is gathered: back faces and nodes turned away are skipped,
    /// not measured (direct light from single-sided emitters, which send nothing backward and
    /// whose coverage nobody reads: a ceiling beside a panel 1 cm below it traced 30 000 rays
    /// for the panel's back).
    pub fronts_only: bool,
    /// Per tree node, when some are: all its patches are black — they reflect nothing and emit
    /// nothing into the patch field, so their exitance is zero whatever the solve finds. Such a
    /// node gets no link, but what it covers is still measured as precisely as any other's,
    /// because an enclosed receiver's row is normalised by its total coverage: a coarser sample
    /// of what black nodes cover would scale the light of every other link in the row.
    pub dark: Option<&'a [bool]>,
    /// What covered parts cover ([`super::covered`]), measured where the patches leave the
    /// hemisphere short of closed; inside a slot it counts as back faces (absorbed), at a
    /// crack's mouth as more of what the receiver sees ([`absorbed_share`]).
    pub covered: Option<&'a Gatherer<'a>>,
}

/// What one gather collects: the links it found and the covered fractions.
struct Collected<'o> {
    links: &'o mut Vec<Link>,
    coverage: Coverage,
}

/// A node the traversal visits: its index, what an ancestor far node's two rays said of it
/// ([`Seen`]), its lowest height over the receiver's plane and its centre's distance (m).
#[derive(Clone, Copy)]
struct Visit {
    i: u32,
    seen: Seen,
    below: f64,
    dist: f64,
}

/// Shadow-ray answers shared by gathers at one point with different normals (the six faces of a
/// probe): a ray toward the same target from origins a hair apart (each pulled off along its
/// face's normal) gets the first face's answer instead of being traced again.
#[derive(Default)]
pub struct SharedRays(HashMap<(u32, u8), bool>);

/// Coverage from which a receiver counts as closed whatever else it sees
/// (`transport::links`): below it, what covered parts cover is measured.
pub const CLOSED: f64 = 0.999;

/// The share of what covered parts cover of a receiver's hemisphere (`covered`, cosine-weighted)
/// that counts as absorbed: none below [`MOUTH`], all from [`INSIDE`], linear between. A
/// receiver inside a slot sees its depths over most of its hemisphere, and they are dark; one
/// beside a crack's mouth (2 mm from a cube standing 1 mm over the floor sees its underside over
/// 5 %) sees the few millimetres next to the mouth, lit like the room, and its value stands for
/// a whole patch beside the crack: counting that as absorbed loses 0.6 % of a ρ = 0.9 room's
/// light (Sumpner, `tests/contacts.rs`).
pub(crate) fn absorbed_share(covered: f64) -> f64 {
    ((covered - MOUTH) / (INSIDE - MOUTH)).clamp(0.0, 1.0)
}

/// Covered share below which none is absorbed, and from which all is.
const MOUTH: f64 = 0.1;
const INSIDE: f64 = 0.5;

impl Gatherer<'_> {
    /// Is node `i` black ([`Gatherer::dark`])?
    fn is_dark(&self, i: u32) -> bool {
        self.dark.is_some_and(|d| d[i as usize])
    }

    /// Append the links seen from `p` (normal `n`) to `out`; return the covered fractions.
    pub(crate) fn links(&self, p: DVec3, n: DVec3, out: &mut Vec<Link>) -> Coverage {
        self.links_shared(p, n, out, None)
    }

    /// [`Gatherer::links`], reading and recording shadow-ray answers in `shared` when given.
    pub(crate) fn links_shared(
        &self,
        p: DVec3,
        n: DVec3,
        out: &mut Vec<Link>,
        shared: Option<&mut SharedRays>,
    ) -> Coverage {
        let mut coverage = self.patch_links(p, n, out, shared);
        if let Some(covered) = self.covered
            && coverage.total < CLOSED
        {
            let c = covered.links(p, n, &mut Vec::new()).total;
            let absorbed = c * absorbed_share(c);
            coverage.total += absorbed;
            coverage.back += absorbed;
        }
        coverage
    }

    /// [`Gatherer::links_shared`] over this gatherer's own tree only.
    fn patch_links(
        &self,
        p: DVec3,
        n: DVec3,
        out: &mut Vec<Link>,
        mut shared: Option<&mut SharedRays>,
    ) -> Coverage {
        let mut collected = Collected {
            links: out,
            coverage: Coverage::default(),
        };
        if self.tree.is_empty() {
            return collected.coverage;
        }
        // (node, what an ancestor far node's two rays said: see [`Seen`]).
        let mut stack = vec![(0u32, Seen::No)];
        while let Some((i, seen)) = stack.pop() {
            let node = &self.tree.bounds[i as usize];
            let (below, above) = node.height_range(p, n);
            if above <= 0.0 {
                continue; // wholly behind the receiver
            }
            let dist = (node.center - p).length();
            let v = Visit {
                i,
                seen,
                below,
                dist,
            };
            if node.is_leaf() {
                if let Some((weight, front)) = self.leaf_weight(p, n, v, &mut shared) {
                    self.add_leaf(i, weight, front, &mut collected);
                }
            } else if let Some(children) = self.inner(p, n, v, &mut shared, &mut collected) {
                push_children(&mut stack, node, children);
            }
        }
        collected.coverage
    }

    /// The visible form factor of leaf `v.i` from `p` (normal `n`) and whether its patch faces
    /// `p`; `None` when it adds nothing (its twin is counted instead, or nothing is; it does not
    /// rise above the receiver's plane; it is hidden).
    fn leaf_weight(
        &self,
        p: DVec3,
        n: DVec3,
        v: Visit,
        shared: &mut Option<&mut SharedRays>,
    ) -> Option<(f64, bool)> {
        let (i, seen) = (v.i, v.seen);
        let node = &self.tree.bounds[i as usize];
        let leaf = self.tree.leaf(node.start);
        let front = leaf.normal.dot(p - node.centroid) > 0.0;
        let patch_index = self.tree.order[node.start as usize] as usize;
        if !front && (self.fronts_only || self.mesh.patches[patch_index].double_sided) {
            return None; // its twin, facing this way, is counted instead (or nothing is)
        }
        let corners = leaf.corners;
        if !lambert::rises_above(p, n, &corners) {
            return None; // its form factor is zero
        }
        let weight = if self.split_leaves && !seen.covers(front) && !self.occluder.convex_empty {
            super::lit::visible_form_factor(self.occluder, p, n, corners, leaf.normal)
        } else {
            // Visibility before the form factor: most leaves far from the receiver turn
            // out hidden, and a hidden patch needs no form factor.
            let vis = if seen.covers(front) {
                1.0
            } else {
                let level = sample_level(node.radius, v.dist, self.tau);
                self.patch_visibility(p, n, i, leaf, level, shared)
            };
            if vis <= 0.0 {
                return None;
            }
            lambert::form_factor_rising(p, n, &corners) * vis
        };
        if weight <= 0.0 {
            return None;
        }
        Some((weight, front))
    }

    /// Leaf `i` seen with visible form factor `weight`: its front linked (a black one only
    /// covers), its back covered (it absorbs).
    fn add_leaf(&self, i: u32, weight: f64, front: bool, c: &mut Collected) {
        c.coverage.total += weight;
        if !front {
            c.coverage.back += weight;
        } else if self.is_dark(i) {
            c.coverage.dark += weight;
        } else {
            c.links.push(Link::plain(i, weight));
        }
    }

    /// What the traversal does with inner node `v.i`: `None` when it is skipped or accepted as
    /// one source (its link added to `c`), else what its children are visited knowing.
    fn inner(
        &self,
        p: DVec3,
        n: DVec3,
        v: Visit,
        shared: &mut Option<&mut SharedRays>,
        c: &mut Collected,
    ) -> Option<Seen> {
        let (i, below, dist) = (v.i, v.below, v.dist);
        let node = &self.tree.bounds[i as usize];
        if self.fronts_only && node.facing(p) == Some(false) {
            return None; // turned away: nothing of it is gathered
        }
        let mut seen = v.seen;
        if self.split_leaves && seen == Seen::No && !self.occluder.convex_empty {
            // Direct light: a node's visibility is proved or the node is refined, never
            // sampled (a penumbra's edge would be where two rays happen to fall).
            match self.proved(p, n, node) {
                Some(true) => seen = Seen::All,
                Some(false) => return None,
                None => return Some(Seen::No),
            }
        }
        if node.mixed {
            // Patches from both sides of a wall: what one part shows says nothing of the
            // other, so no ray settles it (a proof does: [`Gatherer::proved`]).
            let kept = if seen == Seen::All { seen } else { Seen::No };
            return Some(kept);
        }
        if node.radius >= self.tau * dist {
            return Some(seen); // too close
        }
        if below < 0.0 && node.horizon_bound(p, n, dist) < HORIZON {
            return None; // far, on the horizon: what rises above it is worth nothing
        }
        let facing = node.facing(p);
        if below < 0.0 || (facing.is_none() && !node.curved) {
            // Far, but not one source: it crosses the receiver's plane or shows both sides
            // without being clutter. Its patches are gathered one by one, unless its
            // representatives all say it is hidden; when they all say it is seen, its
            // patches (those facing the receiver, when it shows both sides) are gathered
            // without rays of their own.
            let settled = match seen {
                Seen::No => match self.sight(p, n, i, facing, shared) {
                    Sight::Hidden => return None,
                    Sight::Unknown => Seen::No,
                    Sight::Seen if facing.is_some() => Seen::All,
                    Sight::Seen => Seen::Front,
                },
                seen => seen, // an ancestor settled it already
            };
            return Some(settled);
        }
        self.source(p, n, Visit { seen, ..v }, facing, shared, c)
    }

    /// Far node `v.i` (one-sided, `facing`, or curved clutter) taken as one source when its rays
    /// agree: its link added to `c`, `None` returned; partly hidden, `Some(Seen::No)`: refined.
    fn source(
        &self,
        p: DVec3,
        n: DVec3,
        v: Visit,
        facing: Option<bool>,
        shared: &mut Option<&mut SharedRays>,
        c: &mut Collected,
    ) -> Option<Seen> {
        let (i, seen) = (v.i, v.seen);
        // A one-sided node's form factor decides how much its visibility is worth: below
        // SMALL_NODE one ray (to the patch at its area median) stands for it.
        let moments = self.tree.moments(i as usize);
        let f = facing.map(|_| moments.form_factor(p, n).abs());
        let vis = match f {
            _ if self.split_leaves && seen == Seen::All => 1.0, // proved
            Some(_) if seen.covers(facing == Some(true)) => 1.0,
            Some(f) if f < SMALL_NODE => self.ray_visibility(p, n, i, &[1], shared),
            Some(_) => self.ray_visibility(p, n, i, &[0, 2], shared),
            None => self.cluster_visibility(p, n, i, shared),
        };
        if vis > 0.0 && vis < 1.0 {
            // Partly hidden: a shadow boundary runs through the node. Refine rather than
            // guess the visible fraction from two rays.
            return Some(Seen::No);
        }
        match facing.zip(f) {
            Some((front, f)) => self.add_far(i, p, n, (front, f), vis, c),
            // Seen from both sides (clutter): one cluster, its normals to order 2.
            None => self.add_cluster(i, p, n, vis, c),
        }
        None
    }

    /// What is proved of the visibility of all of `node` from `p` (normal `n`): the segments
    /// to its box ([`Occluder::settle`]), the box moved off the plane of a flat node's own
    /// patches by the occluder's epsilon (as a shadow ray's end is) and drawn in from its rim
    /// by 10⁻⁴ of its distance (as [`super::lit`]'s edge samples are: off the edges a panel
    /// shares with the ceiling it is set in). Hidden is proved for the box grown by as much.
    fn proved(&self, p: DVec3, n: DVec3, node: &NodeBounds) -> Option<bool> {
        let eps = self.occluder.epsilon;
        let rim = 1e-4 * (node.center - p).length();
        let half = (node.half - DVec3::splat(rim)).max(DVec3::ZERO);
        let off = match node.cone_wide || node.curved {
            true => DVec3::ZERO,
            false => node.cone_axis * (2.0 * eps),
        };
        let c = node.center + off;
        let start = [p + n * eps];
        match self.occluder.settle(&start, c - half, c + half)? {
            true => Some(true),
            // Hidden only if the whole box, grown by the rim, is: the drawn-in box of a closed
            // emitter (a glowing box) lies inside it, behind its own faces.
            false => {
                let grown = node.half + DVec3::splat(rim + 2.0 * eps);
                let hidden = self
                    .occluder
                    .settle(&start, node.center - grown, node.center + grown);
                (hidden == Some(false)).then_some(false)
            }
        }
    }

    /// Node `i` accepted as one far-field source seen from `p` (`front`: its patches face `p`;
    /// `f`: its form factor) with visible fraction `vis`: second-order area moments and the
    /// first moment of exitance.
    fn add_far(
        &self,
        i: u32,
        p: DVec3,
        n: DVec3,
        (front, f): (bool, f64),
        vis: f64,
        c: &mut Collected,
    ) {
        let coverage = &mut c.coverage;
        let node = &self.tree.nodes[i as usize];
        if front {
            coverage.total += f * vis;
            if self.is_dark(i) {
                coverage.dark += f * vis;
                return;
            }
        } else {
            // Only single-sided backs cover anything (double-sided ones have twins).
            let share = node.single_sided_area / node.area.max(1e-300);
            coverage.total += f * vis * share;
            coverage.back += f * vis * share;
        }
        if front && vis > 0.0 && f > 0.0 {
            let g = self.tree.moments(i as usize).density_gradient(p, n) * vis;
            c.links.push(Link::far(i, f * vis, g, node.area));
        }
    }

    /// Node `i`, whose patches face `p` from both sides, accepted as one cluster: a point source
    /// at its centroid whose intensity follows its exitance-weighted normals to order 2, scaled
    /// by the share of its front faces it does not hide from itself (`silhouette`). It covers the
    /// area it shows toward `p`.
    fn add_cluster(&self, i: u32, p: DVec3, n: DVec3, vis: f64, collected: &mut Collected) {
        let coverage = &mut collected.coverage;
        let c = self.tree.bounds[i as usize].centroid;
        let d2 = (c - p).length_squared();
        let w = (p - c) / d2.sqrt();
        // What the cluster hides from itself is neither seen nor covers anything.
        let slot = self.tree.slot[i as usize] as usize;
        let seen = super::silhouette::share_toward(&self.tree.visible[slot], w);
        let k = (-n.dot(w)).max(0.0) * vis * seen / (std::f64::consts::PI * d2);
        let own = &self.tree.normal_sh[slot];
        let shown = crate::geom::sh::dist_projected(own, w).max(0.0);
        coverage.total += k * shown;
        if self.is_dark(i) {
            coverage.dark += k * shown;
            return;
        }
        if k > 0.0 {
            collected.links.push(Link::cluster_link(i, k, w));
        }
    }
}

/// Form factor below which a far node's visibility is one ray's answer (two rays, and
/// refinement where they disagree, above it). Such a node covers under 0.1 % of the receiver's
/// cosine-weighted hemisphere, so what a shadow edge through it could change is at most that.
const SMALL_NODE: f64 = 1e-3;

/// A far node crossing the receiver's plane whose part above it can have a form factor no larger
/// than this ([`NodeBounds::horizon_bound`]) is skipped: refining it would trace its patches
/// along the horizon one by one, and a receiver's tilted plane (a chair's) cuts a whole floor of
/// furniture. Kept small so that a large wall far away, cut by the plane, keeps nearly all its
/// light.
const HORIZON: f64 = 1e-5;

/// Push a node's children so the first (stored right after it in depth-first order) is visited
/// next: the traversal then walks the node array forwards, which the cache rewards.
fn push_children(stack: &mut Vec<(u32, Seen)>, node: &NodeBounds, seen: Seen) {
    stack.push((node.children[1], seen));
    stack.push((node.children[0], seen));
}

/// How finely to sample a patch's visibility: by its angular size radius/distance.
fn sample_level(radius: f64, dist: f64, tau: f64) -> u32 {
    if radius < tau * dist {
        0
    } else if radius < 4.0 * tau * dist {
        1
    } else {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::SceneBuilder;
    use crate::visibility::{Occluder, OccluderOptions};

    /// A quad in the plane z = `z` facing +z (towards the origin from z < 0).
    fn panel(x: (f64, f64), y: (f64, f64), z: f64) -> [DVec3; 4] {
        [
            DVec3::new(x.0, y.0, z),
            DVec3::new(x.1, y.0, z),
            DVec3::new(x.1, y.1, z),
            DVec3::new(x.0, y.1, z),
        ]
    }

    /// The built scene's occluder, its patches at size `h`, and their tree.
    fn world(b: SceneBuilder, h: f64) -> (Occluder, PatchMesh, PatchTree) {
        let scene = b.build();
        let occluder = Occluder::build(&scene, OccluderOptions::default());
        let mesh = crate::patches::build(&scene, h, None);
        let tree = PatchTree::build(&mesh, (0..mesh.patches.len() as u32).collect());
        (occluder, mesh, tree)
    }

    /// A gatherer over [`world`]'s parts at the default quality's τ.
    fn gatherer<'a>(
        occluder: &'a Occluder,
        mesh: &'a PatchMesh,
        tree: &'a PatchTree,
    ) -> Gatherer<'a> {
        Gatherer {
            mesh,
            tree,
            occluder,
            tau: 0.3,
            split_leaves: false,
            fronts_only: false,
            dark: None,
            covered: None,
        }
    }

    const SCREEN_Y: (f64, f64) = (0.0, 0.5);

    const WALL: [DVec3; 4] = [
        DVec3::new(-3.0, -1.0, -20.0),
        DVec3::new(3.0, -1.0, -20.0),
        DVec3::new(3.0, 2.0, -20.0),
        DVec3::new(-3.0, 2.0, -20.0),
    ];

    /// What stands 20 m away, across the receiver's plane (so it is never one source).
    #[derive(Clone, Copy, PartialEq)]
    enum Far {
        Nothing,
        /// A wall reaching 1 m below the plane and 2 m above it.
        Wall,
        /// A tessellated ball of radius 0.6 m centred on the plane: curved clutter.
        Ball,
    }

    /// The gather at the origin facing +Y (up) in a scene of a screen 2 m away (from x.0 to
    /// x.1, from the receiver's plane to 0.5 m above it, so it never crosses the plane and its
    /// own cost does not mix into the far object's) and `far`, all in 5 cm patches:
    /// coverage, rays traced, whether any link reads a patch of `far`, and what
    /// [`Gatherer::sight`] says of the nodes holding an eighth of `far`'s patches or more
    /// (each answer once). A small box
    /// behind and below the receiver (so it adds nothing) keeps the scene from being a convex
    /// empty enclosure, where nothing is traced.
    fn gather(screen: (f64, f64), far: Far) -> (f64, u64, bool, Vec<Sight>) {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.quad("screen", panel(screen, SCREEN_Y, -2.0), grey);
        match far {
            Far::Nothing => {}
            Far::Wall => b.quad("wall", WALL, grey),
            Far::Ball => {
                let centre = DVec3::new(0.0, 0.0, -20.0);
                b.ball("ball", centre, 0.6, (12, 16), grey);
            }
        }
        let behind = DVec3::new(0.0, -2.0, 5.0);
        b.axis_box("box", behind, behind + 0.5, false, grey);
        let (occluder, mesh, tree) = world(b, 0.05);
        let gatherer = gatherer(&occluder, &mesh, &tree);
        let mut links = Vec::new();
        let coverage = gatherer.links(DVec3::ZERO, DVec3::Y, &mut links);
        let rays = occluder.rays_traced();
        let is_far = |k: u32| mesh.patches[tree.order[k as usize] as usize].group == 1;
        let reads_far = far != Far::Nothing
            && links.iter().any(|l| {
                let node = &tree.bounds[l.node as usize];
                (node.start..node.end).any(is_far)
            });
        // The nodes that hold an eighth of `far` or more (a node's reps may lie below the
        // receiver's plane, leaving its parts to be settled).
        let total = (0..mesh.patches.len() as u32)
            .filter(|&k| is_far(k))
            .count() as u32;
        let mut sights: Vec<Sight> = (0..tree.nodes.len() as u32)
            .filter(|&i| {
                let node = &tree.bounds[i as usize];
                8 * (node.end - node.start) >= total && (node.start..node.end).all(is_far)
            })
            .map(|i| {
                let facing = tree.bounds[i as usize].facing(DVec3::ZERO);
                gatherer.sight(DVec3::ZERO, DVec3::Y, i, facing, &mut None)
            })
            .collect();
        sights.sort_by_key(|s| *s as u8);
        sights.dedup();
        (coverage.total, rays, reads_far, sights)
    }

    /// Exact form factor from the origin (normal +Y) of the screen's part above y = 0 (Lambert's
    /// formula clips to the hemisphere).
    fn screen_exact(x: (f64, f64)) -> f64 {
        lambert::form_factor(DVec3::ZERO, DVec3::Y, &panel(x, SCREEN_Y, -2.0))
    }

    /// Tilted receivers in an empty 60 × 45 × 3 m hall (a closed box: coverage exactly 1 from
    /// anywhere inside, and nothing hidden, the worst case for [`HORIZON`]). Their planes cut
    /// the far walls, floor and ceiling along the horizon, where the rule skips nodes; their
    /// coverage must stay within 10⁻³ of 1 (the rule and the far-field expansion together).
    #[test]
    fn tilted_receivers_in_a_long_hall_see_all_of_it() {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.axis_box("hall", DVec3::ZERO, DVec3::new(60.0, 3.0, 45.0), true, grey);
        let (occluder, mesh, tree) = world(b, 0.5);
        let gatherer = gatherer(&occluder, &mesh, &tree);
        let mut worst: f64 = 0.0;
        for (p, tilt, turn) in [
            (DVec3::new(5.0, 1.0, 5.0), 30.0f64, 40.0f64),
            (DVec3::new(5.0, 1.0, 5.0), 80.0, 40.0),
            (DVec3::new(30.0, 0.7, 20.0), 60.0, 10.0),
            (DVec3::new(55.0, 2.5, 40.0), 89.0, 200.0),
            (DVec3::new(1.0, 1.5, 22.0), 45.0, 0.0),
        ] {
            let (tilt, turn) = (tilt.to_radians(), turn.to_radians());
            let n = DVec3::new(tilt.sin() * turn.cos(), tilt.cos(), tilt.sin() * turn.sin());
            let mut links = Vec::new();
            let c = gatherer.links(p, n, &mut links);
            worst = worst.max((c.total - 1.0).abs());
        }
        eprintln!("oracle: hall-coverage measured {worst:.3e}");
        assert!(worst < 1e-3, "coverage off by {worst}");
    }

    #[test]
    fn far_node_across_the_receiver_plane_is_gathered_when_seen() {
        let beside = (2.0, 3.0);
        let (coverage, rays, wall, sight) = gather(beside, Far::Wall);
        let want = lambert::form_factor(DVec3::ZERO, DVec3::Y, &WALL) + screen_exact(beside);
        assert!(wall);
        assert!(sight.contains(&Sight::Seen) && !sight.contains(&Sight::Hidden));
        assert!((coverage / want - 1.0).abs() < 0.02, "{coverage} vs {want}");
        // Seen by both its representatives, the wall's patches need no rays of their own, not
        // one per patch along the receiver's plane, which cuts it.
        let (_, rays_screen, _, _) = gather(beside, Far::Nothing);
        assert!(
            rays <= rays_screen + 40,
            "{rays} vs {rays_screen} without the wall"
        );
    }

    #[test]
    fn far_node_across_the_receiver_plane_is_skipped_when_hidden() {
        let across = (-0.5, 0.5);
        let (coverage, rays, wall, sight) = gather(across, Far::Wall);
        assert!(!wall, "a hidden wall's patches were linked");
        assert!(sight.contains(&Sight::Hidden) && !sight.contains(&Sight::Seen));
        let want = screen_exact(across);
        assert!((coverage / want - 1.0).abs() < 0.02, "{coverage} vs {want}");
        // Deciding that the wall is hidden takes a few rays per far node, not one per patch
        // along the plane.
        let (_, rays_screen, _, _) = gather(across, Far::Nothing);
        assert!(
            rays <= rays_screen + 40,
            "{rays} vs {rays_screen} without the wall"
        );
    }

    /// The small far nodes of a panel 12 m away (x from −0.6 to 0.6 m, from 2 m below the
    /// receiver's plane to 0.15 m above it) that cross the plane with all three representatives
    /// below it, as seen from the origin facing +Y, with a screen hiding the panel or not: what
    /// [`Gatherer::sight`] says of each, and the rays it traced for them.
    fn small_crossing_sights(screened: bool) -> (Vec<Sight>, u64) {
        let mut b = SceneBuilder::new();
        let grey = b.material("grey", 0.5);
        b.quad("panel", panel((-0.6, 0.6), (-2.0, 0.15), -12.0), grey);
        if screened {
            b.quad("screen", panel((-1.0, 1.0), (-0.5, 0.5), -2.0), grey);
        }
        let behind = DVec3::new(0.0, -2.0, 5.0);
        b.axis_box("box", behind, behind + 0.5, false, grey);
        let (occluder, mesh, tree) = world(b, 0.05);
        let gatherer = gatherer(&occluder, &mesh, &tree);
        let (p, n) = (DVec3::ZERO, DVec3::Y);
        let mut sights = Vec::new();
        let rays_before = occluder.rays_traced();
        for i in 0..tree.nodes.len() as u32 {
            let node = &tree.bounds[i as usize];
            let on_panel = (node.start..node.end)
                .all(|k| mesh.patches[tree.order[k as usize] as usize].group == 0);
            let (below, above) = node.height_range(p, n);
            let area = tree.nodes[i as usize].area;
            let near = (node.center - p).length() - node.radius;
            let small = area < SMALL_NODE * std::f64::consts::PI * near * near;
            let reps_below = (0..3).all(|k| n.dot(tree.rep(i as usize, k).0 - p) <= 0.0);
            if on_panel && !node.is_leaf() && small && below < 0.0 && above > 0.0 && reps_below {
                sights.push(gatherer.sight(p, n, i, node.facing(p), &mut None));
            }
        }
        (sights, occluder.rays_traced() - rays_before)
    }

    #[test]
    fn small_node_across_the_plane_is_settled_by_one_ray_above_it() {
        // Nodes with every representative below the plane: one ray to a patch of theirs above
        // it settles them, as it settles a small node whose median patch is above it (rather
        // than refining them and tracing their patches one by one).
        let (open, rays) = small_crossing_sights(false);
        assert!(open.len() >= 4, "{} such nodes", open.len());
        assert!(open.iter().all(|s| *s == Sight::Seen), "{open:?}");
        assert!(
            rays <= open.len() as u64,
            "{rays} rays for {} nodes",
            open.len()
        );
        let (screened, _) = small_crossing_sights(true);
        assert!(screened.len() >= 4, "{} such nodes", screened.len());
        assert!(screened.iter().all(|s| *s == Sight::Hidden), "{screened:?}");
    }

    #[test]
    fn far_curved_clutter_across_the_receiver_plane_is_skipped_when_hidden() {
        // A ball hidden behind a screen: its own patches do not count as blockers, so its
        // representatives (on either side of it) settle it whole.
        let (_, _, ball, sight) = gather((-0.5, 0.5), Far::Ball);
        assert!(!ball, "a hidden ball's patches were linked");
        assert!(sight.contains(&Sight::Hidden) && !sight.contains(&Sight::Seen));
        // Seen, curved clutter is never taken as seen whole: its own patches may hide some of
        // the others, which rays that ignore them cannot tell. (Parts of it may be settled as
        // hidden: behind its own front, as seen from the receiver.)
        let (_, _, ball, sight) = gather((2.0, 3.0), Far::Ball);
        assert!(ball);
        assert!(!sight.contains(&Sight::Seen), "{sight:?}");
    }

    #[test]
    fn no_vertex_of_a_smooth_column_sees_more_than_its_hemisphere() {
        // A closed 4 × 3 × 4 m room and a 48-sided column (radius 0.2 m, smooth normals) from
        // floor to ceiling. The patch size splits the column's vertical edges, so vertices sit
        // on the ridges between facets, inside the facets above and below them: such a vertex's
        // shading normal differs from those facets' normals by rounding only. The form factors
        // of all it sees sum to its coverage, which no point can have above 1 (the
        // cosine-weighted hemisphere); in a closed room it is 1 but for sampled visibility.
        // Unless facets through the receiver count as edge-on, a vertex in the facet above it
        // sees the whole hemisphere in it and takes much of its light from its own column.
        let mut b = SceneBuilder::new();
        let white = b.material("white", 0.5);
        b.axis_box("room", DVec3::ZERO, DVec3::new(4.0, 3.0, 4.0), true, white);
        let mut column = crate::fixtures::openplan::shapes::Mesh::new();
        let (foot, top) = (DVec3::new(2.0, 0.0, 2.0), DVec3::new(2.0, 3.0, 2.0));
        column.frustum(foot, top, 0.2, 0.2, 48, (false, false));
        b.surface(
            "column",
            column.positions,
            column.normals,
            column.triangles,
            white,
        );
        let (occ, mesh, tree) = world(b, 0.25);
        let g = gatherer(&occ, &mesh, &tree);
        let group = mesh
            .groups
            .iter()
            .position(|g| g.surface == 6)
            .expect("the column");
        let receivers = mesh.groups[group].receivers.clone();
        assert!(
            receivers.len() > 48 * 4,
            "{} column vertices",
            receivers.len()
        );
        // Least coverage away from the floor and ceiling (where the column meets them, sampled
        // visibility of the patches it touches loses a little), most anywhere.
        let mut worst: (f64, f64) = (f64::INFINITY, 0.0);
        for r in &mesh.receivers[receivers] {
            let mut links = Vec::new();
            let c = g.links(r.point, r.normal, &mut links);
            if (0.3..2.7).contains(&r.position.y) {
                worst.0 = worst.0.min(c.total);
            }
            worst.1 = worst.1.max(c.total);
        }
        assert!(
            worst.1 <= 1.02 && worst.0 >= 0.95,
            "column vertices' coverage from {} to {}",
            worst.0,
            worst.1
        );
    }
}
