//! Probes: points in the room where luxbake measures **cubic illuminance** (Cuttle 1997) — the
//! illuminance on the six faces of a small cube — and the metrics derived from it
//! (docs/ANALYTIC.md §4 Cubic illuminance).
//!
//! - [`Probe`]: where (world space, m) and how the cube is turned. The cube is axis-aligned with
//!   the glTF world axes (+Y up) unless `world_from_probe` turns it (rooms not aligned with the
//!   axes).
//! - [`CubicIlluminance`]: the six face illuminances E(+x), E(−x), E(+y), E(−y), E(+z), E(−z) in
//!   the probe's axes, each split into direct (exact, shadowed, from the real luminaire
//!   distributions) and indirect (gathered from the radiosity solution with visibility).
//! - [`metrics::Metrics`]: everything derived from the six numbers, plus the exact scalar and cylindrical
//!   illuminance from an integration over the sphere (where the six-face estimate is known to
//!   err), and Cuttle's constant estimate of the indirect part for comparison.
//!
//! Face order everywhere: `[+x, −x, +y, −y, +z, −z]` (probe axes).
//!
//! Where: [`place`] puts the probes of a bake (nodes marked `probe`, grids, explicit points,
//! the working plane). Input and output: [`csv`] reads probes from a `--probes` file; [`output`]
//! makes the JSON object written to the glTF's `extras.luxbake` and to `--probes-out FILE.json`;
//! [`table`] the `--probes-out FILE.csv` table. Measuring them is a stage of the bake
//! (`bake::probes`): probes are receivers like any other.

pub mod csv;
pub mod metrics;
pub mod output;
pub mod place;
pub mod table;

use glam::{DMat3, DVec3};

/// The six face normals, in the order used everywhere.
pub const FACES: [DVec3; 6] = [
    DVec3::X,
    DVec3::NEG_X,
    DVec3::Y,
    DVec3::NEG_Y,
    DVec3::Z,
    DVec3::NEG_Z,
];

/// The face names, in order, as written in outputs.
pub const FACE_NAMES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// A horizontal grid of probes: points every `spacing` m over the floor, `height` m above it
/// (+Y up).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ProbeGrid {
    pub spacing: f64,
    pub height: f64,
}

/// A measuring point.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    pub name: String,
    /// World position (m).
    pub position: DVec3,
    /// Rotation from the probe's axes to world axes (identity: aligned with the world).
    pub world_from_probe: DMat3,
    pub origin: ProbeOrigin,
    /// A horizontal direction (probe axes) toward which the semi-cylindrical illuminance is also
    /// reported, when given.
    pub toward: Option<DVec3>,
}

/// Where a probe came from.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase", tag = "kind")]
pub enum ProbeOrigin {
    /// A glTF node whose `extras.probe` is true (index into `Scene::nodes`).
    Node { node: usize },
    /// A grid from the command line (`--probe-grid`); `layer` names the grid.
    Grid { layer: String },
    /// A row of a `--probes` CSV file (1-based line).
    File { line: usize },
    /// The working plane of the report (`--working-plane`): only the upward face matters.
    WorkingPlane,
}

/// The six face illuminances (lx, photometric), split.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CubicIlluminance {
    pub total: [f64; 6],
    pub direct: [f64; 6],
    pub indirect: [f64; 6],
}

/// What the probe measured and what follows from it (lx unless stated).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ProbeResult {
    pub probe: Probe,
    pub cubic: CubicIlluminance,
    pub metrics: metrics::Metrics,
}

impl serde::Serialize for Probe {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Probe", 5)?;
        st.serialize_field("name", &self.name)?;
        st.serialize_field("position", &self.position.to_array())?;
        let m = self.world_from_probe;
        st.serialize_field(
            "worldFromProbe",
            &[
                m.x_axis.to_array(),
                m.y_axis.to_array(),
                m.z_axis.to_array(),
            ],
        )?;
        st.serialize_field("origin", &self.origin)?;
        st.serialize_field("toward", &self.toward.map(|t| t.to_array()))?;
        st.end()
    }
}
