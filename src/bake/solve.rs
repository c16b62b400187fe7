//! The solve stage: the patch-to-patch operator from the vertices' rows, balanced so a closed
//! room loses nothing per bounce, and GMRES on (I − ρG)B = ρE_direct.
//!
//! Input: the meshed scene, the [`Rows`] (consumed: the largest thing a bake holds, dropped here
//! once the solve is done; their tree is reduced to its skeleton while the solve runs and
//! rebuilt after), the direct flux into each patch from lights and luminaires, the open patches'
//! measured escape ([`open_fractions`]) and the solver's tolerance. Output: [`Radiosity`]: the reflected exitance of every patch and what
//! the vertices and the energy report need of the operator.

use super::links::{self, Rows};
use super::meshing::Meshed;
use crate::gmres::{self, SolveStats};
use crate::scene::luma;
use crate::transport::escape;
use crate::transport::operator::BalanceStats;
use crate::transport::{operator::PatchOperator, tree::PatchTree};
use crate::visibility::Occluder;
use glam::DVec3;
use rayon::prelude::*;

pub struct Radiosity {
    pub tree: PatchTree,
    pub rho: Vec<DVec3>,
    /// Per tree node, when some are: all its patches are black.
    pub dark: Option<Vec<bool>>,
    /// Reflected exitance per patch (lm/m², RGB).
    pub reflected: Vec<DVec3>,
    /// Direct irradiance of each patch's front (lx, RGB).
    pub direct_patch: Vec<DVec3>,
    /// Inter-reflected illuminance averaged over each patch and at each vertex (lx, RGB).
    pub indirect_patch: Vec<DVec3>,
    pub indirect_vertex: Vec<DVec3>,
    pub stats: SolveStats,
    pub balance: BalanceStats,
    /// Per vertex: the fraction of its hemisphere covered by back faces, and whether its row was
    /// normalised because it is enclosed (what the energy report needs of the rows).
    pub back: Vec<f32>,
    pub closed: Vec<bool>,
    pub counts: LinkCounts,
}

/// How many links the rows had.
#[derive(Clone, Copy)]
pub struct LinkCounts {
    pub links: usize,
    pub cluster_links: usize,
    pub closed_receivers: usize,
    pub gathered_receivers: usize,
}

impl Radiosity {
    /// Cuttle's first reflected flux (lm, photometric): Σ ρ × direct flux onto each patch.
    pub(crate) fn first_reflected_flux(&self, meshed: &Meshed) -> f64 {
        meshed
            .mesh
            .patches
            .iter()
            .enumerate()
            .map(|(i, p)| luma(self.rho[i] * self.direct_patch[i]) * p.area)
            .sum()
    }
}

/// `light_flux`: the direct flux of lights and luminaires into each patch's front (lm, RGB).
pub(crate) fn stage(
    meshed: &Meshed,
    rows: Rows,
    light_flux: Vec<DVec3>,
    open: &[f64],
    tolerance: f64,
) -> Radiosity {
    let mut one = stage_many(meshed, rows, vec![(meshed, light_flux)], open, tolerance);
    one.pop().expect("one right-hand side, one solution")
}

/// The share of each open patch's hemisphere through which light leaves the scene, for the
/// balancing (`PatchOperator::balance`): measured ([`escape::open_fractions`]) for patches with
/// a receiver that is not enclosed and that send light, rays shared by an estimate of what each
/// sends (emitted, and the first reflection of the direct flux); 0 elsewhere. Empty when every
/// receiver is enclosed.
pub(crate) fn open_fractions(
    meshed: &Meshed,
    occ: &Occluder,
    rows: &Rows,
    light_flux: &[DVec3],
) -> Vec<f64> {
    let mesh = &meshed.mesh;
    let closed = &rows.links.closed;
    if closed.iter().all(|&c| c) {
        return Vec::new();
    }
    let weight: Vec<f64> = (mesh.patches.iter().enumerate())
        .map(|(k, p)| {
            if p.v.iter().all(|&v| closed[v as usize])
                || links::black(&rows.rho, &meshed.exitance, k)
            {
                return 0.0;
            }
            let sent = p.area * luma(meshed.exitance[k]) + luma(rows.rho[k] * light_flux[k]);
            // Patches lit only by reflections are measured too, with the fewest rays.
            sent.max(p.area * 1e-12).max(f64::MIN_POSITIVE)
        })
        .collect();
    escape::open_fractions(mesh, occ, &weight, BALANCE_SALT)
}

/// Keeps the balancing's ray pattern apart from the energy report's.
const BALANCE_SALT: u64 = 0xBA1A_0000_0000_0000;

