//! luxbake: solve the diffuse inter-reflection of light (radiosity) in a photometric glTF/OBJ room
//! and write the lit result back as glTF.
//!
//! Pipeline (each stage a function from one data type to the next; see ARCHITECTURE.md):
//! `import` → [`scene::Scene`] → `bake` (patches and receivers, `visibility`, `direct` light,
//! `transport` links, `solve`) → [`solution::Solution`] (light at any receiver) →
//! [`result::BakeResult`] + [`summary::RunSummary`] → `export`; `readback` reads an output back
//! for `report` and `diff`.
//!
//! Units are SI and photometric (m, lx, cd, cd/m², lm); axes are glTF's, +Y up.

pub mod bake;
pub mod contacts;
pub mod design;
pub mod diff;
pub mod direct;
pub mod error;
pub mod export;
pub mod fit;
#[doc(hidden)]
pub mod fixtures;
pub mod geom;
pub mod gmres;
pub mod heap;
pub mod html_report;
pub mod import;
pub mod lightmap;
pub mod machine;
pub mod patches;
pub mod photometry;
pub mod picture;
pub mod plan;
pub mod probes;
pub mod progress;
pub mod readback;
pub mod report;
pub mod result;
pub mod scene;
pub mod settings;
pub mod shardfile;
pub mod solution;
pub mod summary;
pub mod table;
pub mod transport;
pub mod view;
pub mod visibility;

pub use error::{Error, Result};
