//! Integration tests of the OBJ/MTL importer through `luxbake::import::load`.

mod common;

use common::*;
use glam::{DVec2, DVec3};
use luxbake::import::{ImportOptions, UpAxis, load};
use luxbake::scene::{EmissionAmount, ReflectanceSource, Scene, TextureRef};
use std::path::Path;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn load_up(path: &Path, up: UpAxis) -> Scene {
    load(path, &ImportOptions { obj_up: up }).unwrap_or_else(|e| panic!("{e}"))
}

const TRI: &str = "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nf 1/1 2/1 3/1\n";

#[test]
fn z_up_maps_to_y_up() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "tri.OBJ", TRI);

    let scene = load_up(&path, UpAxis::Y);
    let s = &scene.surfaces[0];
    assert_close(s.positions[2], DVec3::Y, "Y-up keeps coordinates");
    assert_close(s.normals[0], DVec3::Z, "flat normal");

    let scene = load_up(&path, UpAxis::Z);
    let s = &scene.surfaces[0];
    // (x, y, z) ↦ (x, z, −y): the file's +Y axis becomes −Z, its +Z (up) becomes +Y.
    assert_close(s.positions[1], DVec3::X, "x kept");
    assert_close(s.positions[2], DVec3::NEG_Z, "file +Y → −Z");
    for n in &s.normals {
        assert_close(*n, DVec3::Y, "a floor facing up in the file faces +Y");
    }
    assert_close(
        geometric_normal(&s.positions, s.triangles[0]),
        DVec3::Y,
        "winding kept",
    );
    // OBJ's v runs up, glTF's down.
    assert_eq!(s.uv0.as_ref().unwrap()[0], DVec2::new(0.25, 0.25));
    assert_eq!(scene.nodes[0].name.as_deref(), Some("tri"));
    assert_eq!(scene.roots, vec![0]);
}

#[test]
fn file_normals_are_used_and_mapped() {
    let dir = tempfile::tempdir().unwrap();
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nf 1//1 2//1 3//1\n";
    let path = write(dir.path(), "n.obj", obj);
    let scene = load_up(&path, UpAxis::Z);
    for n in &scene.surfaces[0].normals {
        assert_close(*n, DVec3::Y, "normalised, Z-up mapped");
    }
    assert_eq!(scene.surfaces[0].positions.len(), 3, "shared vertices kept");
}

#[test]
fn kd_and_ke_with_objects_and_materials() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "room.mtl",
        "newmtl wood\nKd 0.5 0.4 0.3\n\nnewmtl lamp\nKd 0.1 0.1 0.1\nKe 10 5 0\n\
         \nnewmtl glow\nKd 0.2 0.2 0.2\nKe 0.5 0.5 0.5\n",
    );
    let obj = "mtllib room.mtl\n\
        v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
        o desk\nusemtl wood\nf 1 2 3\nusemtl lamp\nf 2 4 3\nusemtl wood\nf 1 2 4\n\
        o floor\nusemtl glow\nf 1 2 3 4\n";
    let path = write(dir.path(), "room.obj", obj);
    let scene = load_up(&path, UpAxis::Y);

    let names: Vec<_> = scene
        .nodes
        .iter()
        .map(|n| n.name.clone().unwrap())
        .collect();
    assert_eq!(names, ["desk", "floor"]);
    assert_eq!(
        scene.nodes[0].surfaces,
        vec![0, 1],
        "one surface per material used"
    );
    let desk_wood = &scene.surfaces[0];
    assert_eq!(desk_wood.triangles.len(), 2, "both wood parts merged");
    assert_eq!(
        desk_wood.source_path,
        "room.obj: object 'desk', material 'wood'"
    );
    assert_eq!(scene.surfaces[2].triangles.len(), 2, "quad triangulated");

    let m = &scene.materials;
    assert_eq!(m.len(), 3, "no default material needed");
    assert_eq!(scene.surfaces[1].material, 1);
    assert_close(m[0].reflectance, DVec3::new(0.5, 0.4, 0.3), "Kd");
    assert_eq!(m[0].reflectance_source, ReflectanceSource::MtlKd);
    assert_eq!(m[0].source_path, "room.mtl: material 'wood'");
    assert!(!m[0].double_sided);
    assert!(m[0].emission.is_none());
    let d = &m[0].display;
    assert_close(
        DVec3::new(
            d.base_color_factor[0],
            d.base_color_factor[1],
            d.base_color_factor[2],
        ),
        DVec3::new(0.5, 0.4, 0.3),
        "display base colour",
    );
    assert_eq!((d.metallic_factor, d.roughness_factor), (0.0, 1.0));

    // Ke (10, 5, 0): luminance Y = 10·0.2126 + 5·0.7152 = 5.702 cd/m².
    let e = m[1].emission.unwrap();
    let EmissionAmount::Luminance(l) = e.amount else {
        panic!("luminance expected");
    };
    assert_near(l, 5.702, "Y(Ke)");
    assert_close(
        e.color,
        DVec3::new(10.0, 5.0, 0.0) / 5.702,
        "colour normalised",
    );
    assert_eq!(m[1].display.emissive_factor, [1.0, 0.5, 0.0]);
    assert_eq!(m[1].display.emissive_strength, Some(10.0));

    let e = m[2].emission.unwrap();
    assert_eq!(e.amount, EmissionAmount::Luminance(0.5));
    assert_eq!(m[2].display.emissive_factor, [0.5, 0.5, 0.5]);
    assert_eq!(
        m[2].display.emissive_strength, None,
        "already within [0, 1]"
    );

    let canonical = |n: &str| dir.path().join(n).canonicalize().unwrap();
    assert_eq!(
        scene.input_files,
        vec![canonical("room.obj"), canonical("room.mtl")]
    );
}

