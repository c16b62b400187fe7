//! Visibility: shadow-ray queries against the scene's triangles, answered by `obvhs` BVHs that
//! are built once and shared by every stage.
//!
//! Input: every surface triangle of the scene (world space, m). Output: an [`Occluder`] answering
//! "is the segment between two points clear?", "does a ray escape the scene?", "what does a
//! ray hit first?" and, for a group of luminaires, "are all segments from these points to this
//! box provably clear, or provably blocked?" ([`Occluder::settle`]). Beside it, for searches
//! that are not rays, [`boxes::BoxIndex`]: which of some boxes meet a box.
//!
//! Skipping what a scene does not need: the planes that have the whole scene (every vertex,
//! light and luminaire opening) on their front side bound a convex hull — the room's shell. A
//! segment between two points inside that hull can never cross a shell face (it could only graze
//! it), so segments between inner points are traced against the other triangles only: the
//! furniture. An empty convex room (or a single plane) has no such triangles, and its segments
//! are clear without tracing. Rays that may leave the hull (escape tests, points outside) use all
//! triangles.
//!
//! Robustness: the BVHs work in f32 on coordinates re-centred on the scene's bounding box and
//! scaled to a fixed size, so a room far from the origin keeps its precision and the traversal's
//! built-in absolute epsilon means the same in every unit. Segment ends are pulled off their
//! surfaces by ε = 10⁻⁵ × the scene's diagonal (along the normals, towards each other), so a
//! scene in millimetres and one in kilometres behave alike. Single-sided triangles block light
//! from both sides. Answers do not depend on the BVHs' layout, so they are deterministic.

use crate::scene::Scene;
use glam::{DVec3, Vec3A};
use obvhs::{
    Boundable, BvhBuildParams,
    aabb::Aabb,
    cwbvh::CwBvh,
    cwbvh::builder::build_cwbvh,
    ray::{Ray, RayHit},
    triangle::Triangle,
};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

pub mod boxes;
mod hull;
mod settle;

/// The BVH works on the scene mapped to this diagonal. obvhs's wide-BVH traversal skips boxes
/// nearer than a fixed 10⁻⁴ along the ray; at this scale that is 10⁻⁸ of the scene, below f32
/// resolution, so short shadow rays near corners are not lost, whatever the scene's units.
const BVH_DIAGONAL: f64 = 1e4;

/// Rays traced, counted per worker thread: one shared atomic bounced its cache line between the
/// cores on every ray (millions per bake). The total does not depend on the thread count.
struct RayCount {
    shards: Vec<Shard>,
}

#[repr(align(128))]
#[derive(Default)]
struct Shard(AtomicU64);

impl Default for RayCount {
    fn default() -> Self {
        // One shard per rayon worker, and one for calls from outside the pool.
        let n = rayon::current_num_threads() + 1;
        RayCount {
            shards: (0..n).map(|_| Shard::default()).collect(),
        }
    }
}

impl RayCount {
    #[inline]
    fn add(&self) {
        let n = self.shards.len();
        let i = rayon::current_thread_index().map_or(n - 1, |i| i % (n - 1).max(1));
        self.shards[i].0.fetch_add(1, Ordering::Relaxed);
    }

    fn total(&self) -> u64 {
        self.shards
            .iter()
            .map(|s| s.0.load(Ordering::Relaxed))
            .sum()
    }
}

/// What blocks a segment, as [`Occluder::first_hit_near`] tells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Blocker {
    /// Something before the segment enters the given sphere.
    Before,
    /// The nearest blocker, a triangle (index as given to the constructor).
    At(usize),
}

/// A closest-hit answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub triangle: usize,
    pub distance: f64,
    pub normal: DVec3,
}

thread_local! {
    /// The tracer (its address) and the triangle (its index in BVH order) that blocked this
    /// thread's last blocked ray ([`Tracer::miss`]). A stale entry (another tracer at the same
    /// address) only costs one triangle test: a triangle that meets the ray blocks it.
    static LAST_BLOCKER: std::cell::Cell<(usize, u32)> =
        const { std::cell::Cell::new((0, u32::MAX)) };
}

/// A BVH over a set of triangles in the occluder's mapped coordinates.
#[derive(Default)]
struct Tracer {
    bvh: Option<CwBvh>,
    /// Triangles in BVH primitive order.
    triangles: Vec<Triangle>,
    /// For each of them, its index in the constructor's input.
    ids: Vec<u32>,
}

