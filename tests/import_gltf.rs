//! Integration tests of the glTF importer through the public API `luxbake::import::load`.
//! Fixtures are written into a temporary folder by `common::Builder`.

mod common;

use common::*;
use glam::{DMat4, DQuat, DVec3};
use luxbake::scene::{LocalTransform, ReflectanceSource};
use serde_json::json;
use std::f64::consts::FRAC_PI_2;
use std::path::Path;

#[test]
fn nested_trs_and_matrix_compose_to_world_space() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let mesh = b.simple_mesh(&TRIANGLE, None, None, None);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    // Root: translate (1, 2, 3), rotate 90° about +Y, scale 2. Child: matrix translating +X.
    b.node(json!({"children": [1], "translation": [1, 2, 3],
        "rotation": [0, h, 0, h], "scale": [2, 2, 2]}));
    b.node(json!({"mesh": mesh, "matrix":
        [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1]}));
    b.set("scenes", json!([{"nodes": [0]}]));
    let scene = load_ok(&b.write_gltf(dir.path(), "nested.gltf", Bin::External("n.bin")));

    assert_eq!(scene.roots, vec![0]);
    assert_eq!(scene.nodes[0].children, vec![1]);
    assert!(matches!(scene.nodes[1].local, LocalTransform::Matrix(_)));
    let LocalTransform::Trs { translation, .. } = scene.nodes[0].local else {
        panic!("root keeps its TRS");
    };
    assert_close(
        translation,
        DVec3::new(1.0, 2.0, 3.0),
        "root translation kept",
    );
    let expected_world = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        DQuat::from_rotation_y(FRAC_PI_2),
        DVec3::new(1.0, 2.0, 3.0),
    ) * DMat4::from_translation(DVec3::X);
    assert!(
        scene.nodes[1]
            .world_from_local
            .abs_diff_eq(expected_world, 1e-9)
    );

    let s = &scene.surfaces[0];
    assert_eq!(scene.nodes[1].surfaces, vec![0]);
    assert_eq!((s.node, s.primitive), (1, 0));
    assert_eq!(s.source_path, "/meshes/0/primitives/0");
    // Local (0,0,0) → +X (1,0,0) → ×2 (2,0,0) → Ry(90°) (0,0,−2) → +(1,2,3) = (1,2,1).
    assert_close(s.positions[0], DVec3::new(1.0, 2.0, 1.0), "vertex 0");
    // Local (1,0,0) → (2,0,0) → (4,0,0) → (0,0,−4) → (1,2,−1).
    assert_close(s.positions[1], DVec3::new(1.0, 2.0, -1.0), "vertex 1");
    // Local (0,1,0) → (1,1,0) → (2,2,0) → (0,2,−2) → (1,4,1).
    assert_close(s.positions[2], DVec3::new(1.0, 4.0, 1.0), "vertex 2");
    // No NORMAL: flat normal of the face, local +Z turned by Ry(90°) to +X.
    for n in &s.normals {
        assert_close(*n, DVec3::X, "flat normal");
    }
    assert_close(
        geometric_normal(&s.positions, s.triangles[0]),
        DVec3::X,
        "winding",
    );
    // No material: the default one is appended.
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(
        scene.materials[0].reflectance_source,
        ReflectanceSource::Default
    );
}

#[test]
fn negative_scale_flips_winding_and_keeps_normals_consistent() {
    let dir = tempfile::tempdir().unwrap();
    for (scale, name) in [
        ([1.0, 1.0, 1.0], "pos.gltf"),
        ([-1.0, 1.0, 1.0], "neg.gltf"),
    ] {
        let mut b = Builder::new();
        let position = b.vec3s(&TRIANGLE);
        let normal = b.vec3s(&[[0.0, 0.0, 1.0]; 3]);
        let mesh = b.mesh(vec![
            json!({"attributes": {"POSITION": position, "NORMAL": normal}}),
        ]);
        b.node(json!({"mesh": mesh, "scale": scale}));
        b.set("scenes", json!([{"nodes": [0]}]));
        let scene = load_ok(&b.write_gltf(dir.path(), name, Bin::DataUri));
        let s = &scene.surfaces[0];
        let geometric = geometric_normal(&s.positions, s.triangles[0]);
        assert_close(geometric, DVec3::Z, "geometric normal faces the front");
        for n in &s.normals {
            assert_close(*n, DVec3::Z, "shading normal (inverse transpose)");
        }
        if scale[0] < 0.0 {
            assert_close(
                s.positions[1],
                DVec3::new(-1.0, 0.0, 0.0),
                "mirrored vertex",
            );
            assert_eq!(s.triangles[0], [0, 2, 1]);
        } else {
            assert_eq!(s.triangles[0], [0, 1, 2]);
        }
    }
}

