//! Meshing: the scene's surfaces refined into patches, and the receivers at their vertices.
//!
//! Input: a [`Scene`] and the patch size `h` (m). Output: a [`PatchMesh`]:
//! - `groups`: one per (surface, side). Double-sided materials get a `Back` group: the same
//!   positions with reversed winding and flipped normals, its own patches and receivers.
//! - `patches`: triangles no longer than about `h` on a side (see [`refine`]), each owned by one
//!   group, with area, unit geometric normal (the side's front) and vertex receivers.
//! - `receivers`: one per refined vertex and side. A receiver is where the values users see are
//!   computed (vertex colours, `_ILLUMINANCE`); the solver also uses receivers as the quadrature
//!   points of its patches (a patch's irradiance is the mean of its three receivers').
//!
//! Invariants: patches have area > 0; every patch's vertices are receivers of the same group;
//! receiver normals have unit length and face the side's front; `Vertex::point` lies on the
//! surface, nudged a hair (10⁻⁴ of the longest edge around it) into the adjacent patches so that a receiver at a room corner
//! sees the neighbouring wall as the limit from inside the face, not edge-on (further on a
//! contact's outline, and out from under a cover too small to cut along: [`under`]).

pub mod adapt;
pub mod refine;
mod under;

use crate::contacts::{Contacts, cut};
use crate::scene::Scene;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// Which face of a surface a baked mesh carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum Side {
    Front,
    /// The back face of a double-sided material, written as an extra primitive with reversed
    /// winding so viewers show each face its own light.
    Back,
}

#[derive(Debug, Clone)]
pub struct Patch {
    /// Indices of its vertices in `PatchMesh::receivers`, counter-clockwise seen from the front.
    pub v: [u32; 3],
    pub group: u32,
    pub area: f64,
    pub normal: DVec3,
    /// The surface is double-sided: this patch has a coincident twin facing the other way, which
    /// receives and sends what reaches or leaves this patch's back. Its own back is never seen.
    pub double_sided: bool,
}

impl Patch {
    pub(crate) fn corners(&self, receivers: &[Vertex]) -> [DVec3; 3] {
        self.v.map(|i| receivers[i as usize].position)
    }
}

#[derive(Debug, Clone, Copy)]
/// A vertex of the patch mesh on one side of its surface: a receiver, where the values users see
/// are computed.
pub struct Vertex {
    /// The vertex position (m, world).
    pub position: DVec3,
    /// Unit normal of the receiving side.
    pub normal: DVec3,
    /// Where illuminance is evaluated: `position` nudged into the adjacent patches.
    pub point: DVec3,
    pub group: u32,
}

/// One side of one scene surface.
#[derive(Debug, Clone)]
pub struct Group {
    pub surface: usize,
    pub side: Side,
    pub material: usize,
    /// Ranges into `PatchMesh::receivers` and `PatchMesh::patches`.
    pub receivers: std::ops::Range<usize>,
    pub patches: std::ops::Range<usize>,
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    /// Area of this side (m², its patches': what is not covered).
    pub area: f64,
    /// The part of this side another surface covers (see [`crate::contacts`]): written to the
    /// output with no light, never a patch or a receiver.
    pub covered: Option<CoveredPart>,
}

/// Triangles of one side that another surface covers, with vertices of their own.
#[derive(Debug, Clone, Default)]
pub struct CoveredPart {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
}

impl CoveredPart {
    /// The triangles `tris` of a mesh, with only the vertices they use.
    fn of(
        positions: &[DVec3],
        normals: &[DVec3],
        uv0: &Option<Vec<DVec2>>,
        uv1: &Option<Vec<DVec2>>,
        tris: &[[u32; 3]],
    ) -> Option<Self> {
        if tris.is_empty() {
            return None;
        }
        let (positions, normals, uv0, uv1, triangles, _) =
            compact(positions, normals, uv0.clone(), uv1.clone(), tris);
        Some(CoveredPart {
            positions,
            normals,
            uv0,
            uv1,
            triangles,
        })
    }

    /// Area (m²).
    pub(crate) fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let p = t.map(|v| self.positions[v as usize]);
                (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0
            })
            .sum()
    }
}