impl Tracer {
    fn new(tris: Vec<(u32, Triangle)>) -> Self {
        // Boxes padded by a millionth of the scene: a flat box (a wall) seen by a ray that starts
        // a hair away from it otherwise slips through the slab test in f32 and the ray leaks.
        let pad = (1e-6 * BVH_DIAGONAL) as f32;
        let padded: Vec<Padded> = tris.iter().map(|(_, t)| Padded { tri: *t, pad }).collect();
        let bvh = (!tris.is_empty()).then(|| {
            build_cwbvh(
                &padded,
                // The slower, higher-quality build: the BVH is built once and traced by every
                // shadow ray of the bake.
                BvhBuildParams::slow_build(),
                &mut Duration::default(),
            )
        });
        let order: Vec<usize> = bvh
            .as_ref()
            .map(|b| b.primitive_indices.iter().map(|&i| i as usize).collect())
            .unwrap_or_default();
        Tracer {
            bvh,
            triangles: order.iter().map(|&i| tris[i].1).collect(),
            ids: order.iter().map(|&i| tris[i].0).collect(),
        }
    }

    /// The nearest hit of `ray` (BVH units) by the test `hit` (a distance, infinite for none).
    fn nearest(&self, ray: Ray, hit: impl Fn(&Triangle, &Ray) -> f32) -> Option<RayHit> {
        let bvh = self.bvh.as_ref()?;
        let mut found = RayHit::none();
        (bvh.ray_traverse(ray, &mut found, |r, id| hit(&self.triangles[id], r))).then_some(found)
    }

    /// No triangle blocks `ray`. The triangle that blocked this thread's last blocked ray is
    /// tried first (a desk top hides a chair's seat from most luminaires, a seat its legs from
    /// most of the ceiling): it blocks only where the traversal would find a blocker too, so the
    /// answer is the same, sooner.
    fn miss(&self, ray: Ray) -> bool {
        let Some(bvh) = &self.bvh else {
            return true;
        };
        let me = self as *const Tracer as usize;
        let (owner, last) = LAST_BLOCKER.get();
        if owner == me
            && let Some(t) = self.triangles.get(last as usize)
            && intersect(t, &ray) < ray.tmax
        {
            return false;
        }
        let mut blocker = u32::MAX;
        let miss = bvh.ray_traverse_miss(ray, |r, id| {
            let t = intersect(&self.triangles[id], r);
            if t < r.tmax {
                blocker = id as u32;
            }
            t
        });
        if !miss {
            LAST_BLOCKER.set((me, blocker));
        }
        miss
    }
}

pub struct Occluder {
    /// The triangles not on the convex shell (every triangle when there is no shell): the only
    /// possible blockers between inner points.
    interior: Tracer,
    /// The triangles on the convex shell (none when there is none). Segments that leave the
    /// shell are traced against both: the scene's triangles are held once.
    on_shell: Tracer,
    /// The shell's planes (unit normal n, offset d: inside is n·x ≥ d).
    shell: Vec<(DVec3, f64)>,
    center: DVec3,
    /// World metres → BVH units (the scene is mapped to a diagonal of [`BVH_DIAGONAL`]).
    scale: f64,
    /// Offset that pulls segment ends off their surfaces (m).
    pub epsilon: f64,
    /// True when no segment between points inside the shell can be blocked (an empty convex
    /// enclosure or a single plane): such queries skip tracing.
    pub convex_empty: bool,
    /// The interior triangles' bounding box (world, m), padded: a segment between inner points
    /// whose own box misses it is clear without tracing (the floor and walls of a room whose
    /// only furniture hangs under its ceiling).
    interior_box: (DVec3, DVec3),
    /// Scene bounding-box diagonal (m).
    pub diagonal: f64,
    rays: RayCount,
}

/// Options for building the occluder.
#[derive(Debug, Clone, Copy, Default)]
pub struct OccluderOptions {
    /// Ignore the convex shell: trace every segment against every triangle (for tests of the
    /// tracing itself, and to measure what the shell saves).
    pub always_trace: bool,
}

impl Occluder {
    pub fn build(scene: &Scene, options: OccluderOptions) -> Self {
        let tris: Vec<[DVec3; 3]> = scene
            .surfaces
            .iter()
            .flat_map(|s| {
                s.triangles
                    .iter()
                    .map(|t| t.map(|v| s.positions[v as usize]))
            })
            .collect();
        let shell = if options.always_trace {
            None
        } else {
            shell_planes(scene, &tris)
        };
        Self::with_shell(&tris, shell)
    }

