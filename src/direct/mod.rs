//! Direct light: from punctual lights and from emitting surfaces, evaluated exactly at every
//! receiver and as flux into every patch (what the radiosity solution then reflects).

pub mod bounds;
pub mod cut;
pub mod emitters;
pub mod enclosed;
pub mod flux;
pub mod groups;
pub mod luminaire;
pub mod opening;
pub mod penumbra;
pub mod profiled;
pub mod punctual;
pub mod sources;
pub mod targets;
