//! Scenes built in code (not library API: hidden from the docs, free to change): the builder,
//! the benchmark's open-plan office and building floor that `bake generate` writes, and — with
//! the `test-scenes` feature, on for `cargo test` and the examples — the scenes with known
//! answers that the tests compare against closed forms (docs/ANALYTIC.md) and the benchmark
//! harness bakes. Axes: +Y up; lengths in metres.

use crate::scene::{
    DisplayMaterial, Emission, EmissionAmount, Light, LightKind, LocalTransform, Material, Node,
    ReflectanceSource, Scene, Surface,
};
use glam::{DMat4, DVec3};

pub mod building_floor;
pub mod openplan;
pub use openplan::{OpenPlan, open_plan};

// The known-answer scenes are for tests and benchmarks only (on with the `test-scenes` feature,
// which `cargo test` and the examples turn on); `bake generate` needs only the builder and the
// benchmark's floors.
#[cfg(any(test, feature = "test-scenes"))]
pub mod building;
#[cfg(any(test, feature = "test-scenes"))]
pub mod contacts;
#[cfg(any(test, feature = "test-scenes"))]
mod known;
#[cfg(any(test, feature = "test-scenes"))]
pub use known::*;

/// Builds a [`Scene`] one node per surface.
#[derive(Default)]
pub struct SceneBuilder {
    scene: Scene,
}

impl SceneBuilder {
    pub fn new() -> Self {
        SceneBuilder::default()
    }

    /// Go on building `scene`.
    pub fn from_scene(scene: Scene) -> Self {
        SceneBuilder { scene }
    }

    /// A grey diffuse material with reflectance `rho`; returns its index.
    pub fn material(&mut self, name: &str, rho: f64) -> usize {
        self.material_full(name, DVec3::splat(rho), None, false)
    }

    /// A material that emits luminance `l` (cd/m²) and reflects `rho`.
    pub fn emitter(&mut self, name: &str, rho: f64, l: f64) -> usize {
        let e = Emission {
            amount: EmissionAmount::Luminance(l),
            color: DVec3::ONE,
            profile: None,
        };
        self.material_full(name, DVec3::splat(rho), Some(e), false)
    }

    /// A material with per-channel reflectance `rho`; its `LUXBAKE_material` object (reflectance
    /// and emission) is filled in, so that an exported scene keeps both.
    pub fn material_full(
        &mut self,
        name: &str,
        rho: DVec3,
        emission: Option<Emission>,
        double_sided: bool,
    ) -> usize {
        let mut ext = serde_json::Map::new();
        ext.insert("reflectance".into(), serde_json::json!(rho.to_array()));
        if let Some(e) = &emission {
            let mut em = serde_json::Map::new();
            match e.amount {
                EmissionAmount::Luminance(l) => em.insert("luminance".into(), l.into()),
                EmissionAmount::LuminousFlux(f) => em.insert("luminousFlux".into(), f.into()),
            };
            if e.color != DVec3::ONE {
                em.insert("color".into(), serde_json::json!(e.color.to_array()));
            }
            ext.insert("emission".into(), em.into());
        }
        self.scene.materials.push(Material {
            name: Some(name.into()),
            source_path: format!("/materials/{}", self.scene.materials.len()),
            reflectance: rho,
            emission,
            double_sided,
            reflectance_source: ReflectanceSource::Extension,
            display: DisplayMaterial {
                base_color_factor: [rho.x, rho.y, rho.z, 1.0],
                metallic_factor: 0.0,
                luxbake_extension: Some(ext.into()),
                ..Default::default()
            },
            extras: None,
        });
        self.scene.materials.len() - 1
    }

    /// A planar quad (corners counter-clockwise seen from its front) as its own node.
    pub fn quad(&mut self, name: &str, corners: [DVec3; 4], material: usize) {
        let n = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        self.surface(
            name,
            corners.to_vec(),
            vec![n; 4],
            vec![[0, 1, 2], [0, 2, 3]],
            material,
        );
    }

    /// A horizontal square of half-size `half` at height `y`, centred on the Y axis, facing up (+Y).
    pub fn floor(&mut self, name: &str, half: f64, y: f64, material: usize) {
        let c = |x: f64, z: f64| DVec3::new(x, y, z);
        self.quad(
            name,
            [
                c(-half, -half),
                c(-half, half),
                c(half, half),
                c(half, -half),
            ],
            material,
        );
    }