    /// An occluder over arbitrary world triangles (e.g. the refined patches, for closest-hit
    /// look-ups); zero-area triangles are left out. Hits report indices into `tris`.
    pub(crate) fn from_triangles(tris: &[[DVec3; 3]], convex_empty: bool) -> Self {
        let mut occ = Self::with_shell(tris, None);
        occ.convex_empty = convex_empty;
        occ
    }

    fn with_shell(tris: &[[DVec3; 3]], shell: Option<Vec<(DVec3, f64)>>) -> Self {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in tris.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if lo.x > hi.x {
            lo = DVec3::ZERO;
            hi = DVec3::ZERO;
        }
        let center = (lo + hi) * 0.5;
        let diagonal = (hi - lo).length();
        let scale = BVH_DIAGONAL / diagonal.max(1e-300);
        let tol = 1e-7 * diagonal.max(1e-12);
        let f = |p: DVec3| as_vec3a((p - center) * scale);
        let (mut on_shell_tris, mut interior) = (Vec::new(), Vec::new());
        let (mut box_lo, mut box_hi) =
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for (k, [a, b, c]) in tris.iter().enumerate() {
            let n = (*b - *a).cross(*c - *a);
            if n.length_squared() <= 0.0 {
                continue;
            }
            let t = (
                k as u32,
                Triangle {
                    v0: f(*a),
                    v1: f(*b),
                    v2: f(*c),
                },
            );
            let on_shell = shell.as_ref().is_some_and(|planes| {
                planes
                    .iter()
                    .any(|(m, d)| [a, b, c].iter().all(|p| (m.dot(**p) - d).abs() <= tol))
            });
            match on_shell {
                true => on_shell_tris.push(t),
                false => {
                    interior.push(t);
                    box_lo = box_lo.min(a.min(*b).min(*c));
                    box_hi = box_hi.max(a.max(*b).max(*c));
                }
            }
        }
        let shell_present = shell.is_some();
        // Padded well past the BVH's own box padding (10⁻⁶ of the scene) and f32 rounding.
        let pad = DVec3::splat(2e-6 * diagonal);
        let interior_box = (box_lo - pad, box_hi + pad);
        let interior = Tracer::new(interior);
        Occluder {
            convex_empty: shell_present && interior.bvh.is_none(),
            interior,
            interior_box,
            on_shell: Tracer::new(on_shell_tris),
            shell: shell.unwrap_or_default(),
            center,
            scale,
            epsilon: 1e-5 * diagonal.max(1e-9),
            diagonal,
            rays: RayCount::default(),
        }
    }

    /// True when `p` is inside (or on) the convex shell, so only interior triangles can block
    /// segments from it to another inner point.
    fn inside_shell(&self, p: DVec3) -> bool {
        let tol = 1e-7 * self.diagonal;
        !self.shell.is_empty() && self.shell.iter().all(|(n, d)| n.dot(p) - d >= -tol)
    }

    fn ray(&self, origin: DVec3, dir: DVec3, tmax: f64) -> Ray {
        let o = (origin - self.center) * self.scale;
        // obvhs's slab test misses with a zero direction component (an axis-aligned ray finds
        // nothing); a component of 1e-20 is zero for the distance and finite for the slabs.
        let dir = dir.map(|c| if c == 0.0 { 1e-20 } else { c });
        Ray::new(
            as_vec3a(o),
            as_vec3a(dir),
            0.0,
            if tmax.is_finite() {
                (tmax * self.scale) as f32
            } else {
                f32::INFINITY
            },
        )
    }

    /// The nearest triangle a ray from `origin` along the unit `dir` hits: its index (as given to
    /// the constructor), distance (m) and unit geometric normal (by its winding).
    pub(crate) fn closest(&self, origin: DVec3, dir: DVec3) -> Option<Hit> {
        let ray = self.ray(origin, dir, f64::INFINITY);
        self.rays.add();
        self.nearest_of(|t| t.nearest(ray, intersect))
    }

    /// The nearest triangle whose FRONT (counter-clockwise side) a ray from `origin` along the
    /// unit `dir` hits, back-facing triangles culled inside the traversal (as a glTF viewer
    /// culls the back faces of single-sided surfaces): index (as given to the constructor),
    /// distance (m) and unit geometric normal. The ray starts at `origin` itself, not pulled off
    /// anything, so of a front and a back triangle in one plane the front one is found.
    pub(crate) fn closest_front(&self, origin: DVec3, dir: DVec3) -> Option<Hit> {
        self.closest_facing(origin, dir, true)
    }

