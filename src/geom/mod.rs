//! Geometric kernels shared by every stage: exact point-to-polygon transfer (Lambert's formula),
//! solid angles, far-field cluster expansions, deterministic sample patterns, a fast `atan2` and
//! a hash for maps keyed by small integers.

pub mod atan;
pub mod farfield;
pub mod hash;
pub mod lambert;
pub mod samples;
pub mod sh;
