//! The `bake` command line's subcommands (the binary's own modules; the library knows nothing of
//! them).

pub mod bake;
pub mod design;
pub mod diff;
pub mod fit;
pub mod formats;
pub mod generate;
pub mod luminaire;
pub mod memory;
pub mod plan;
pub mod probes;
pub mod progress;
pub mod report;
pub mod settings;
pub mod shard;
pub mod view;