    /// [`Occluder::closest_front`] for the triangles whose BACK the ray meets (the front faces
    /// culled): the first back face along the ray.
    pub(crate) fn closest_back(&self, origin: DVec3, dir: DVec3) -> Option<Hit> {
        self.closest_facing(origin, dir, false)
    }

    fn closest_facing(&self, origin: DVec3, dir: DVec3, front: bool) -> Option<Hit> {
        let ray = self.ray(origin, dir, f64::INFINITY);
        self.rays.add();
        self.nearest_of(|t| t.nearest(ray, |tri, r| intersect_facing(tri, r, front)))
    }

    /// The nearer of the hits `find` reports in the interior and on the shell (the interior's
    /// on a tie), as a [`Hit`].
    fn nearest_of(&self, find: impl Fn(&Tracer) -> Option<RayHit>) -> Option<Hit> {
        let inner = find(&self.interior).map(|h| (h, &self.interior));
        let shell = find(&self.on_shell).map(|h| (h, &self.on_shell));
        let (hit, tracer) = match (inner, shell) {
            (Some(a), Some(b)) => match b.0.t < a.0.t {
                true => b,
                false => a,
            },
            (a, b) => a.or(b)?,
        };
        let t = &tracer.triangles[hit.primitive_id as usize];
        let n = (t.v1 - t.v0).cross(t.v2 - t.v0);
        Some(Hit {
            triangle: tracer.ids[hit.primitive_id as usize] as usize,
            distance: hit.t as f64 / self.scale,
            normal: n.as_dvec3().normalize_or_zero(),
        })
    }

    /// No triangle, in the interior or on the shell, blocks `ray`.
    fn miss_all(&self, ray: Ray) -> bool {
        self.interior.miss(ray) && self.on_shell.miss(ray)
    }

    /// The ends of the segment from `a` (surface normal `na`) to `b` (normal `nb`), each pulled
    /// off its surface by the epsilon toward the other end's side.
    fn pulled_ends(&self, a: DVec3, na: DVec3, b: DVec3, nb: DVec3) -> (DVec3, DVec3) {
        let d = b - a;
        let side_a = if na.dot(d) >= 0.0 { 1.0 } else { -1.0 };
        let side_b = if nb.dot(d) <= 0.0 { 1.0 } else { -1.0 };
        (
            a + na * (self.epsilon * side_a),
            b + nb * (self.epsilon * side_b),
        )
    }

    /// Number of rays traced so far.
    pub fn rays_traced(&self) -> u64 {
        self.rays.total()
    }

    /// Count `n` rays traced elsewhere (by another process of a distributed bake) as traced here.
    pub(crate) fn credit_rays(&self, n: u64) {
        let last = self.rays.shards.len() - 1;
        self.rays.shards[last].0.fetch_add(n, Ordering::Relaxed);
    }

    /// Is the segment from point `a` (surface normal `na`) to point `b` (normal `nb`) free of
    /// blockers? Either normal may be zero (a point in free space, e.g. a light).
    pub fn clear(&self, a: DVec3, na: DVec3, b: DVec3, nb: DVec3) -> bool {
        let (from, to) = self.pulled_ends(a, na, b, nb);
        // The pulled-off ends decide: a face on the shell looking out (the top of a fitting
        // flush with the ceiling) pulls its end outside, and then the shell must count.
        let inner = self.inside_shell(from) && self.inside_shell(to);
        if self.interior.bvh.is_none() && (inner || self.on_shell.bvh.is_none()) {
            return true;
        }
        let dir = to - from;
        let len = dir.length();
        if len <= self.epsilon {
            return true;
        }
        let (lo, hi) = self.interior_box;
        if inner && (from.max(to).cmplt(lo).any() || from.min(to).cmpgt(hi).any()) {
            return true; // nothing that could block it lies within its box
        }
        self.rays.add();
        let ray = self.ray(from, dir / len, len - self.epsilon);
        match inner {
            true => self.interior.miss(ray),
            false => self.miss_all(ray),
        }
    }

