//! Light transport between patches and receivers: the patch hierarchy ([`tree`]), fields
//! summarised on it ([`field`]), gathering at a point ([`gather`], giving [`link`]s; the seen
//! part of an emitting patch, [`lit`]), the precomputed receiver rows used by the solver
//! ([`links`]) and the patch-to-patch operator ([`operator`]), which reads only the tree's
//! [`skeleton`].

pub mod covered;
pub mod escape;
pub mod field;
pub mod gather;
pub mod link;
pub mod links;
pub mod lit;
pub mod operator;
pub mod packed;
pub mod sharing;
pub mod silhouette;
pub mod skeleton;
pub mod tree;
pub mod zones;
