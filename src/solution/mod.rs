//! A solved scene and the receivers that read light from it.
//!
//! - [`receivers`]: what a receiver is (a point and its planes) and how a kind of receiver is
//!   read in parallel;
//! - [`direct`]: direct light at any receiver ([`DirectLight`]), read before the solve at the
//!   mesh vertices and kept for every receiver after it;
//! - [`solved`]: the [`Solution`] — light at any receiver after the solve;
//! - `sight` and [`sphere`]: what a point sees along a direction, and integrals over the sphere.
//!
//! Nothing here decides *where* receivers are (the bake's stages, the probes, the lightmaps do)
//! or writes anything.

pub mod direct;
pub mod receivers;
mod sight;
pub mod solved;
pub mod sphere;

pub use direct::DirectLight;
pub use receivers::{PlaneLight, Planes, Receiver, Receivers};
pub use solved::Solution;
