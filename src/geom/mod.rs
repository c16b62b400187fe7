//! Geometric kernels shared by every stage: exact point-to-polygon transfer (Lambert's formula),
//! solid angles, far-field cluster expansions, deterministic sample patterns and a fast `atan2`.

pub mod atan;
pub mod farfield;
pub mod lambert;
pub mod samples;
pub mod sh;