    /// The first triangle (index as given to the constructor) that blocks the segment from `a`
    /// (surface normal `na`) to `b` (normal `nb`), ends pulled off their surfaces as in
    /// [`Occluder::clear`]; `None` when it is clear.
    pub(crate) fn first_hit(&self, a: DVec3, na: DVec3, b: DVec3, nb: DVec3) -> Option<usize> {
        let (from, to) = self.pulled_ends(a, na, b, nb);
        let dir = to - from;
        let len = dir.length();
        if len <= self.epsilon {
            return None;
        }
        let ray = self.ray(from, dir / len, len - self.epsilon);
        self.rays.add();
        self.nearest_of(|t| t.nearest(ray, intersect))
            .map(|h| h.triangle)
    }

    /// [`Occluder::first_hit`]'s answer where only a blocker inside the sphere (`center`,
    /// `radius`) needs naming: one met before the segment enters the sphere is
    /// [`Blocker::Before`], found by an any-hit trace that stops at the first blocker, and only
    /// the rest of the segment is searched for its nearest hit. For a cluster's rays, where the
    /// cluster's own patches (all inside its sphere) do not count as blockers: most such rays
    /// are blocked by something else long before the cluster, and searching their whole length
    /// for the nearest hit cost more than any other kind of ray on the open-plan floors.
    /// Whenever `first_hit` names a triangle inside the sphere's bounds this names the same
    /// one; a triangle it names before the sphere is `Before` here.
    pub(crate) fn first_hit_near(
        &self,
        (a, na): (DVec3, DVec3),
        (b, nb): (DVec3, DVec3),
        center: DVec3,
        radius: f64,
    ) -> Option<Blocker> {
        let (from, to) = self.pulled_ends(a, na, b, nb);
        let dir = to - from;
        let len = dir.length();
        if len <= self.epsilon {
            return None;
        }
        let dir = dir / len;
        let tmax = len - self.epsilon;
        // Where the segment enters the sphere, less a margin far above the BVH's f32 rounding
        // (so no triangle inside the sphere can be met before `split`), and `tmax` when it
        // misses the sphere.
        let margin = 1e-6 * self.diagonal;
        let oc = from - center;
        let (half_b, c) = (dir.dot(oc), oc.length_squared() - radius * radius);
        let disc = half_b * half_b - c;
        let enter = if disc > 0.0 {
            -half_b - disc.sqrt()
        } else {
            tmax
        };
        let split = (enter - 2.0 * margin).min(tmax);
        if split <= 2.0 * margin {
            return self.first_hit(a, na, b, nb).map(Blocker::At);
        }
        self.rays.add();
        if !self.miss_all(self.ray(from, dir, split)) {
            return Some(Blocker::Before);
        }
        if split >= tmax {
            return None;
        }
        // The rest, overlapping the first part by a margin: a hit the first part's f32 bound
        // left out is found here.
        let mut rest = self.ray(from, dir, tmax);
        rest.tmin = ((split - margin) * self.scale) as f32;
        self.nearest_of(|t| t.nearest(rest, intersect))
            .map(|h| Blocker::At(h.triangle))
    }

    /// Does a ray from point `a` (surface normal `na`) in direction `dir` leave the scene?
    pub(crate) fn escapes(&self, a: DVec3, na: DVec3, dir: DVec3) -> bool {
        let side = if na.dot(dir) >= 0.0 { 1.0 } else { -1.0 };
        self.rays.add();
        self.miss_all(self.ray(
            a + na * (self.epsilon * side),
            dir.normalize(),
            f64::INFINITY,
        ))
    }
}

/// A point in the BVH's f32 coordinates (already mapped).
fn as_vec3a(p: DVec3) -> Vec3A {
    Vec3A::from(p.as_vec3())
}

/// A triangle whose bounding box is grown by `pad` on every side.
struct Padded {
    tri: Triangle,
    pad: f32,
}

impl Boundable for Padded {
    fn aabb(&self) -> Aabb {
        let b = self.tri.aabb();
        Aabb::new(
            b.min - Vec3A::splat(self.pad),
            b.max + Vec3A::splat(self.pad),
        )
    }
}

/// [`intersect`] for a triangle seen from its front only (`front`; ∞ when the ray meets its
/// back), or from its back only.
fn intersect_facing(t: &Triangle, ray: &Ray, front: bool) -> f32 {
    let n = (t.v1.as_dvec3() - t.v0.as_dvec3()).cross(t.v2.as_dvec3() - t.v0.as_dvec3());
    let towards = n.dot(ray.direction.as_dvec3());
    if (front && towards >= 0.0) || (!front && towards <= 0.0) {
        return f32::INFINITY;
    }
    intersect(t, ray)
}