#[test]
fn normals_use_inverse_transpose_and_are_renormalised() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let position = b.vec3s(&TRIANGLE);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let normal = b.vec3s(&[[h, h, 0.0]; 3]);
    let mesh = b.mesh(vec![
        json!({"attributes": {"POSITION": position, "NORMAL": normal}}),
    ]);
    b.node(json!({"mesh": mesh, "scale": [2, 1, 1]}));
    let scene = load_ok(&b.write_gltf(dir.path(), "n.gltf", Bin::DataUri));
    // (h, h, 0) under diag(2,1,1)⁻ᵀ = diag(0.5,1,1) → (0.5h, h, 0) → (1, 2, 0)/√5.
    let expected = DVec3::new(1.0, 2.0, 0.0) / 5f64.sqrt();
    assert_close(scene.surfaces[0].normals[0], expected, "normal");
}

#[test]
fn strips_fans_non_indexed_and_skipped_points() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let strip_pos = b.vec3s(&square);
    // Fan around the centre of the square's lower-left corner.
    let fan_pos = b.vec3s(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let fan_idx = b.indices(&[0, 1, 2, 3]);
    let mesh = b.mesh(vec![
        json!({"attributes": {"POSITION": strip_pos}, "mode": 5}),
        json!({"attributes": {"POSITION": fan_pos}, "indices": fan_idx, "mode": 6}),
        json!({"attributes": {"POSITION": strip_pos}, "mode": 0}),
    ]);
    b.node(json!({"mesh": mesh}));
    let scene = load_ok(&b.write_gltf(dir.path(), "modes.gltf", Bin::External("m.bin")));
    assert_eq!(scene.surfaces.len(), 2, "the POINTS primitive is skipped");
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("/meshes/0/primitives/2")),
        "{:?}",
        scene.warnings
    );
    for s in &scene.surfaces {
        assert_eq!(s.triangles.len(), 2, "{}", s.source_path);
        let mut area = 0.0;
        for &t in &s.triangles {
            assert_close(geometric_normal(&s.positions, t), DVec3::Z, &s.source_path);
            let [a, b, c] = t.map(|i| s.positions[i as usize]);
            area += 0.5 * (b - a).cross(c - a).length();
        }
        assert!((area - 1.0).abs() < 1e-9, "{}: area {area}", s.source_path);
    }
    assert_eq!(scene.surfaces[1].primitive, 1);
}

#[test]
fn external_bin_data_uri_and_glb_agree() {
    let dir = tempfile::tempdir().unwrap();
    let b = triangle_builder();
    let external = b.write_gltf(dir.path(), "ext.gltf", Bin::External("ext%20data.bin"));
    // The URI is percent-encoded; the file on disk has a space.
    std::fs::rename(
        dir.path().join("ext%20data.bin"),
        dir.path().join("ext data.bin"),
    )
    .unwrap();
    let data_uri = b.write_gltf(dir.path(), "data.gltf", Bin::DataUri);
    let glb = b.write_glb(dir.path(), "bin.GLB");
    let scenes = [load_ok(&external), load_ok(&data_uri), load_ok(&glb)];
    for scene in &scenes {
        let s = &scene.surfaces[0];
        for (p, q) in s.positions.iter().zip(TRIANGLE) {
            assert_close(
                *p,
                DVec3::new(q[0] as f64, q[1] as f64, q[2] as f64),
                "position",
            );
        }
    }
    let canonical = |p: &Path| p.canonicalize().unwrap();
    assert_eq!(
        scenes[0].input_files,
        vec![
            canonical(&external),
            canonical(&dir.path().join("ext data.bin"))
        ]
    );
    assert_eq!(scenes[1].input_files, vec![canonical(&data_uri)]);
    assert_eq!(scenes[2].input_files, vec![canonical(&glb)]);
}

