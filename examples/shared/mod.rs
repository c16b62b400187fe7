//! What the direct-light examples (`light_tail`, `direct_floor`) read from a scene file.

use glam::DVec3;
use luxbake::direct::bounds::ProfileBounds;
use luxbake::direct::luminaire::Source;
use luxbake::direct::sources::DirectSource;
use luxbake::import::{ImportOptions, load};
use luxbake::scene::Scene;

/// The scene at `path`, imported as the bake imports it (panics with the path on failure).
pub fn scene(path: &str) -> Scene {
    load(std::path::Path::new(path), &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{path} does not load: {e}"))
}

/// The scene's luminaires as direct sources.
pub fn luminaires<'a>(scene: &'a Scene, bounds: &'a ProfileBounds) -> Vec<DirectSource<'a>> {
    (Source::all(scene, bounds).into_iter())
        .map(DirectSource::Luminaire)
        .collect()
}

/// Every vertex of the scene's surfaces with its normal.
pub fn vertices(scene: &Scene) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
    (scene.surfaces.iter()).flat_map(|s| s.positions.iter().copied().zip(s.normals.iter().copied()))
}
