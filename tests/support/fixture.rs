//! A small hand-built scene and bake result that exercises every part of the exporter:
//! - node 0 "Room" (root, extras) with children 1–4;
//! - node 1 "Panel": rotated and negatively scaled (TRS, det < 0), a textured quad (material 0,
//!   with a generated 2×2 PNG, a sampler, emissive strength and a `LUXBAKE_material` object),
//!   extras `{"probe": true, "label": "panel", "nested": {"k": 1}}`;
//! - node 2 "Divider": a matrix transform, a quad with the double-sided material 1, baked on its
//!   front and its back;
//! - node 3 "Spot": a spot light; node 4 "Camera": a perspective camera;
//! - scene extras `{"project": "test room"}`.
//!
//! World-space data are made from local quads through each node's composed transform, with the
//! winding the importer would give (counter-clockwise from the front *in world space*).

use glam::{DMat4, DQuat, DVec2, DVec3};
use luxbake::result::{BakeResult, BakedSurface, Side};
use luxbake::scene::{
    DisplayMaterial, Image, Light, LightKind, LocalTransform, Material, Node, ReflectanceSource,
    Sampler, Scene, Surface, Texture, TextureRef, normalise_color,
};
use luxbake::summary::{Counts, RunSummary};
use serde_json::json;

/// A local unit quad in the XY plane facing +Z: positions, uvs, triangles (CCW from +Z).
fn quad() -> (Vec<DVec3>, Vec<DVec2>, Vec<[u32; 3]>) {
    let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    (
        p.iter().map(|&[x, y]| DVec3::new(x, y, 0.0)).collect(),
        p.iter().map(|&[x, y]| DVec2::new(x, 1.0 - y)).collect(),
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// An RGBA 2×2 PNG.
pub fn png_2x2() -> Vec<u8> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, 2, 2);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().unwrap();
    w.write_image_data(&[
        255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255,
    ])
    .unwrap();
    w.finish().unwrap();
    out
}

fn node(name: &str, local: LocalTransform, parent: DMat4) -> Node {
    Node {
        name: Some(name.into()),
        source_path: format!("/nodes/{name}"),
        children: vec![],
        local,
        world_from_local: parent * local.to_matrix(),
        mesh_name: None,
        surfaces: vec![],
        light: None,
        camera: None,
        extras: None,
    }
}

/// The world-space surface of a local quad placed by `m` (winding as the importer gives it).
fn surface(node: usize, material: usize, m: DMat4) -> Surface {
    let (p, uv, mut tris) = quad();
    if m.determinant() < 0.0 {
        tris.iter_mut().for_each(|t| t.swap(1, 2));
    }
    let n = m
        .inverse()
        .transpose()
        .transform_vector3(DVec3::Z)
        .normalize();
    Surface {
        node,
        primitive: 0,
        source_path: format!("/meshes/{node}/primitives/0"),
        material,
        positions: p.iter().map(|&q| m.transform_point3(q)).collect(),
        normals: vec![n; 4],
        uv0: Some(uv),
        uv1: None,
        triangles: tris,
    }
}

/// Baked values of one side: illuminance `e0 + 100 i` at vertex i, colour varied per vertex.
fn baked(index: usize, s: &Surface, side: Side, e0: f32, rho: f32) -> BakedSurface {
    let (normals, triangles) = match side {
        Side::Front => (s.normals.clone(), s.triangles.clone()),
        Side::Back => (
            s.normals.iter().map(|n| -*n).collect(),
            s.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect(),
        ),
    };
    let illuminance: Vec<f32> = (0..4).map(|i| e0 + 100.0 * i as f32).collect();
    BakedSurface {
        surface: index,
        side,
        positions: s.positions.clone(),
        normals,
        uv0: s.uv0.clone(),
        uv1: None,
        triangles,
        luminance: illuminance
            .iter()
            .map(|e| rho * e / std::f32::consts::PI)
            .collect(),
        illuminance_direct: illuminance.iter().map(|e| e * 0.5).collect(),
        illuminance,
        color: vec![
            [0.1, 0.2, 0.3],
            [0.5, 0.5, 0.5],
            [0.9, 0.8, 0.7],
            [1.0, 0.0, 0.25],
        ],
        lightmap: None,
        covered_from: None,
    }
}

