//! Geometric kernels shared by every stage: exact point-to-polygon transfer (Lambert's formula),
//! solid angles, far-field cluster expansions and deterministic sample patterns.

pub mod farfield;
pub mod lambert;
pub mod samples;
pub mod sh;