#[derive(Debug, Clone, Default)]
pub struct PatchMesh {
    pub groups: Vec<Group>,
    pub patches: Vec<Patch>,
    pub receivers: Vec<Vertex>,
    /// The patch size used (m).
    pub patch_size: f64,
    /// Per patch, the zone of the air in front of it (`transport::zones`); empty: one zone.
    pub zone: Vec<u32>,
}

/// Refine every surface of `scene` into patches of size ≤ `h` (m), then, with `adapt`, split
/// them further where direct light needs it (see [`adapt`]). No contacts: see [`build_cut`].
pub fn build(scene: &Scene, h: f64, adapt: Option<&adapt::Adapt>) -> PatchMesh {
    build_cut(scene, h, adapt, &Contacts::none())
}

/// [`build`], with each surface first cut along the outlines of what covers it; covered parts
/// become the groups' [`CoveredPart`]s, not patches.
pub(crate) fn build_cut(
    scene: &Scene,
    h: f64,
    adapt: Option<&adapt::Adapt>,
    contacts: &Contacts,
) -> PatchMesh {
    let mut mesh = PatchMesh {
        patch_size: h,
        ..Default::default()
    };
    // Surfaces are refined independently (in parallel), then added in surface order, so the
    // mesh does not depend on the thread count.
    let refined: Vec<Option<SurfacePatches>> = scene
        .surfaces
        .par_iter()
        .enumerate()
        .map(|(s, surface)| refine_surface(scene, surface, h, adapt, contacts, s))
        .collect();
    for (s, r) in refined.into_iter().enumerate() {
        let Some(mut r) = r else { continue };
        let material = scene.surfaces[s].material;
        for (k, &side) in r.sides.iter().enumerate() {
            let mut covered = std::mem::take(&mut r.covered[k]);
            if let (Side::Back, Some(c)) = (side, covered.as_mut()) {
                // The back's covered part faces the other way, like its patches.
                c.triangles.iter_mut().for_each(|t| t.swap(1, 2));
                c.normals.iter_mut().for_each(|n| *n = -*n);
            }
            let outline = std::mem::take(&mut r.outline[k]);
            let sign = if side == Side::Front { 1.0 } else { -1.0 };
            let tris: Vec<[u32; 3]> = r.open[k]
                .iter()
                .map(|&i| r.triangles[i as usize])
                .map(|t| {
                    if side == Side::Front {
                        t
                    } else {
                        [t[0], t[2], t[1]]
                    }
                })
                .collect();
            // With some triangles covered, the side keeps only the vertices it uses.
            let part;
            let (positions, normals, uv0, uv1, tris, outline) = if tris.len() < r.triangles.len() {
                let (p, n, u0, u1, t, order) = compact(
                    &r.positions,
                    &r.normals,
                    r.uv0.clone(),
                    r.uv1.clone(),
                    &tris,
                );
                let o: Vec<Option<f64>> = order
                    .iter()
                    .map(|&i| outline.get(i).copied().flatten())
                    .collect();
                part = (p, n, t, o);
                (&part.0, &part.1, u0, u1, &part.2, part.3.as_slice())
            } else {
                (
                    &r.positions,
                    &r.normals,
                    r.uv0.clone(),
                    r.uv1.clone(),
                    &tris,
                    outline.as_slice(),
                )
            };
            let shading: Vec<DVec3> = normals.iter().map(|n| *n * sign).collect();
            add_group(
                &mut mesh,
                GroupInput {
                    surface: s,
                    side,
                    material,
                    positions,
                    shading_normals: &shading,
                    triangles: tris,
                    uv0,
                    uv1,
                    h,
                    double_sided: r.sides.len() == 2,
                    covered,
                    outline,
                    under: under::covers(scene, contacts, s, side == Side::Back),
                },
            );
        }
    }
    mesh
}

/// One surface refined (and adapted), before its sides become patch groups.
struct SurfacePatches {
    sides: &'static [Side],
    /// Per side: the triangles it receives on (indices into `triangles`), and its covered part.
    open: Vec<Vec<u32>>,
    covered: Vec<Option<CoveredPart>>,
    /// Per side, per vertex: the gap of the cover whose outline it lies on (m), if any.
    outline: Vec<Vec<Option<f64>>>,
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    uv0: Option<Vec<DVec2>>,
    uv1: Option<Vec<DVec2>>,
    triangles: Vec<[u32; 3]>,
}