#[test]
fn map_kd_texture_mean_scales_kd() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("maps")).unwrap();
    let png = png(2, 2, |x, _| if x == 0 { [255, 0, 0] } else { [0, 0, 255] });
    std::fs::write(dir.path().join("maps/paint.png"), &png).unwrap();
    write(
        dir.path(),
        "maps/m.mtl",
        "newmtl painted\nKd 0.8 0.8 0.8\nmap_Kd -s 1 1 1 paint.png\n",
    );
    let path = write(
        dir.path(),
        "t.obj",
        &format!("mtllib maps/m.mtl\nusemtl painted\n{TRI}"),
    );
    let scene = load_up(&path, UpAxis::Y);
    let m = &scene.materials[0];
    assert_close(
        m.reflectance,
        DVec3::new(0.4, 0.0, 0.4),
        "Kd × mean(map_Kd)",
    );
    assert_eq!(
        m.display.base_color_texture,
        Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            scale: 1.0
        })
    );
    assert_eq!(scene.images[0].bytes, png);
    assert_eq!(scene.images[0].mime_type, "image/png");
    assert_eq!(scene.textures[0].image, 0);
    let png_path = dir.path().join("maps/paint.png").canonicalize().unwrap();
    assert!(scene.input_files.contains(&png_path));
}

#[test]
fn mtllib_outside_the_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("inner")).unwrap();
    write(dir.path(), "outside.mtl", "newmtl x\nKd 0.5 0.5 0.5\n");
    let path = write(
        &dir.path().join("inner"),
        "s.obj",
        &format!("mtllib ../outside.mtl\nusemtl x\n{TRI}"),
    );
    let e = load(&path, &ImportOptions::default()).unwrap_err();
    let luxbake::Error::Input { at, message, .. } = &e else {
        panic!("{e}");
    };
    assert_eq!(at, "mtllib '../outside.mtl'");
    assert!(message.contains("outside the folder"), "{e}");
}

#[test]
fn missing_mtl_warns_and_uses_the_default_material() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "m.obj",
        &format!("mtllib nothere.mtl\nusemtl wood\n{TRI}"),
    );
    let scene = load_up(&path, UpAxis::Y);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("nothere.mtl") && w.contains("missing")),
        "{:?}",
        scene.warnings
    );
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(
        scene.materials[0].reflectance_source,
        ReflectanceSource::Default
    );
    assert_close(scene.materials[0].reflectance, DVec3::splat(0.5), "default");
    assert_eq!(scene.surfaces[0].material, 0);
}

#[test]
fn kd_at_or_above_one_is_an_error_naming_the_mtl_material() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = write(dir.path(), "bad.mtl", "newmtl wall\nKd 1.2 0.5 0.5\n");
    let path = write(
        dir.path(),
        "b.obj",
        &format!("mtllib bad.mtl\nusemtl wall\n{TRI}"),
    );
    let e = load(&path, &ImportOptions::default()).unwrap_err();
    let shown = e.to_string();
    let luxbake::Error::Input { file, at, message } = e else {
        panic!("{shown}");
    };
    assert_eq!(file, mtl.canonicalize().unwrap());
    assert_eq!(at, "material 'wall'");
    assert!(
        message.contains("reflectance 1.2 ≥ 1") && message.contains("Kd"),
        "{shown}"
    );
    assert!(shown.contains("bad.mtl: material 'wall': "), "{shown}");
}

#[test]
fn non_finite_vertex_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "nan.obj",
        "o bad\nv 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let e = load(&path, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("nan.obj: object 'bad'") && e.contains("not finite"),
        "{e}"
    );
}