#[test]
fn sparse_accessor_overrides_base_values() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let base = b.vec3s(&TRIANGLE);
    let indices_view = b.view(&1u16.to_le_bytes());
    let values: Vec<u8> = [5.0f32, 0.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let values_view = b.view(&values);
    b.json["accessors"][base]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": indices_view, "componentType": UNSIGNED_SHORT},
        "values": {"bufferView": values_view}
    });
    // A second accessor with no bufferView at all: zeros plus the sparse value.
    let viewless = b.accessor(json!({"componentType": FLOAT, "count": 3, "type": "VEC3",
        "sparse": {"count": 1,
            "indices": {"bufferView": indices_view, "componentType": UNSIGNED_SHORT},
            "values": {"bufferView": values_view}}}));
    let mesh = b.mesh(vec![
        json!({"attributes": {"POSITION": base}}),
        json!({"attributes": {"POSITION": viewless}}),
    ]);
    b.node(json!({"mesh": mesh}));
    let scene = load_ok(&b.write_gltf(dir.path(), "sparse.gltf", Bin::DataUri));
    let p = &scene.surfaces[0].positions;
    assert_close(p[0], DVec3::ZERO, "untouched vertex 0");
    assert_close(p[1], DVec3::new(5.0, 0.0, 0.0), "sparse vertex 1");
    assert_close(p[2], DVec3::Y, "untouched vertex 2");
    // The view-less accessor gives (0,0,0), (5,0,0), (0,0,0): a triangle without area, dropped
    // with a warning (tests/hostile_input.rs reads a view-less sparse POSITION with area).
    assert_eq!(scene.surfaces.len(), 1);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("/meshes/0/primitives/1")
                && w.contains("none of its 1 triangles has an area")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn scene_choice_default_first_or_all_roots() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let mesh = b.simple_mesh(&TRIANGLE, None, None, None);
    b.node(json!({"mesh": mesh, "name": "a"}));
    b.node(json!({"mesh": mesh, "name": "b", "translation": [0, 0, 7]}));
    b.set(
        "scenes",
        json!([{"name": "first", "nodes": [0]},
               {"name": "second", "nodes": [1], "extras": {"k": 1}}]),
    );
    b.set("scene", json!(1));
    let scene = load_ok(&b.write_gltf(dir.path(), "s1.gltf", Bin::DataUri));
    assert_eq!(scene.name.as_deref(), Some("second"));
    assert_eq!(scene.roots, vec![1]);
    assert_eq!(scene.extras, Some(json!({"k": 1})));
    assert_eq!(scene.surfaces.len(), 1);
    assert_eq!(scene.surfaces[0].node, 1);
    assert_close(
        scene.surfaces[0].positions[0],
        DVec3::new(0.0, 0.0, 7.0),
        "node b",
    );
    assert_eq!(scene.nodes.len(), 2, "all nodes are kept");
    assert!(scene.nodes[0].surfaces.is_empty());

    b.json.as_object_mut().unwrap().remove("scene");
    let scene = load_ok(&b.write_gltf(dir.path(), "s0.gltf", Bin::DataUri));
    assert_eq!(scene.name.as_deref(), Some("first"));
    assert_eq!(scene.surfaces.len(), 1);
    assert_eq!(scene.surfaces[0].node, 0);

    b.json.as_object_mut().unwrap().remove("scenes");
    let scene = load_ok(&b.write_gltf(dir.path(), "none.gltf", Bin::DataUri));
    assert_eq!(scene.name, None);
    assert_eq!(scene.roots, vec![0, 1]);
    assert_eq!(scene.surfaces.len(), 2);
}

#[test]
fn a_scene_without_nodes_is_valid() {
    // glTF 2.0 makes a scene's `nodes` optional (Blender writes an empty scene so).
    let dir = tempfile::tempdir().unwrap();
    let mut b = Builder::new();
    let mesh = b.simple_mesh(&TRIANGLE, None, None, None);
    b.node(json!({"mesh": mesh, "name": "a"}));
    b.set(
        "scenes",
        json!([{"name": "lit", "nodes": [0]}, {"name": "empty"}]),
    );
    let scene = load_ok(&b.write_gltf(dir.path(), "two.gltf", Bin::DataUri));
    assert_eq!(scene.name.as_deref(), Some("lit"));
    assert_eq!(scene.surfaces.len(), 1);
    // The empty scene chosen: nothing in it, not a parse error.
    b.set("scene", json!(1));
    let scene = load_ok(&b.write_gltf(dir.path(), "empty.gltf", Bin::DataUri));
    assert_eq!(scene.name.as_deref(), Some("empty"));
    assert!(scene.roots.is_empty() && scene.surfaces.is_empty());
}

#[test]
fn cameras_and_extras_are_kept_verbatim() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    let camera = json!({"type": "perspective", "name": "eye",
        "perspective": {"yfov": 0.8, "znear": 0.1}, "extras": {"x": [1, 2]}});
    b.set("cameras", json!([camera.clone()]));
    b.node(json!({"camera": 0, "extras": {"probe": true, "nested": {"a": 1.5}}}));
    b.json["scenes"][0]["nodes"] = json!([0, 1]);
    let scene = load_ok(&b.write_gltf(dir.path(), "cam.gltf", Bin::DataUri));
    assert_eq!(scene.cameras, vec![camera]);
    assert_eq!(scene.nodes[1].camera, Some(0));
    assert_eq!(
        scene.nodes[1].extras,
        Some(json!({"probe": true, "nested": {"a": 1.5}}))
    );
}

#[test]
fn hierarchy_cycles_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mut b = triangle_builder();
    b.json["nodes"][0]["children"] = json!([1]);
    b.node(json!({"children": [0]}));
    b.set("scenes", json!([{"nodes": []}]));
    let (at, message) = load_err(&b.write_gltf(dir.path(), "cycle.gltf", Bin::DataUri));
    assert!(at.starts_with("/nodes/"), "{message}");
    assert!(message.contains("cycle"), "{message}");
}