/// Refine one surface (`s`) to patch size `h`, then adapt it; `None` when nothing is left.
/// The surface is first cut along the outlines of what covers it; every refined triangle keeps
/// which sides of it are covered, and a side's covered triangles become its [`CoveredPart`].
fn refine_surface(
    scene: &Scene,
    surface: &crate::scene::Surface,
    h: f64,
    adapt: Option<&adapt::Adapt>,
    contacts: &Contacts,
    s: usize,
) -> Option<SurfacePatches> {
    let cut = contacts.cut(s);
    let mut m = refined_mesh(surface, cut, h)?;
    let sides: &'static [Side] = if scene.materials[surface.material].double_sided {
        &[Side::Front, Side::Back]
    } else {
        &[Side::Front]
    };
    if let Some(a) = adapt {
        let signs: Vec<f64> = sides
            .iter()
            .map(|s| if *s == Side::Front { 1.0 } else { -1.0 })
            .collect();
        adapt::refine(&mut m, &signs, a);
    }
    let mut open = Vec::with_capacity(sides.len());
    let mut covered = Vec::with_capacity(sides.len());
    let mut outline = Vec::with_capacity(sides.len());
    for k in 0..sides.len() {
        let Some(c) = cut else {
            // Nothing covers the surface: every triangle receives, no receiver is on an outline.
            open.push((0..m.triangles.len() as u32).collect());
            covered.push(None);
            outline.push(Vec::new());
            continue;
        };
        let (mine, part, gap_at) = side_of(&m, c, [cut::FRONT, cut::BACK][k]);
        covered.push(part);
        open.push(mine);
        outline.push(gap_at);
    }
    Some(SurfacePatches {
        sides,
        open,
        covered,
        outline,
        positions: m.positions,
        normals: m.normals,
        uv0: m.uv0,
        uv1: m.uv1,
        triangles: m.triangles,
    })
}

/// `surface` (or its `cut` along its contacts, when it has one) refined to patch size `h`, its
/// normals and texture coordinates interpolated and unused vertices dropped; each triangle
/// tagged with the cut triangle it came from (no tags when uncut). `None` when nothing is left.
fn refined_mesh(
    surface: &crate::scene::Surface,
    cut: Option<&cut::CutSurface>,
    h: f64,
) -> Option<adapt::SurfaceMesh> {
    let (positions, in_normals, in_uv0, in_uv1, in_triangles) = match cut {
        None => (
            &surface.positions,
            &surface.normals,
            &surface.uv0,
            &surface.uv1,
            &surface.triangles,
        ),
        Some(c) => (&c.positions, &c.normals, &c.uv0, &c.uv1, &c.triangles),
    };
    let refined = refine::refine(positions, in_triangles, h);
    if refined.triangles.is_empty() {
        return None;
    }
    let normals: Vec<DVec3> = refined
        .origin
        .iter()
        .map(|b| b.apply(in_normals).normalize_or_zero())
        .collect();
    let interp = |uv: &Option<Vec<DVec2>>| {
        uv.as_ref().map(|d| {
            refined
                .origin
                .iter()
                .map(|b| b.apply(d))
                .collect::<Vec<_>>()
        })
    };
    let (uv0, uv1) = (interp(in_uv0), interp(in_uv1));
    let (positions, normals, uv0, uv1, triangles, _) =
        compact(&refined.positions, &normals, uv0, uv1, &refined.triangles);
    Some(adapt::SurfaceMesh {
        positions,
        normals,
        uv0,
        uv1,
        triangles,
        tags: match cut {
            Some(_) => refined.parent,
            None => Vec::new(),
        },
    })
}

/// The side `bit` of cut mesh `m` (tagged with `c`'s triangles): the triangles it receives on,
/// its covered part, and per vertex the gap of the cover whose outline it lies on (a receiver
/// shared with covered triangles), if any.
fn side_of(
    m: &adapt::SurfaceMesh,
    c: &cut::CutSurface,
    bit: u8,
) -> (Vec<u32>, Option<CoveredPart>, Vec<Option<f64>>) {
    let (mut mine, mut theirs) = (Vec::new(), Vec::new());
    let mut gap_at: Vec<Option<f64>> = vec![None; m.positions.len()];
    let mut used = vec![false; m.positions.len()];
    for (i, t) in m.triangles.iter().enumerate() {
        let parent = m.tags[i] as usize;
        if c.covered[parent] & bit != 0 {
            theirs.push(*t);
            for &v in t {
                let w = &mut gap_at[v as usize];
                *w = Some(w.unwrap_or(0.0).max(c.gap[parent]));
            }
        } else {
            mine.push(i as u32);
            for &v in t {
                used[v as usize] = true;
            }
        }
    }
    // Receivers shared with covered triangles lie on an outline.
    for (w, u) in gap_at.iter_mut().zip(&used) {
        if !u {
            *w = None;
        }
    }
    let part = CoveredPart::of(&m.positions, &m.normals, &m.uv0, &m.uv1, &theirs);
    (mine, part, gap_at)
}