/// Ray–triangle distance (∞ for a miss), Möller–Trumbore evaluated in f64 with barycentric
/// coordinates allowed a hair (10⁻⁷) outside [0, 1], so a ray through the edge shared by two
/// triangles cannot slip between them. For shadow rays a blocker grown by 10⁻⁷ of its size is
/// harmless; a crack is a light leak.
fn intersect(t: &Triangle, ray: &Ray) -> f32 {
    const SLACK: f64 = 1e-7;
    let (v0, v1, v2) = (t.v0.as_dvec3(), t.v1.as_dvec3(), t.v2.as_dvec3());
    let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
    let e1 = v1 - v0;
    let e2 = v2 - v0;
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det == 0.0 {
        return f32::INFINITY;
    }
    let inv = 1.0 / det;
    let tv = o - v0;
    let u = tv.dot(pv) * inv;
    if !(-SLACK..=1.0 + SLACK).contains(&u) {
        return f32::INFINITY;
    }
    let qv = tv.cross(e1);
    let w = d.dot(qv) * inv;
    if w < -SLACK || u + w > 1.0 + SLACK {
        return f32::INFINITY;
    }
    let dist = e2.dot(qv) * inv;
    if dist >= ray.tmin as f64 && dist <= ray.tmax as f64 {
        dist as f32
    } else {
        f32::INFINITY
    }
}