    /// A triangle mesh as its own node (identity transform).
    pub fn surface(
        &mut self,
        name: &str,
        positions: Vec<DVec3>,
        normals: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
        material: usize,
    ) {
        let node = self.scene.nodes.len();
        let surface = self.scene.surfaces.len();
        self.scene.surfaces.push(Surface {
            node,
            primitive: 0,
            source_path: format!("/meshes/{surface}/primitives/0"),
            material,
            positions,
            normals,
            uv0: None,
            uv1: None,
            triangles,
        });
        self.scene.nodes.push(Node {
            name: Some(name.into()),
            source_path: format!("/nodes/{node}"),
            children: Vec::new(),
            local: LocalTransform::default(),
            world_from_local: DMat4::IDENTITY,
            mesh_name: Some(name.into()),
            surfaces: vec![surface],
            light: None,
            camera: None,
            extras: None,
        });
        self.scene.roots.push(node);
    }

    /// The six faces of an axis-aligned box, facing inward (`inward`) or outward.
    pub fn axis_box(&mut self, name: &str, lo: DVec3, hi: DVec3, inward: bool, material: usize) {
        for (face, corners) in box_faces(lo, hi).into_iter().enumerate() {
            let c = if inward {
                corners
            } else {
                [corners[0], corners[3], corners[2], corners[1]]
            };
            self.quad(&format!("{name}_{face}"), c, material);
        }
    }

    /// An isotropic point light of `flux` lm at `position`.
    /// A tessellated ball (latitude-longitude, `rings` × `segments`), counter-clockwise seen from
    /// outside, with radial shading normals: curved clutter.
    pub fn ball(
        &mut self,
        name: &str,
        centre: DVec3,
        radius: f64,
        (rings, segments): (u32, u32),
        material: usize,
    ) {
        let (dirs, mut triangles) = lat_long(rings, segments);
        let positions: Vec<DVec3> = dirs.iter().map(|d| centre + *d * radius).collect();
        for t in &mut triangles {
            let p = t.map(|v| dirs[v as usize]);
            if (p[1] - p[0]).cross(p[2] - p[0]).dot(p[0] + p[1] + p[2]) < 0.0 {
                t.swap(1, 2);
            }
        }
        let normals = positions
            .iter()
            .map(|p| (*p - centre).normalize_or_zero())
            .collect();
        self.surface(name, positions, normals, triangles, material);
    }

    pub fn point_light(&mut self, name: &str, position: DVec3, flux: f64) {
        self.light(
            name,
            LightKind::Point,
            position,
            -DVec3::Y,
            flux / (4.0 * std::f64::consts::PI),
        );
    }

    /// A light of any kind; `intensity` in cd (lx for directional).
    pub fn light(
        &mut self,
        name: &str,
        kind: LightKind,
        position: DVec3,
        direction: DVec3,
        intensity: f64,
    ) {
        let node = self.scene.nodes.len();
        let index = self.scene.lights.len();
        self.scene.lights.push(Light {
            name: Some(name.into()),
            source_path: format!("/extensions/KHR_lights_punctual/lights/{index}"),
            node,
            kind,
            intensity,
            color: DVec3::ONE,
            position,
            direction: direction.normalize(),
            range: None,
        });
        let rotation = glam::DQuat::from_rotation_arc(-DVec3::Z, direction.normalize());
        self.scene.nodes.push(Node {
            name: Some(name.into()),
            source_path: format!("/nodes/{node}"),
            children: Vec::new(),
            local: LocalTransform::Trs {
                translation: position,
                rotation,
                scale: DVec3::ONE,
            },
            world_from_local: DMat4::from_rotation_translation(rotation, position),
            mesh_name: None,
            surfaces: Vec::new(),
            light: Some(index),
            camera: None,
            extras: None,
        });
        self.scene.roots.push(node);
    }

    /// Add a photometric profile (panics on a malformed file: fixtures are trusted input).
    pub fn profile(
        &mut self,
        name: &str,
        bytes: &[u8],
        format: crate::photometry::Format,
    ) -> usize {
        let path = format!(
            "/extensions/LUXBAKE_luminaire/profiles/{}",
            self.scene.profiles.len()
        );
        self.add_profile(name, bytes, format, path)
    }

    /// Add an IES LM-63 profile that an exported scene lists under `EXT_lights_ies` (its
    /// luminaires then carry `EXT_lights_ies` nodes, as in the office sample) rather than
    /// `LUXBAKE_luminaire`. Panics on a malformed file.
    pub fn ies_light(&mut self, name: &str, bytes: &[u8]) -> usize {
        let lights = self
            .scene
            .profiles
            .iter()
            .filter(|p| p.source_path.starts_with("/extensions/EXT_lights_ies/"))
            .count();
        let path = format!("/extensions/EXT_lights_ies/lights/{lights}");
        self.add_profile(name, bytes, crate::photometry::Format::Ies, path)
    }

