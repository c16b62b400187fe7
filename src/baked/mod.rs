//! A finished bake as its output holds it: what `bake report` and `bake diff` read (and next the
//! views and lightmap readers).
//!
//! [`read`] reads an output file; [`from_glb`] reads the bytes the exporter is about to write
//! (`export::Prepared::glb`), so a report made at bake time comes from the very values the file
//! will hold ([`as_written`]: a bake in memory that way). Both give a [`BakedOutput`] ([`model`]); the run summary in it is read typed only
//! by those who need it ([`BakedOutput::run_summary`]).
//!
//! Below the consumers (`report`, `diff`), above the edges it reads through (`import`'s glTF
//! file layer, `export` for the bytes of a bake in memory) and the summary's format.

pub mod model;
mod read;

pub use model::{
    BakedOutput, MaterialInfo, NodeInfo, PlaneInput, PlanePoint, Primitive, ProbeNode,
};
pub use read::{as_written, from_glb, read};
