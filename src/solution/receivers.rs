//! Receivers: the points where light is read, each with the planes through it whose illuminance
//! is wanted — one plane for a mesh vertex (and next a lightmap texel), six for a probe's cube.
//!
//! A kind of receiver is a [`Receivers`] set: it numbers its points and says where each is and
//! how its planes turn. [`map`] runs a reading over a whole set in parallel, deterministically
//! (fixed chunks, results in order), so adding a kind is implementing the trait where the kind
//! lives and mapping a reading over it: direct light ([`super::DirectLight::at`]), light after
//! the solve ([`super::Solution::light_at`]).

use crate::patches::Vertex;
use crate::progress::Progress;
use glam::DVec3;
use rayon::prelude::*;

/// Most planes a receiver can have (a probe's six faces).
pub const MAX_PLANES: usize = 6;

/// The unit normals of a receiver's planes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Planes {
    normals: [DVec3; MAX_PLANES],
    len: usize,
}

impl Planes {
    /// One plane.
    pub fn one(n: DVec3) -> Self {
        Planes::of(&[n])
    }

    /// These planes (at most [`MAX_PLANES`]).
    pub fn of(normals: &[DVec3]) -> Self {
        assert!(
            normals.len() <= MAX_PLANES,
            "a receiver has at most six planes"
        );
        let mut out = Planes {
            normals: [DVec3::ZERO; MAX_PLANES],
            len: normals.len(),
        };
        out.normals[..normals.len()].copy_from_slice(normals);
        out
    }

    pub(crate) fn as_slice(&self) -> &[DVec3] {
        &self.normals[..self.len]
    }
}

/// A point (m, world space, +Y up) and its planes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Receiver {
    pub point: DVec3,
    pub planes: Planes,
}

/// Illuminance on one plane of a receiver (lx, linear RGB), split into the direct part (lights,
/// luminaires, emitting surfaces, unreflected) and the inter-reflected part.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlaneLight {
    pub direct: DVec3,
    pub indirect: DVec3,
}

impl PlaneLight {
    pub(crate) fn total(&self) -> DVec3 {
        self.direct + self.indirect
    }
}

/// A kind of receiver: a numbered set of points, each with its planes.
pub trait Receivers: Sync {
    fn len(&self) -> usize;

    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Receiver `i` (`i < len()`).
    fn receiver(&self, i: usize) -> Receiver;
}

/// The vertices of a patch mesh, each a receiver with the one plane of its side.
pub struct Vertices<'a>(pub &'a [Vertex]);

impl Receivers for Vertices<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }

    fn receiver(&self, i: usize) -> Receiver {
        let v = &self.0[i];
        Receiver {
            point: v.point,
            planes: Planes::one(v.normal),
        }
    }
}

/// Some vertices of a patch mesh (indices into it), in the given order, as [`Vertices`] has them.
pub struct VertexSubset<'a>(pub &'a [Vertex], pub &'a [u32]);

impl Receivers for VertexSubset<'_> {
    fn len(&self) -> usize {
        self.1.len()
    }

    fn receiver(&self, i: usize) -> Receiver {
        Vertices(self.0).receiver(self.1[i] as usize)
    }
}

/// Receivers per parallel chunk of [`map`] at most, and the fewest chunks a set is cut into (a
/// few hundred probes, each costing as much as thousands of vertices, were one chunk: one core).
const CHUNK: usize = 256;
const MIN_CHUNKS: usize = 64;

/// `read` at every receiver of `set`, in order. Chunks of receivers (at least [`MIN_CHUNKS`]
/// when there are that many receivers) run in parallel and each
/// receiver's value depends on it alone, so the result does not depend on the thread count;
/// `progress` advances by a chunk's receivers as each finishes.
pub(crate) fn map<T: Send>(
    set: &(impl Receivers + ?Sized),
    progress: &dyn Progress,
    read: impl Fn(usize, &Receiver) -> T + Sync,
) -> Vec<T> {
    let n = set.len();
    let chunk = n.div_ceil(MIN_CHUNKS).clamp(1, CHUNK);
    (0..n.div_ceil(chunk))
        .into_par_iter()
        .flat_map_iter(|c| {
            let range = c * chunk..(c * chunk + chunk).min(n);
            let out: Vec<T> = range.clone().map(|i| read(i, &set.receiver(i))).collect();
            progress.advance(range.len() as u64);
            out
        })
        .collect()
}