type Compacted = (
    Vec<DVec3>,
    Vec<DVec3>,
    Option<Vec<DVec2>>,
    Option<Vec<DVec2>>,
    Vec<[u32; 3]>,
    Vec<usize>,
);

/// Drop vertices no triangle uses (from zero-area input triangles or unused input vertices);
/// the last item is each kept vertex's old index.
fn compact(
    positions: &[DVec3],
    normals: &[DVec3],
    uv0: Option<Vec<DVec2>>,
    uv1: Option<Vec<DVec2>>,
    triangles: &[[u32; 3]],
) -> Compacted {
    let mut map = vec![u32::MAX; positions.len()];
    let mut order = Vec::new();
    let triangles = triangles
        .iter()
        .map(|t| {
            t.map(|v| {
                if map[v as usize] == u32::MAX {
                    map[v as usize] = order.len() as u32;
                    order.push(v as usize);
                }
                map[v as usize]
            })
        })
        .collect();
    let pick = |d: &[DVec3]| order.iter().map(|&i| d[i]).collect::<Vec<_>>();
    let pick_uv =
        |d: Option<Vec<DVec2>>| d.map(|d| order.iter().map(|&i| d[i]).collect::<Vec<_>>());
    (
        pick(positions),
        pick(normals),
        pick_uv(uv0),
        pick_uv(uv1),
        triangles,
        order,
    )
}

struct GroupInput<'a> {
    surface: usize,
    side: Side,
    material: usize,
    positions: &'a [DVec3],
    shading_normals: &'a [DVec3],
    triangles: &'a [[u32; 3]],
    uv0: Option<Vec<DVec2>>,
    uv1: Option<Vec<DVec2>>,
    h: f64,
    double_sided: bool,
    covered: Option<CoveredPart>,
    /// Per vertex (or empty): the gap of the contact whose outline it lies on (m).
    outline: &'a [Option<f64>],
    /// The side's covers too small to cut along ([`under`]).
    under: under::Covers,
}

/// Per vertex: Σ over the triangles around it of the unit direction from it to their centroids
/// (where "into the surface" is, to nudge points off edges and corners; zero where they cancel);
/// the same directions weighed by each triangle's angle at the vertex (the bisector of an open
/// fan, whatever its triangles' count); and the longest edge of those triangles (the local patch
/// size). Zero-area triangles are skipped.
pub(crate) type Around = (Vec<DVec3>, Vec<DVec3>, Vec<f64>);

pub(crate) fn around(positions: &[DVec3], triangles: &[[u32; 3]]) -> Around {
    let mut inward = vec![DVec3::ZERO; positions.len()];
    let mut by_angle = vec![DVec3::ZERO; positions.len()];
    let mut longest = vec![0.0f64; positions.len()];
    for t in triangles {
        let p = t.map(|v| positions[v as usize]);
        let a = (p[1] - p[0]).cross(p[2] - p[0]).length();
        if a <= 0.0 || !a.is_finite() {
            continue;
        }
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let edge = (0..3)
            .map(|k| (p[k] - p[(k + 1) % 3]).length())
            .fold(0.0, f64::max);
        for (k, &v) in t.iter().enumerate() {
            let to_centroid = (centroid - p[k]).normalize_or_zero();
            let angle = (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]);
            inward[v as usize] += to_centroid;
            by_angle[v as usize] += to_centroid * angle;
            longest[v as usize] = longest[v as usize].max(edge);
        }
    }
    // Inside a symmetric fan (a vertex inside a face) the directions cancel, and what is left
    // is rounding noise, different at every scale: such a vertex has no inward direction.
    for d in inward.iter_mut().chain(&mut by_angle) {
        if d.length() < 1e-6 {
            *d = DVec3::ZERO;
        }
    }
    (inward, by_angle, longest)
}

