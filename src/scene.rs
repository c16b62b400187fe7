//! The resolved, format-neutral scene model that every pipeline stage consumes.
//!
//! Importers (`import::gltf`, `import::obj`) produce a [`Scene`]; the exporter writes one back
//! (together with the bake results). Nothing here knows about file formats.
//!
//! Invariants (established by the importers, relied on everywhere else):
//! - Units are SI: metres, cd, lx, cd/m², lm. Axes are glTF's: right-handed, **+Y up**.
//! - Surface geometry is in **world space**; `Node::world_from_local` maps a node's local space to
//!   world space. Triangles are wound counter-clockwise seen from their front side *in world
//!   space* (importers flip the winding under a negative-determinant transform).
//! - Every `Surface::material` indexes `Scene::materials` (importers add a default material when
//!   the input has none). Every index (node, surface, texture, image, sampler, light) is valid.
//! - All positions and normals are finite; normals have unit length.
//! - Reflectances are validated: each channel in [0, 1).
//! - `source_path` strings name the input element for messages: a JSON pointer such as
//!   `/materials/3` for glTF, or a description such as `room.mtl: material 'wall'` for OBJ.

use glam::{DMat4, DQuat, DVec2, DVec3};
use serde_json::Value;
use std::path::PathBuf;

/// Largest world coordinate a scene may hold (m): 10 000 km, beyond any building; larger ones
/// come from a wrong unit or a broken transform (the importers and the probe reader refuse them).
pub const MAX_COORDINATE: f64 = 1e7;

/// A whole input scene, resolved to world space.

#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// The file the scene was read from (for messages and the output's provenance).
    pub source_file: PathBuf,
    /// Name of the scene that was imported (glTF: the default scene's name).
    pub name: Option<String>,
    /// All nodes, in input order. `roots` lists the scene's root nodes.
    pub nodes: Vec<Node>,
    pub roots: Vec<usize>,
    /// One entry per mesh primitive *instance* (a mesh used by two nodes gives two surfaces).
    pub surfaces: Vec<Surface>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub images: Vec<Image>,
    pub samplers: Vec<Sampler>,
    /// Punctual lights (KHR_lights_punctual), resolved to world space.
    pub lights: Vec<Light>,
    /// Photometric profiles (IES LM-63 or EULUMDAT files), shared by luminaires and emitting
    /// materials.
    pub profiles: Vec<Profile>,
    /// Luminaires with measured distributions (EXT_lights_ies, LUXBAKE_luminaire), world space.
    pub luminaires: Vec<Luminaire>,
    /// Camera definitions, kept verbatim (glTF `cameras[i]` JSON) so the output keeps them.
    pub cameras: Vec<Value>,
    /// The input scene's `extras`, kept verbatim.
    pub extras: Option<Value>,
    /// Non-fatal problems found while importing (unsupported attributes dropped, ...).
    pub warnings: Vec<String>,
    /// Every file the import read (the input, its buffers, images, MTL files), canonicalised;
    /// the exporter refuses to overwrite any of them.
    pub input_files: Vec<PathBuf>,
}

/// A node of the input hierarchy.
#[derive(Debug, Clone)]
pub struct Node {
    pub name: Option<String>,
    pub source_path: String,
    pub children: Vec<usize>,
    /// The node's own transform as the input gave it (kept so the output is faithful).
    pub local: LocalTransform,
    /// Composed transform from this node's local space to world space.
    pub world_from_local: DMat4,
    /// Name of the mesh this node instantiates, if any.
    pub mesh_name: Option<String>,
    /// The surfaces (mesh primitives) instantiated by this node, in primitive order.
    pub surfaces: Vec<usize>,
    /// Index into `Scene::lights`.
    pub light: Option<usize>,
    /// Index into `Scene::cameras`.
    pub camera: Option<usize>,
    /// The node's `extras`, kept verbatim (probes will be marked here).
    pub extras: Option<Value>,
}

/// A node's transform relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LocalTransform {
    Matrix(DMat4),
    Trs {
        translation: DVec3,
        rotation: DQuat,
        scale: DVec3,
    },
}

impl LocalTransform {
    pub fn to_matrix(&self) -> DMat4 {
        match *self {
            LocalTransform::Matrix(m) => m,
            LocalTransform::Trs {
                translation,
                rotation,
                scale,
            } => DMat4::from_scale_rotation_translation(scale, rotation, translation),
        }
    }
}

impl Default for LocalTransform {
    fn default() -> Self {
        LocalTransform::Trs {
            translation: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            scale: DVec3::ONE,
        }
    }
}

/// One triangle mesh with one material, in world space.
#[derive(Debug, Clone)]
pub struct Surface {
    /// The node that instantiates it.
    pub node: usize,
    /// Index of the primitive within its mesh (the output keeps the order).
    pub primitive: usize,
    /// `/meshes/2/primitives/0` (glTF) or `room.obj: object 'desk'` (OBJ).
    pub source_path: String,
    pub material: usize,
    /// World-space positions (m).
    pub positions: Vec<DVec3>,
    /// World-space unit shading normals, one per position.
    pub normals: Vec<DVec3>,
    /// `TEXCOORD_0` and `TEXCOORD_1`, when the input has them.
    pub uv0: Option<Vec<DVec2>>,
    pub uv1: Option<Vec<DVec2>>,
    /// Triangles, counter-clockwise seen from the front, in world space.
    pub triangles: Vec<[u32; 3]>,
}