    fn add_profile(
        &mut self,
        name: &str,
        bytes: &[u8],
        format: crate::photometry::Format,
        source_path: String,
    ) -> usize {
        let photometry =
            crate::photometry::Photometry::parse(bytes, format).expect("fixture profile parses");
        self.scene.profiles.push(crate::scene::Profile {
            name: Some(name.into()),
            source_path,
            bytes: bytes.to_vec(),
            photometry,
        });
        self.scene.profiles.len() - 1
    }

    /// A luminaire with the photometric file `bytes` at `position`, its nadir along `nadir` and
    /// photometric C = 0 along `c0` (made perpendicular to the nadir); `opening` overrides the
    /// file's luminous opening. Panics on a malformed file (fixtures are trusted input).
    #[allow(clippy::too_many_arguments)]
    pub fn luminaire(
        &mut self,
        name: &str,
        bytes: &[u8],
        format: crate::photometry::Format,
        position: DVec3,
        nadir: DVec3,
        c0: DVec3,
        multiplier: f64,
        opening: Option<crate::photometry::Opening>,
    ) {
        let profile = self.profile(name, bytes, format);
        self.place_luminaire(name, profile, position, nadir, c0, multiplier, opening);
    }

    /// A luminaire with the profile `profile` (from [`SceneBuilder::profile`], shared by as many
    /// luminaires as use it), placed like [`SceneBuilder::luminaire`].
    #[allow(clippy::too_many_arguments)]
    pub fn place_luminaire(
        &mut self,
        name: &str,
        profile: usize,
        position: DVec3,
        nadir: DVec3,
        c0: DVec3,
        multiplier: f64,
        opening: Option<crate::photometry::Opening>,
    ) {
        let z = -nadir.normalize();
        let x = (c0 - z * c0.dot(z)).normalize();
        let frame = glam::DMat3::from_cols(x, z.cross(x), z);
        let node = self.scene.nodes.len();
        let rotation = glam::DQuat::from_mat3(&frame);
        self.scene.luminaires.push(crate::scene::Luminaire {
            name: Some(name.into()),
            source_path: format!("/nodes/{node}/extensions/LUXBAKE_luminaire"),
            node,
            profile,
            multiplier,
            maintenance_factor: 1.0,
            color: DVec3::ONE,
            position,
            world_from_photometric: frame,
            opening,
            extensions: Default::default(),
        });
        self.scene.nodes.push(Node {
            name: Some(name.into()),
            source_path: format!("/nodes/{node}"),
            children: Vec::new(),
            local: LocalTransform::Trs {
                translation: position,
                rotation,
                scale: DVec3::ONE,
            },
            world_from_local: DMat4::from_rotation_translation(rotation, position),
            mesh_name: None,
            surfaces: Vec::new(),
            light: None,
            camera: None,
            extras: None,
        });
        self.scene.roots.push(node);
    }

    pub fn build(self) -> Scene {
        self.scene
    }
}

/// The six faces of a box, each counter-clockwise seen from INSIDE the box.
pub fn box_faces(lo: DVec3, hi: DVec3) -> [[DVec3; 4]; 6] {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let (a, b) = (lo, hi);
    [
        // floor (normal +Y), ceiling (−Y)
        [
            p(a.x, a.y, a.z),
            p(a.x, a.y, b.z),
            p(b.x, a.y, b.z),
            p(b.x, a.y, a.z),
        ],
        [
            p(a.x, b.y, a.z),
            p(b.x, b.y, a.z),
            p(b.x, b.y, b.z),
            p(a.x, b.y, b.z),
        ],
        // x = lo (normal +X), x = hi (−X)
        [
            p(a.x, a.y, a.z),
            p(a.x, b.y, a.z),
            p(a.x, b.y, b.z),
            p(a.x, a.y, b.z),
        ],
        [
            p(b.x, a.y, a.z),
            p(b.x, a.y, b.z),
            p(b.x, b.y, b.z),
            p(b.x, b.y, a.z),
        ],
        // z = lo (normal +Z), z = hi (−Z)
        [
            p(a.x, a.y, a.z),
            p(b.x, a.y, a.z),
            p(b.x, b.y, a.z),
            p(a.x, b.y, a.z),
        ],
        [
            p(a.x, a.y, b.z),
            p(a.x, b.y, b.z),
            p(b.x, b.y, b.z),
            p(b.x, a.y, b.z),
        ],
    ]
}

/// Unit directions of a latitude-longitude sphere (`rings` × `segments`, +Y the pole) and its
/// triangles, unoriented.
pub fn lat_long(rings: u32, segments: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut dirs = Vec::new();
    for i in 0..=rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            dirs.push(DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ));
        }
    }
    let at = |i: u32, j: u32| i * segments + j % segments;
    let mut triangles = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            if i > 0 {
                triangles.push([a, b, d]);
            }
            if i + 1 < rings {
                triangles.push([b, c, d]);
            }
        }
    }
    (dirs, triangles)
}