fn add_group(mesh: &mut PatchMesh, g: GroupInput) {
    let group = mesh.groups.len() as u32;
    let r0 = mesh.receivers.len();
    let p0 = mesh.patches.len();
    let n = g.positions.len();
    // Per vertex: Σ of adjacent face normals (area-weighted).
    let mut face_sum = vec![DVec3::ZERO; n];
    let (inward, by_angle, local) = around(g.positions, g.triangles);
    let mut area = 0.0;
    for t in g.triangles {
        let p = t.map(|v| g.positions[v as usize]);
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let a = cross.length() / 2.0;
        if a <= 0.0 || !a.is_finite() {
            continue;
        }
        let normal = cross / (2.0 * a);
        for &v in t {
            face_sum[v as usize] += cross;
        }
        area += a;
        mesh.patches.push(Patch {
            v: t.map(|v| v + r0 as u32),
            group,
            area: a,
            normal,
            double_sided: g.double_sided,
        });
    }
    let mut offset = Vec::with_capacity(n);
    for i in 0..n {
        // On a contact's outline of depth c the light changes within about c of it (a glowing
        // panel's edge, a picture's shade), falling off as (c/d)²: read it where that profile
        // equals its mean over the patches around (size w, weighted as linear interpolation
        // weighs them): d = ½·√(c·w), at least 2c and at most a quarter of the patches around.
        let contact = g.outline.get(i).copied().flatten().unwrap_or(0.0);
        let off = (2.0 * contact).max(0.5 * (contact * local[i]).sqrt());
        let nudge = (1e-4 * local[i].min(g.h)).max(off.min(local[i] / 4.0));
        let face = face_sum[i].normalize_or_zero();
        let shading = g.shading_normals[i];
        // Trust the shading normal unless it disagrees with the faces around the vertex.
        let normal = if shading.dot(face) > 0.3 || face == DVec3::ZERO {
            if shading == DVec3::ZERO {
                DVec3::Y
            } else {
                shading
            }
        } else {
            face
        };
        // On an outline the step goes along the open fan's bisector: the plain sum of many thin
        // triangles along the two edges of a 270° corner (a shelf's end) points along an edge or
        // into the missing quarter, and the receiver reads the shelf's shadow (a dark vertex
        // smeared over the wall's large triangles).
        let into = match g.outline.get(i).copied().flatten() {
            Some(_) => by_angle[i],
            None => inward[i],
        };
        let tangent_in = (into - normal * into.dot(normal)).normalize_or_zero();
        let nudged = tangent_in * nudge;
        let p = g.positions[i];
        offset.push(
            under::step_out(&g.under, p, nudged, tangent_in, normal, local[i]).unwrap_or(nudged),
        );
        mesh.receivers.push(Vertex {
            position: g.positions[i],
            normal,
            point: g.positions[i],
            group,
        });
    }
    // On a concave curved surface (a dome or a round room seen from inside) a step along the
    // tangent plane leaves the surface behind the facets around the vertex, which would then
    // show the receiver their backs over up to half its hemisphere. Lift the step along the
    // normal until no facet around the vertex has the point behind its plane; the most tilted
    // one then passes through the point (seen edge-on, it covers nothing). On flat and convex
    // surfaces the step is already on or in front of every facet around it.
    let mut lift = vec![0.0f64; n];
    for p in &mesh.patches[p0..] {
        for &v in &p.v {
            let i = v as usize - r0;
            let normal = mesh.receivers[v as usize].normal;
            let (behind, rise) = (-p.normal.dot(offset[i]), p.normal.dot(normal));
            if behind > 0.0 && rise > 0.0 {
                lift[i] = lift[i].max(behind / rise);
            }
        }
    }
    for (i, r) in mesh.receivers[r0..].iter_mut().enumerate() {
        r.point = g.positions[i] + offset[i] + r.normal * lift[i];
    }
    mesh.groups.push(Group {
        surface: g.surface,
        side: g.side,
        material: g.material,
        receivers: r0..mesh.receivers.len(),
        patches: p0..mesh.patches.len(),
        uv0: g.uv0,
        uv1: g.uv1,
        area,
        covered: g.covered,
    });
}