impl Scene {
    /// The world-space box around every surface's vertices (m), if there is any vertex.
    pub(crate) fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for p in self.surfaces.iter().flat_map(|s| s.positions.iter()) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }
}

impl Surface {
    /// Total area of its triangles (m²).
    pub(crate) fn area(&self) -> f64 {
        (self.triangles.iter())
            .map(|t| {
                let [a, b, c] = t.map(|v| self.positions[v as usize]);
                (b - a).cross(c - a).length() / 2.0
            })
            .sum()
    }
}

/// A material: its photometric meaning (what the bake uses) and its display data (what the output
/// keeps so viewers draw it as the author made it).
#[derive(Debug, Clone)]
pub struct Material {
    pub name: Option<String>,
    pub source_path: String,
    /// Linear diffuse reflectance per channel (linear Rec. 709 RGB), each in [0, 1).
    pub reflectance: DVec3,
    /// Light emitted by surfaces with this material (Lambertian), if any.
    pub emission: Option<Emission>,
    /// Both faces reflect (and emit). Single-sided back faces absorb everything and still block.
    pub double_sided: bool,
    /// Where the reflectance came from (shown in reports and the output's extras).
    pub reflectance_source: ReflectanceSource,
    pub display: DisplayMaterial,
    /// The input material's `extras`, kept verbatim.
    pub extras: Option<Value>,
}

impl Material {
    /// The linear RGB a viewer multiplies the baked display value (COLOR_0, a display texture)
    /// by: the base colour; for an emitting material, its emission colour scaled to a largest
    /// channel of 1, so a source shows at its own luminance instead of reflectance × it.
    pub(crate) fn display_base(&self) -> DVec3 {
        match &self.emission {
            Some(e) => e.color / e.color.max_element().max(1e-12),
            None => {
                let [r, g, b, _] = self.display.base_color_factor;
                DVec3::new(r, g, b)
            }
        }
    }

