//! A finished bake as its output holds it: what `bake report` and `bake diff` read (and next the
//! views and lightmap readers).
//!
//! [`read`] reads an output file; [`from_prepared`] reads the bytes the exporter is about to
//! write (`export::Prepared::glb`) and the atlases its EXR files will hold, so a report made at
//! bake time comes from the very values the files will hold ([`as_written`]: a bake in memory
//! that way). Lightmaps are read eagerly, and each lightmapped primitive's texels found
//! ([`texels`]), at read time. Both give a [`BakedOutput`] ([`model`]); the run summary in it is read typed only
//! by those who need it ([`BakedOutput::run_summary`]).
//!
//! Also the scene's cameras ([`cameras`]), each material's display factors ([`Look`]) and
//! `COLOR_0`, for the views.
//!
//! Below the consumers (`report`, `diff`, `view`), above the edges it reads through (`import`'s glTF
//! file layer, `export` for the bytes of a bake in memory) and the summary's format.

pub mod cameras;
pub mod keys;
mod lightmaps;
pub mod model;
mod read;
mod texels;

pub use cameras::{Camera, Projection};
pub use lightmaps::CHANNELS as LIGHTMAP_CHANNELS;
pub use model::{
    BakedOutput, Lightmap, LightmapUse, Look, MaterialInfo, NodeInfo, PlaneInput, PlanePoint,
    Primitive, ProbeNode, Texel,
};
pub use read::{as_written, from_glb, from_prepared, read};
pub use texels::bilinear;