/// The fixture scene and its bake result.
pub fn scene() -> (Scene, BakeResult) {
    let room = node("Room", LocalTransform::default(), DMat4::IDENTITY);
    let root = room.world_from_local;
    let mut panel = node(
        "Panel",
        LocalTransform::Trs {
            translation: DVec3::new(1.0, 2.0, 3.0),
            rotation: DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.3),
            scale: DVec3::new(-1.5, 1.0, 2.0),
        },
        root,
    );
    panel.mesh_name = Some("PanelMesh".into());
    panel.surfaces = vec![0];
    panel.extras = Some(json!({"probe": true, "label": "panel", "nested": {"k": 1}}));
    let m =
        DMat4::from_rotation_translation(DQuat::from_rotation_y(1.2), DVec3::new(-2.0, 0.0, 1.0));
    let mut divider = node("Divider", LocalTransform::Matrix(m), root);
    divider.mesh_name = Some("DividerMesh".into());
    divider.surfaces = vec![1];
    let mut spot = node(
        "Spot",
        LocalTransform::Trs {
            translation: DVec3::new(0.0, 3.0, 0.0),
            rotation: DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2),
            scale: DVec3::ONE,
        },
        root,
    );
    spot.light = Some(0);
    let mut camera = node(
        "Camera",
        LocalTransform::Trs {
            translation: DVec3::new(0.0, 1.6, 5.0),
            rotation: DQuat::IDENTITY,
            scale: DVec3::ONE,
        },
        root,
    );
    camera.camera = Some(0);
    let mut room = room;
    room.children = vec![1, 2, 3, 4];
    room.extras = Some(json!({"zone": "A"}));

    let surfaces = vec![
        surface(1, 0, panel.world_from_local),
        surface(2, 1, divider.world_from_local),
    ];
    let textured = Material {
        name: Some("Textured".into()),
        source_path: "/materials/0".into(),
        reflectance: DVec3::splat(0.4),
        emission: None,
        double_sided: false,
        reflectance_source: ReflectanceSource::Extension,
        display: DisplayMaterial {
            base_color_factor: [0.8, 0.7, 0.6, 1.0],
            base_color_texture: Some(TextureRef {
                texture: 0,
                tex_coord: 0,
                scale: 1.0,
            }),
            metallic_factor: 0.2,
            roughness_factor: 0.6,
            emissive_factor: [0.1, 0.0, 0.0],
            emissive_strength: Some(2.0),
            luxbake_extension: Some(json!({"reflectance": [0.4, 0.4, 0.4]})),
            ..DisplayMaterial::default()
        },
        extras: Some(json!({"author": "fixture"})),
    };
    let two_sided = Material {
        name: Some("TwoSided".into()),
        source_path: "/materials/1".into(),
        double_sided: true,
        reflectance_source: ReflectanceSource::BaseColor,
        ..Material::default_material()
    };
    let spot_world = spot.world_from_local;
    let light = Light {
        name: Some("Spot".into()),
        source_path: "/extensions/KHR_lights_punctual/lights/0".into(),
        node: 3,
        kind: LightKind::Spot {
            inner_cone_angle: 0.2,
            outer_cone_angle: 0.4,
        },
        intensity: 990.0,
        color: normalise_color(DVec3::new(1.0, 0.9, 0.8)).unwrap(),
        position: spot_world.transform_point3(DVec3::ZERO),
        direction: spot_world.transform_vector3(-DVec3::Z).normalize(),
        range: None,
    };
    let result = BakeResult {
        surfaces: vec![
            baked(0, &surfaces[0], Side::Front, 100.0, 0.4),
            baked(1, &surfaces[1], Side::Front, 50.0, 0.5),
            baked(1, &surfaces[1], Side::Back, 20.0, 0.5),
        ],
        lightmaps: None,
        openings: Vec::new(),
        summary: RunSummary {
            counts: Counts {
                patches: 12,
                ..Default::default()
            },
            ..Default::default()
        },
        timings: Default::default(),
        probes: Vec::new(),
    };
    let scene = Scene {
        source_file: "fixture.gltf".into(),
        name: Some("Lit room".into()),
        nodes: vec![room, panel, divider, spot, camera],
        roots: vec![0],
        surfaces,
        materials: vec![textured, two_sided],
        textures: vec![Texture {
            name: Some("checker".into()),
            image: 0,
            sampler: Some(0),
        }],
        images: vec![Image {
            name: Some("checker".into()),
            mime_type: "image/png".into(),
            bytes: png_2x2(),
        }],
        samplers: vec![Sampler {
            mag_filter: Some(9729),
            min_filter: Some(9987),
            wrap_s: Some(10497),
            wrap_t: Some(33648),
        }],
        lights: vec![light],
        profiles: Vec::new(),
        luminaires: Vec::new(),
        cameras: vec![json!({
            "name": "Eye",
            "type": "perspective",
            "perspective": {"aspectRatio": 1.5, "yfov": 0.8, "zfar": 100.0, "znear": 0.1}
        })],
        extras: Some(json!({"project": "test room"})),
        warnings: vec![],
        input_files: vec![],
    };
    (scene, result)
}