/// The solve for several right-hand sides on one operator: each `(lit, light_flux)` is the same
/// mesh lit by other sources (its emitting patches and its direct flux). The operator is built
/// from `rows` and balanced once, for `base` (which patches are black), so the solutions add:
/// the light of two groups of sources together is the sum of their solutions.
pub(crate) fn stage_many(
    base: &Meshed,
    rows: Rows,
    rhs: Vec<(&Meshed, Vec<DVec3>)>,
    open: &[f64],
    tolerance: f64,
) -> Vec<Radiosity> {
    let Rows {
        tree,
        rho,
        dark,
        mut links,
        ..
    } = rows;
    // The solve reads only the tree's skeleton: the rest is freed while the rows are held and
    // rebuilt from the skeleton once they are dropped (the same tree).
    let skeleton = tree.into_skeleton();
    let mesh = &base.mesh;
    let areas: Vec<f64> = mesh.patches.iter().map(|p| p.area).collect();
    let mut operator = PatchOperator::new(mesh, &skeleton, &links);
    let black = |p: usize| dark.is_some() && links::black(&rho, &base.exitance, p);
    let balance = operator.balance(40, 1e-5, &black, open);
    let mut solved = Vec::with_capacity(rhs.len());
    for (lit, light_flux) in rhs {
        // Direct irradiance of each patch: punctual lights exactly (solid angle), emitting
        // surfaces through the balanced operator (so a closed room receives exactly what they
        // emit).
        let from_emitters = match lit.lights.has_emitting_surfaces() {
            true => operator.apply(&lit.exitance),
            false => vec![DVec3::ZERO; mesh.patches.len()],
        };
        let direct_patch: Vec<DVec3> = (0..mesh.patches.len())
            .map(|i| light_flux[i] / areas[i] + from_emitters[i])
            .collect();
        // Not needed past here: two patch-sized vectors fewer while the solver runs.
        drop(from_emitters);
        drop(light_flux);
        let b: Vec<DVec3> = (0..mesh.patches.len())
            .map(|i| rho[i] * direct_patch[i])
            .collect();
        let apply = |x: gmres::Input, out: &mut [DVec3]| {
            operator.apply_fn(|p| x.get(p), out);
            out.par_iter_mut()
                .enumerate()
                .for_each(|(i, o)| *o = x.get(i) - rho[i] * *o);
        };
        let (reflected, stats) = gmres::gmres(apply, &b, &areas, tolerance, 2_000, 40);
        let indirect_patch = operator.apply(&reflected);
        let indirect_vertex = operator.gather_receivers(&reflected);
        solved.push((
            reflected,
            direct_patch,
            indirect_patch,
            indirect_vertex,
            stats,
        ));
    }
    drop(operator);
    // The rows are done with: keep what the energy report needs.
    let counts = LinkCounts {
        links: links.link_count(),
        cluster_links: links.far_links().filter(|l| l.is_cluster()).count(),
        closed_receivers: links.closed.iter().filter(|c| **c).count(),
        gathered_receivers: links.rows(),
    };
    let back = std::mem::take(&mut links.back);
    let closed = std::mem::take(&mut links.closed);
    drop(links);
    // The rows lived in the allocator's heap (chunks of 64 rows: blocks too small to be
    // mapped on their own): hand their pages back before the tree is rebuilt beside them.
    crate::heap::return_freed();
    // Every solution gets the tree back, rebuilt from the skeleton (the last takes it).
    let n = solved.len();
    let mut skeleton = Some(skeleton);
    let mut out = Vec::with_capacity(n);
    for (k, (reflected, direct_patch, indirect_patch, indirect_vertex, stats)) in
        solved.into_iter().enumerate()
    {
        let skeleton = match k + 1 == n {
            true => skeleton
                .take()
                .expect("the last solution takes the skeleton"),
            false => skeleton
                .clone()
                .expect("the skeleton is kept until the last"),
        };
        let tree = PatchTree::from_skeleton(skeleton, mesh);
        out.push(Radiosity {
            tree,
            rho: rho.clone(),
            dark: dark.clone(),
            reflected,
            direct_patch,
            indirect_patch,
            indirect_vertex,
            stats,
            balance,
            back: back.clone(),
            closed: closed.clone(),
            counts,
        });
    }
    out
}

/// The warning for a solve that stopped before reaching `tolerance` (`None` when it converged).
pub(crate) fn warning(stats: &SolveStats, tolerance: f64) -> Option<String> {
    (!stats.converged).then(|| {
        format!(
            "the solver stopped at {} iterations with relative residual {:.2e} (tolerance \
             {tolerance:.0e}): the inter-reflected light is not converged",
            stats.iterations, stats.relative_residual
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solve_that_stopped_early_is_warned_about() {
        let stopped = SolveStats {
            iterations: 2000,
            relative_residual: 3e-4,
            converged: false,
        };
        let w = warning(&stopped, 1e-7).expect("must warn");
        assert!(
            w.contains("2000 iterations") && w.contains("3.00e-4") && w.contains("1e-7"),
            "{w}"
        );
        let done = SolveStats {
            converged: true,
            ..stopped
        };
        assert_eq!(warning(&done, 1e-7), None);
    }
}
