//! Luminance images of a finished bake seen through a pinhole camera (`bake view`).
//!
//! Radiosity is view-independent, so a view is a read of the baked solution: per pixel, rays
//! from the camera ([`camera`]) to the first front-facing baked surface ([`surfaces`]: its
//! lightmap, else its interpolated vertex values), or to a luminaire opening in front of it
//! ([`luminaires`]), averaged over fixed antialiasing offsets ([`render`]).
//!
//! Input: a [`BakedOutput`] and the same output imported as a [`Scene`] (for its luminaires and
//! the images of its display textures), a [`Camera`], [`ViewOptions`]. Output: a [`View`]: per
//! pixel (row 0 at the top) luminance RGB and Y (cd/m²), illuminance of the surface seen (lx,
//! NaN where no ray hit one) and, when asked, the display colour a glTF viewer shows (sRGB
//! bytes). Invariants: deterministic (same bytes whatever the thread count); only baked
//! primitives are drawn (probe glyphs and other unbaked meshes are not).

pub mod camera;
pub mod luminaires;
pub mod render;
pub mod surfaces;

pub use camera::Camera;

use crate::readback::BakedOutput;
use crate::scene::{Scene, luma};
use crate::{Error, Result};
use glam::DVec3;
use luminaires::Openings;
use surfaces::{DisplayTexture, Surfaces};

/// Largest antialiasing sample count per pixel.
pub const MAX_SAMPLES: u32 = 256;

#[derive(Debug, Clone, Copy)]
pub struct ViewOptions {
    /// Rays per pixel (1: the centre only; 4: rotated grid).
    pub samples: u32,
    /// Also compute the display colours (`--display`).
    pub display: bool,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            samples: 4,
            display: false,
        }
    }
}

/// A rendered view.
pub struct View {
    pub camera: Camera,
    pub samples: u32,
    pub pixels: Vec<render::Pixel>,
    /// The eye seems to be inside a solid (every test direction meets a back face first).
    pub inside_solid: bool,
}

impl View {
    /// Luminance RGB per pixel (cd/m²).
    pub fn rgb(&self) -> Vec<[f32; 3]> {
        self.pixels.iter().map(|p| p.luminance).collect()
    }

    /// Luminance Y per pixel (cd/m²).
    pub fn luminance(&self) -> Vec<f32> {
        (self.pixels.iter())
            .map(|p| luma(DVec3::from_array(p.luminance.map(f64::from))) as f32)
            .collect()
    }

    /// Illuminance of the surface seen per pixel (lx; NaN where none).
    pub fn illuminance(&self) -> Vec<f32> {
        self.pixels.iter().map(|p| p.illuminance).collect()
    }

    /// Display colours (sRGB bytes), when rendered with `display`.
    pub fn display(&self) -> Vec<[u8; 3]> {
        self.pixels.iter().map(|p| p.display).collect()
    }
}

/// Check a sample count: 1, 4, 9, 16, … 256 (a square, at most [`MAX_SAMPLES`]).
pub fn check_samples(n: u32) -> Result<()> {
    match camera::valid_samples(n) && n <= MAX_SAMPLES {
        true => Ok(()),
        false => Err(Error::Settings(format!(
            "--samples {n}: must be 1, 4 or a square up to {MAX_SAMPLES} (9, 16, 25, …)"
        ))),
    }
}

/// The camera node named `name`; an unknown name is an error listing the cameras there are.
pub fn named_camera(
    baked: &BakedOutput,
    name: &str,
    size: Option<(u32, u32)>,
    near: Option<f64>,
) -> Result<Camera> {
    match baked
        .cameras
        .iter()
        .find(|c| c.name.as_deref() == Some(name))
    {
        Some(c) => Camera::from_node(c, size, near),
        None => {
            let names: Vec<String> = (baked.cameras.iter())
                .map(|c| c.name.clone().unwrap_or_else(|| format!("node {}", c.node)))
                .collect();
            let list = match names.is_empty() {
                true => "it has no camera nodes".to_string(),
                false => format!("its cameras are: {}", names.join(", ")),
            };
            Err(Error::Settings(format!(
                "no camera named \"{name}\" in {}: {list}",
                baked.file.display()
            )))
        }
    }
}

/// Render `readback` (imported again as `scene`) from `camera`.
pub fn render(
    baked: &BakedOutput,
    scene: &Scene,
    camera: &Camera,
    options: &ViewOptions,
) -> Result<View> {
    check_samples(options.samples)?;
    let textures = match options.display {
        true => display_textures(baked, scene)?,
        false => Vec::new(),
    };
    let surfaces = Surfaces::new(baked, textures);
    let openings = Openings::new(scene);
    let pixels = render::trace(
        camera,
        &surfaces,
        &openings,
        options.samples,
        options.display,
        surfaces.epsilon(),
    );
    Ok(View {
        camera: *camera,
        samples: options.samples,
        pixels,
        inside_solid: render::inside_solid(&surfaces, camera.eye),
    })
}

/// The textures the materials' `emissiveTexture` name (the lightmaps' display textures),
/// decoded; `None` for the others.
fn display_textures(baked: &BakedOutput, scene: &Scene) -> Result<Vec<Option<DisplayTexture>>> {
    let mut out: Vec<Option<DisplayTexture>> = (0..scene.textures.len()).map(|_| None).collect();
    for m in &baked.materials {
        let Some((t, _)) = m.look.emissive_texture else {
            continue;
        };
        if t >= out.len() || out[t].is_some() {
            continue;
        }
        let image = scene.textures[t].image;
        let (w, h, texels) = crate::import::decode_rgb8(&scene.images[image].bytes)
            .map_err(|m| Error::input(&baked.file, format!("/images/{image}"), m))?;
        out[t] = Some(DisplayTexture::from_srgb8(w, h, &texels));
    }
    Ok(out)
}
