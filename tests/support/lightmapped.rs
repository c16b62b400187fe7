//! The exporter fixture (`fixture.rs`) with lightmaps, values known texel by texel:
//! - the Panel (surface 0, material 0 "Textured") is laid out in the left half of atlas 0
//!   (8 × 4 texels): its `uv1` is (x/2, 1 − y) of the local quad, so its local +Y edge is row 0;
//! - the Divider's back side (surface 1, material 1 "TwoSided") fills atlas 1 (4 × 2 texels) and
//!   has no `uv0` (its TEXCOORD_0 must then be the layout too); its front keeps vertex colours.
//!   Material 1's base colour is 0.5 (reflectance 0.5, as the bake used).
//!
//! Atlas k, texel (col, row), i = row·W + col: luminance [col + 0.5, 10·row + 0.25, 100k + i]
//! cd/m², illuminance 100·col + row + 1000k lx, direct half of it, area 1.5/16 m² where a surface
//! is (0 for the right half of atlas 0: padding), display [col/(W−1), row/(H−1), 0.5].

use super::fixture;
use glam::DVec2;
use luxbake::result::{Atlas, BakeResult, Lightmaps, Side};
use luxbake::scene::Scene;

pub const SIZES: [(u32, u32); 2] = [(8, 4), (4, 2)];
pub const TEXEL_SIZE: f64 = 0.25;

/// Atlas `k` with the values above.
pub fn atlas(k: usize) -> Atlas {
    let (w, h) = SIZES[k];
    let mut a = Atlas::new(w, h);
    for row in 0..h {
        for col in 0..w {
            let i = (row * w + col) as usize;
            let (c, r) = (col as f32, row as f32);
            a.luminance[i] = [c + 0.5, 10.0 * r + 0.25, 100.0 * k as f32 + i as f32];
            a.illuminance[i] = 100.0 * c + r + 1000.0 * k as f32;
            a.illuminance_direct[i] = a.illuminance[i] / 2.0;
            a.area[i] = if k == 0 && col >= w / 2 {
                0.0
            } else {
                1.5 / 16.0
            };
            a.display[i] = [c / (w - 1) as f32, r / (h - 1) as f32, 0.5];
        }
    }
    a
}

/// The fixture scene and its bake result with two atlases.
pub fn scene() -> (Scene, BakeResult) {
    let (mut scene, mut result) = fixture::scene();
    // Base colour 1 would read back as reflectance 1 (refused) from the unlit material written
    // for the Divider's front.
    scene.materials[1].display.base_color_factor = [0.5, 0.5, 0.5, 1.0];
    // Local quad corners (0,0), (1,0), (1,1), (0,1): uv0 is (x, 1 − y).
    let panel = &mut result.surfaces[0];
    let uv0 = panel.uv0.clone().unwrap();
    panel.uv1 = Some(uv0.iter().map(|uv| DVec2::new(uv.x / 2.0, uv.y)).collect());
    panel.lightmap = Some(0);
    let back = &mut result.surfaces[2];
    assert_eq!(back.side, Side::Back);
    back.uv1 = back.uv0.take();
    back.lightmap = Some(1);
    result.lightmaps = Some(Lightmaps {
        texel_size: TEXEL_SIZE,
        atlases: vec![atlas(0), atlas(1)],
    });
    result.summary.tool = "luxbake test".into();
    result.summary.exposure.white_illuminance_lx = 400.0;
    result.summary.exposure.rule = "COLOR_0 = shoulder(E_rgb / whiteIlluminanceLx)".into();
    (scene, result)
}
