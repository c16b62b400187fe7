//! Light transport between patches and receivers: the patch hierarchy ([`tree`]), gathering at
//! a point ([`gather`]), and the precomputed receiver rows used by the solver ([`links`]).

pub mod gather;
pub mod links;
pub mod operator;
pub mod silhouette;
pub mod tree;