/// The planes of the scene's triangles that have every vertex, every point or spot light and
/// every luminaire opening on their front side (within tolerance): the faces of the convex shell.
/// `None` when the check would be too costly, or when a double-sided surface lies on one (it is
/// seen from outside too).
fn shell_planes(scene: &Scene, tris: &[[DVec3; 3]]) -> Option<Vec<(DVec3, f64)>> {
    let mut points: Vec<DVec3> = tris.iter().flatten().copied().collect();
    points.extend(
        scene
            .lights
            .iter()
            .filter(|l| l.kind != crate::scene::LightKind::Directional)
            .map(|l| l.position),
    );
    for l in &scene.luminaires {
        let o = l
            .opening
            .unwrap_or_else(|| scene.profiles[l.profile].photometry.opening());
        let (a, b) = (o.length.max(0.0) / 2.0, o.width.max(0.0) / 2.0);
        for (x, y) in [(-a, -b), (a, -b), (a, b), (-a, b)] {
            points.push(l.position + l.world_from_photometric * DVec3::new(x, y, 0.0));
        }
    }
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in &points {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let tol = 1e-7 * (hi - lo).length().max(1e-12);
    let double_sided: Vec<bool> = scene
        .surfaces
        .iter()
        .flat_map(|s| {
            std::iter::repeat_n(scene.materials[s.material].double_sided, s.triangles.len())
        })
        .collect();
    let mut candidates: Vec<(DVec3, f64, bool)> = Vec::new();
    for (k, [a, b, c]) in tris.iter().enumerate() {
        let n = (*b - *a).cross(*c - *a).normalize_or_zero();
        if n == DVec3::ZERO {
            continue;
        }
        let d = n.dot(*a);
        match candidates
            .iter_mut()
            .find(|(m, e, _)| m.dot(n) > 1.0 - 1e-12 && (e - d).abs() <= tol)
        {
            Some(c) => c.2 |= double_sided[k],
            None => candidates.push((n, d, double_sided[k])),
        }
        if candidates.len() * points.len() > 50_000_000 {
            return None;
        }
    }
    let shell: Vec<(DVec3, f64)> = candidates
        .into_iter()
        .filter(|(n, d, two_sided)| !two_sided && points.iter().all(|p| n.dot(*p) - d >= -tol))
        .map(|(n, d, _)| (n, d))
        .collect();
    Some(shell)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Surface};

    pub(super) fn quad_surface(corners: [DVec3; 4]) -> Surface {
        let n = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        Surface {
            node: 0,
            primitive: 0,
            source_path: String::new(),
            material: 0,
            positions: corners.to_vec(),
            normals: vec![n; 4],
            uv0: None,
            uv1: None,
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    pub(super) fn scene_with(surfaces: Vec<Surface>) -> Scene {
        Scene {
            surfaces,
            materials: vec![Material::default_material()],
            ..Default::default()
        }
    }

    #[test]
    fn blocker_between_points_is_seen_and_convexity_detected() {
        let floor = quad_surface([
            DVec3::new(-5.0, 0.0, 5.0),
            DVec3::new(5.0, 0.0, 5.0),
            DVec3::new(5.0, 0.0, -5.0),
            DVec3::new(-5.0, 0.0, -5.0),
        ]);
        let open = Occluder::build(&scene_with(vec![floor.clone()]), OccluderOptions::default());
        assert!(open.convex_empty, "a single plane cannot occlude itself");
        let blocker = quad_surface([
            DVec3::new(-1.0, 1.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, 1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
        ]);
        let occ = Occluder::build(
            &scene_with(vec![floor, blocker]),
            OccluderOptions::default(),
        );
        assert!(!occ.convex_empty);
        let light = DVec3::new(0.0, 2.0, 0.0);
        assert!(!occ.clear(DVec3::ZERO, DVec3::Y, light, DVec3::ZERO));
        assert!(occ.clear(DVec3::new(4.0, 0.0, 0.0), DVec3::Y, light, DVec3::ZERO));
        assert!(!occ.escapes(DVec3::ZERO, DVec3::Y, DVec3::Y));
        assert!(occ.escapes(DVec3::new(4.0, 0.0, 0.0), DVec3::Y, DVec3::Y));
    }

    #[test]
    fn the_last_blocker_tried_first_changes_no_answer() {
        // 400 small triangles scattered in a 10 m cube (a deterministic LCG), and segments from
        // 50 points to 40 targets each: every answer with the last blocker tried first must be
        // the traversal's alone (the cache emptied before asking again).
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut unit = move || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut point = || DVec3::new(unit(), unit(), unit()) * 10.0;
        let tris: Vec<[DVec3; 3]> = (0..400)
            .map(|_| {
                let c = point();
                let d = DVec3::new(1.0, 0.3, -0.5);
                [c, c + d, c + DVec3::new(-0.2, 0.9, 0.6)]
            })
            .collect();
        let occ = Occluder::from_triangles(&tris, false);
        // The answer with whatever the cache holds, checked against the traversal's alone (which
        // leaves its own blocker cached for the next question).
        let checked = |from: DVec3, to: DVec3| {
            let answer = occ.clear(from, DVec3::ZERO, to, DVec3::ZERO);
            LAST_BLOCKER.set((0, u32::MAX));
            assert_eq!(answer, occ.clear(from, DVec3::ZERO, to, DVec3::ZERO));
            answer
        };
        let (mut blocked, mut total) = (0, 0);
        for _ in 0..50 {
            let from = point();
            for _ in 0..40 {
                let to = point();
                let answer = checked(from, to);
                // The same blocker cached, a segment stopping halfway: only the traversal decides.
                checked(from, from + (to - from) * 0.5);
                blocked += usize::from(!answer);
                total += 1;
            }
        }
        // Both answers are common, so the cache was both tried and refused.
        assert!(
            blocked > total / 5 && blocked < total * 4 / 5,
            "{blocked} of {total}"
        );
    }

    #[test]
    fn first_hit_near_names_what_first_hit_names_inside_the_sphere() {
        // 600 small triangles in a 10 m cube; segments between random points; spheres around
        // random groups of triangles (their corners' box, as a tree node's). Wherever first_hit
        // names a triangle of the group, first_hit_near names the same; it says Before only
        // when first_hit's triangle lies outside the group, and nothing only when first_hit
        // finds nothing. At several scales, so the margins are checked where f32 is coarse.
        for scale in [1e-3, 1.0, 1e3] {
            let mut seed = 0x9e37_79b9_7f4a_7c15u64;
            let mut unit = move || {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                (seed >> 11) as f64 / (1u64 << 53) as f64
            };
            let tris: Vec<[DVec3; 3]> = (0..600)
                .map(|k| {
                    let c = DVec3::new((k % 10) as f64, ((k / 10) % 10) as f64, (k / 100) as f64)
                        + DVec3::new(unit(), unit(), unit()) * 0.5;
                    let d = DVec3::new(0.8, 0.2, -0.4);
                    [c, c + d, c + DVec3::new(-0.1, 0.7, 0.5)].map(|v| v * scale)
                })
                .collect();
            let occ = Occluder::from_triangles(&tris, false);
            let (mut inside, mut before, mut clear) = (0, 0, 0);
            for _ in 0..3000 {
                let first = (unit() * 590.0) as usize;
                let group = first..first + 1 + (unit() * 8.0) as usize;
                let (lo, hi) = tris[group.clone()]
                    .iter()
                    .flatten()
                    .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| {
                        (lo.min(*v), hi.max(*v))
                    });
                let (center, radius) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
                let from = DVec3::new(unit(), unit(), unit()) * 12.0 * scale;
                // Through the group's middle to just past it, so it is often what is hit.
                let from_far = (center - from).normalize_or_zero();
                let to = center + (from_far + DVec3::new(unit(), unit(), unit()) * 0.2) * radius;
                let full = occ.first_hit(from, DVec3::ZERO, to, DVec3::ZERO);
                let near =
                    occ.first_hit_near((from, DVec3::ZERO), (to, DVec3::ZERO), center, radius);
                match (full, near) {
                    (None, None) => clear += 1,
                    (Some(a), Some(Blocker::At(b))) => {
                        assert_eq!(a, b);
                        inside += usize::from(group.contains(&a));
                    }
                    (Some(a), Some(Blocker::Before)) => {
                        assert!(!group.contains(&a), "{a} is in the sphere");
                        before += 1;
                    }
                    other => panic!("first_hit and first_hit_near disagree: {other:?}"),
                }
            }
            // Every kind of answer was met.
            assert!(
                inside > 150 && before > 400 && clear > 400,
                "{inside} {before} {clear}"
            );
        }
    }

    #[test]
    fn far_from_origin_and_tiny_scales_keep_precision() {
        for &(offset, scale) in &[
            (DVec3::new(1e6, 0.0, -2e6), 1.0),
            (DVec3::ZERO, 1e-3),
            (DVec3::ZERO, 1e3),
        ] {
            let q = |x: f64, y: f64, z: f64| offset + DVec3::new(x, y, z) * scale;
            let floor = quad_surface([
                q(-5., 0., 5.),
                q(5., 0., 5.),
                q(5., 0., -5.),
                q(-5., 0., -5.),
            ]);
            let blocker = quad_surface([
                q(-1., 1., 1.),
                q(1., 1., 1.),
                q(1., 1., -1.),
                q(-1., 1., -1.),
            ]);
            let occ = Occluder::build(
                &scene_with(vec![floor, blocker]),
                OccluderOptions::default(),
            );
            assert!(!occ.clear(q(0., 0., 0.), DVec3::Y, q(0., 2., 0.), DVec3::ZERO));
            assert!(occ.clear(q(3., 0., 0.), DVec3::Y, q(0., 2., 0.), DVec3::ZERO));
            // A grazing segment along the floor stays clear of the floor itself.
            assert!(occ.clear(q(-4., 0., 4.), DVec3::Y, q(4., 0., -4.), DVec3::Y));
        }
    }

    #[test]
    fn closest_front_culls_back_faces_and_keeps_coincident_fronts() {
        // A double-sided plate at y = 1 as two coincident triangles, one facing +y, one −y, and
        // a floor at y = 0 facing +y.
        let up = [
            DVec3::new(-1.0, 1.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(0.0, 1.0, -1.0),
        ];
        let down = [up[0], up[2], up[1]];
        let floor = [
            DVec3::new(-5.0, 0.0, 5.0),
            DVec3::new(5.0, 0.0, 5.0),
            DVec3::new(0.0, 0.0, -5.0),
        ];
        for tris in [[up, down, floor], [down, up, floor]] {
            let occ = Occluder::from_triangles(&tris, false);
            let id = |t: [DVec3; 3]| tris.iter().position(|x| *x == t).unwrap();
            let from_above = occ
                .closest_front(DVec3::new(0.0, 3.0, 0.0), -DVec3::Y)
                .unwrap();
            assert_eq!(from_above.triangle, id(up));
            assert!((from_above.distance - 2.0).abs() < 1e-6);
            let from_below = occ
                .closest_front(DVec3::new(0.0, 0.5, 0.0), DVec3::Y)
                .unwrap();
            assert_eq!(from_below.triangle, id(down));
            assert!((from_below.distance - 0.5).abs() < 1e-6);
            // Under the floor, looking up: the floor's back is culled, the plate's underside seen.
            let under = occ
                .closest_front(DVec3::new(0.0, -1.0, 0.0), DVec3::Y)
                .unwrap();
            assert_eq!(under.triangle, id(down));
            // Looking down from under the floor: nothing faces the ray.
            assert!(
                occ.closest_front(DVec3::new(0.0, -1.0, 0.0), -DVec3::Y)
                    .is_none()
            );
        }
    }
}