    /// The material used for primitives that have none (glTF's default material: white, ρ from
    /// baseColor 1 would be ≥ 1, so we use a documented neutral 0.5).
    pub fn default_material() -> Self {
        Material {
            name: Some("luxbake default".into()),
            source_path: "(default material)".into(),
            reflectance: DVec3::splat(0.5),
            emission: None,
            double_sided: false,
            reflectance_source: ReflectanceSource::Default,
            display: DisplayMaterial::default(),
            extras: None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum ReflectanceSource {
    /// `LUXBAKE_material.reflectance`.
    Extension,
    /// `baseColorFactor` × mean of `baseColorTexture` × (1 − metallic).
    BaseColor,
    /// OBJ/MTL `Kd`.
    MtlKd,
    /// No material given.
    Default,
}

/// Lambertian emission of a material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emission {
    pub amount: EmissionAmount,
    /// Relative linear RGB colour, normalised so that its luminance
    /// Y = 0.2126 R + 0.7152 G + 0.0722 B is 1 (white is [1, 1, 1]).
    pub color: DVec3,
    /// A profile (index into `Scene::profiles`) giving the shape of the emitted distribution
    /// instead of Lambert's cosine: its nadir (0, 0) along the surface normal, C = 0 along the
    /// node's local +X projected onto the surface. The amount still sets the emitted flux
    /// (luminance L means the flux π·L·A a Lambertian face would emit).
    pub profile: Option<usize>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EmissionAmount {
    /// Luminance in cd/m² of every emitting face.
    Luminance(f64),
    /// Total luminous flux in lm, shared by all faces using the material in proportion to area.
    LuminousFlux(f64),
}

/// The display side of a material: what a glTF viewer needs to draw it.
#[derive(Debug, Clone)]
pub struct DisplayMaterial {
    /// Linear RGBA.
    pub base_color_factor: [f64; 4],
    pub base_color_texture: Option<TextureRef>,
    pub metallic_factor: f64,
    pub roughness_factor: f64,
    pub metallic_roughness_texture: Option<TextureRef>,
    pub normal_texture: Option<TextureRef>,
    pub occlusion_texture: Option<TextureRef>,
    pub emissive_texture: Option<TextureRef>,
    pub emissive_factor: [f64; 3],
    /// `KHR_materials_emissive_strength.emissiveStrength`, when present.
    pub emissive_strength: Option<f64>,
    pub alpha_mode: AlphaMode,
    pub alpha_cutoff: Option<f64>,
    /// The material's `LUXBAKE_material` extension object as given (kept in the output).
    pub luxbake_extension: Option<Value>,
}

impl Default for DisplayMaterial {
    fn default() -> Self {
        DisplayMaterial {
            base_color_factor: [1.0, 1.0, 1.0, 1.0],
            base_color_texture: None,
            metallic_factor: 1.0,
            roughness_factor: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive_texture: None,
            emissive_factor: [0.0; 3],
            emissive_strength: None,
            alpha_mode: AlphaMode::Opaque,
            alpha_cutoff: None,
            luxbake_extension: None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AlphaMode {
    Opaque,
    Mask,
    Blend,
}

/// A reference from a material to a texture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureRef {
    pub texture: usize,
    /// Which `TEXCOORD_n` set it uses.
    pub tex_coord: u32,
    /// `scale` (normal textures) or `strength` (occlusion textures); 1 otherwise.
    pub scale: f64,
}

#[derive(Debug, Clone)]
pub struct Texture {
    pub name: Option<String>,
    pub image: usize,
    pub sampler: Option<usize>,
}

/// An image's encoded bytes (PNG or JPEG), embedded in the output whatever the input did.
#[derive(Debug, Clone)]
pub struct Image {
    pub name: Option<String>,
    pub mime_type: String,
    pub bytes: Vec<u8>,
}

/// A texture sampler, as glTF numbers (`None` = unset).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Sampler {
    pub mag_filter: Option<u32>,
    pub min_filter: Option<u32>,
    pub wrap_s: Option<u32>,
    pub wrap_t: Option<u32>,
}

/// A photometric data file as read, parsed.
#[derive(Debug, Clone)]
pub struct Profile {
    pub name: Option<String>,
    /// `/extensions/EXT_lights_ies/lights/0` or `/extensions/LUXBAKE_luminaire/profiles/1`.
    pub source_path: String,
    /// The file's bytes (embedded in the output).
    pub bytes: Vec<u8>,
    pub photometry: crate::photometry::Photometry,
}

/// A luminaire with a measured distribution, placed by a node, in world space.
///
/// The photometric frame (the profile's own axes) maps to world space by `world_from_photometric`
/// (orthonormal, node scale removed): photometric −Z is the nadir, the direction of (C, γ) = (0, 0)
/// (EXT_lights_ies: "an untransformed light points down −Z"); +X is C = 0 and +Y is C = 90°.
#[derive(Debug, Clone)]
pub struct Luminaire {
    pub name: Option<String>,
    /// The node extension that defines it, e.g. `/nodes/4/extensions/EXT_lights_ies`.
    pub source_path: String,
    pub node: usize,
    /// Index into `Scene::profiles`.
    pub profile: usize,
    /// Intensity scale: EXT_lights_ies `multiplier` × luminance of its raw `color` (the spec's
    /// colour is a per-channel multiplier that changes the output) × maintenance factor.
    pub multiplier: f64,
    /// The maintenance (light loss) factor included in `multiplier` (1 when not given).
    pub maintenance_factor: f64,
    /// Relative linear RGB colour normalised to luminance 1 (see [`Emission::color`]).
    pub color: DVec3,
    /// Photometric centre (m, world).
    pub position: DVec3,
    pub world_from_photometric: glam::DMat3,
    /// Luminous opening overriding the profile's (m), from `LUXBAKE_luminaire.opening`.
    pub opening: Option<crate::photometry::Opening>,
    /// The node's EXT_lights_ies / LUXBAKE_luminaire objects as given, for the output.
    pub extensions: serde_json::Map<String, Value>,
}

/// A punctual light (KHR_lights_punctual) in world space.
#[derive(Debug, Clone)]
pub struct Light {
    pub name: Option<String>,
    /// `/extensions/KHR_lights_punctual/lights/0`.
    pub source_path: String,
    /// The node that places it.
    pub node: usize,
    pub kind: LightKind,
    /// Point and spot: luminous intensity in cd (on the axis, inside the inner cone for spots).
    /// Directional: illuminance in lx on a surface facing the light.
    pub intensity: f64,
    /// Relative linear RGB colour, normalised to luminance Y = 1 (see [`Emission::color`]).
    pub color: DVec3,
    /// World-space position (m); unused for directional lights.
    pub position: DVec3,
    /// World-space unit direction the light points in (the node's local −Z).
    pub direction: DVec3,
    /// KHR_lights_punctual `range`, kept for the output; the bake ignores it (physical falloff).
    pub range: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    Point,
    /// Cone angles in radians from the axis; 0 ≤ inner < outer ≤ π/2.
    Spot {
        inner_cone_angle: f64,
        outer_cone_angle: f64,
    },
    Directional,
}

/// Luminance-weighting of linear Rec. 709 RGB (the Y of CIE XYZ).
pub const LUMA: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);

/// Photometric luminance Y of a linear RGB triple.
pub fn luma(c: DVec3) -> f64 {
    c.dot(LUMA)
}

/// Normalise a linear RGB colour so that its luminance is 1; `None` if it has no luminance.
pub fn normalise_color(c: DVec3) -> Option<DVec3> {
    let y = luma(c);
    (y.is_finite() && y > 0.0 && c.min_element() >= 0.0).then(|| c / y)
}
