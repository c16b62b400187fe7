//! `bake view LIT.gltf|.glb -o VIEW.exr|VIEW.png [--camera NAME | --eye X,Y,Z --target X,Y,Z [--up X,Y,Z]
//! --fov DEG] [--size WxH] [--near M] [--samples N] [--threads N] [--png OUT.png]
//! [--false-colour OUT.png [--quantity luminance|illuminance] [--scale auto|LO:HI] [--log]
//! [--steps N] [--contours]] [--display OUT.png]`: a luminance image of a finished bake.
//!
//! Each output's format follows its extension (`-o`: .exr luminance or .png tone mapped; the
//! pictures: .png), else the run is refused before any work (`super::formats`).
//! Every output path is checked against the files the bake is made of before any work; all
//! outputs are written together at the end (atomically). A camera that seems to be inside a
//! solid is a warning on stderr.

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use glam::DVec3;
use luxbake::Error;
use luxbake::export::{self, ViewImage};
use luxbake::import::{self, ImportOptions};
use luxbake::picture::{Rgb8Image, legend, scale::ColourScale, tonemap};
use luxbake::view::{self, Camera, ViewOptions, camera};
use std::path::{Path, PathBuf};

/// Render a luminance image (EXR, cd/m²) of a luxbake output from a camera.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// A glTF written by bake (.gltf or .glb).
    file: PathBuf,
    /// The image to write, its format by its extension: .exr (R, G, B and luminance in cd/m²)
    /// or .png (tone mapped for the adapted eye, as --png).
    #[arg(short, long, value_name = "VIEW.exr|VIEW.png")]
    output: PathBuf,
    /// A glTF camera node of the file, by name (perspective).
    #[arg(long, value_name = "NAME", conflicts_with_all = ["eye", "target", "up", "fov"])]
    camera: Option<String>,
    /// Eye position (m, glTF axes, +Y up).
    #[arg(long, value_name = "X,Y,Z", requires = "target")]
    eye: Option<String>,
    /// The point looked at (m).
    #[arg(long, value_name = "X,Y,Z", requires = "eye")]
    target: Option<String>,
    /// Up direction of the image [default: 0,1,0].
    #[arg(long, value_name = "X,Y,Z")]
    up: Option<String>,
    /// Vertical field of view (degrees) [default: 60].
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    fov: Option<f64>,
    /// Image size in pixels [default: 1280x720, or 1280 wide at a camera's aspect ratio].
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Rays start this far in front of the eye (m) [default: the camera's znear, or 0].
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    near: Option<f64>,
    /// Antialiasing rays per pixel: 1 (the centre only), 4 (rotated grid) or a square (9, 16, …
    /// 256: a regular grid).
    #[arg(long, value_name = "N", default_value_t = 4)]
    samples: u32,
    /// Worker threads (default: all cores); the image does not depend on it.
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Write the EXR ZIP-compressed (lossless, smaller, slower to write).
    #[arg(long)]
    zip: bool,
    /// Also write the view tone mapped for the adapted eye (histogram adjustment), sRGB PNG.
    #[arg(long, value_name = "OUT.png")]
    png: Option<PathBuf>,
    /// Also write a false-colour PNG with a legend.
    #[arg(
        long = "false-colour",
        visible_alias = "false-color",
        value_name = "OUT.png"
    )]
    false_colour: Option<PathBuf>,
    /// What the false colours show: luminance (cd/m²) or the illuminance of the surface seen (lx).
    #[arg(long, value_enum, default_value_t = Quantity::Luminance)]
    quantity: Quantity,
    /// False-colour range: 'auto' (a round range) or LO:HI.
    #[arg(long, value_name = "auto|LO:HI", default_value = "auto")]
    scale: String,
    /// Logarithmic false-colour scale.
    #[arg(long)]
    log: bool,
    /// False colours in this many bands (0: smooth; at most 64).
    #[arg(long, value_name = "N", default_value_t = 0,
          value_parser = clap::value_parser!(u32).range(0..=64))]
    steps: u32,
    /// Draw contour lines between the bands.
    #[arg(long)]
    contours: bool,
    /// Also write what a glTF viewer shows with the bake's unlit materials (COLOR_0, lightmap
    /// display textures), sRGB PNG.
    #[arg(long, value_name = "OUT.png")]
    display: Option<PathBuf>,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq)]
pub enum Quantity {
    Luminance,
    Illuminance,
}

fn usage(message: String) -> anyhow::Error {
    Error::Settings(message).into()
}

/// `X,Y,Z` as a vector.
fn vector(option: &str, s: &str) -> Result<DVec3> {
    let parts: Vec<Option<f64>> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect();
    match parts.as_slice() {
        [Some(x), Some(y), Some(z)] => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(usage(format!(
            "--{option} {s}: three finite numbers X,Y,Z are expected"
        ))),
    }
}

/// `WxH` as a checked size.
fn size(s: &str) -> Result<(u32, u32)> {
    let bad = || {
        usage(format!(
            "--size {s}: WxH in pixels is expected, e.g. 1280x720"
        ))
    };
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    camera::check_size(w, h)?;
    Ok((w, h))
}

/// The false-colour scale of `values`.
fn colour_scale(args: &ViewArgs, values: &[f64]) -> Result<ColourScale> {
    if args.scale == "auto" {
        // The 2nd–98th percentiles set it: a few pixels that see almost nothing (a
        // luminaire's back, a grazing edge) or the sources themselves do not stretch it.
        return Ok(ColourScale::auto(values, args.log, args.steps));
    }
    let bad = |m: String| usage(format!("--scale {}: {m}", args.scale));
    let (lo, hi) = args
        .scale
        .split_once(':')
        .ok_or_else(|| bad("'auto' or LO:HI is expected".into()))?;
    let number = |v: &str| {
        v.trim()
            .parse::<f64>()
            .map_err(|_| bad(format!("'{v}' is not a number")))
    };
    ColourScale::fixed(number(lo)?, number(hi)?, args.log, args.steps).map_err(bad)
}

/// The camera the arguments describe.
fn camera_of(args: &ViewArgs, baked: &luxbake::readback::BakedOutput) -> Result<Camera> {
    let size = args.size.as_deref().map(size).transpose()?;
    if let Some(name) = &args.camera {
        return Ok(view::named_camera(baked, name, size, args.near)?);
    }
    let (Some(eye), Some(target)) = (&args.eye, &args.target) else {
        return Err(usage(
            "a view needs --camera NAME or --eye X,Y,Z --target X,Y,Z".into(),
        ));
    };
    let up = args
        .up
        .as_deref()
        .map_or(Ok(DVec3::Y), |u| vector("up", u))?;
    Ok(Camera::look_at(
        vector("eye", eye)?,
        vector("target", target)?,
        up,
        args.fov.unwrap_or(60.0),
        size.unwrap_or((camera::DEFAULT_WIDTH, camera::DEFAULT_HEIGHT)),
        args.near.unwrap_or(0.0),
    )?)
}

/// The camera as the EXR header records it (JSON, ASCII).
fn camera_text(c: &Camera, samples: u32) -> String {
    let v = |p: DVec3| [p.x, p.y, p.z];
    export::ascii_json(&serde_json::json!({
        "eye": v(c.eye),
        "forward": v(c.forward),
        "up": v(c.up),
        "target": v(c.target()),
        "yfovDeg": c.yfov.to_degrees(),
        "width": c.width,
        "height": c.height,
        "near": c.near,
        "samplesPerPixel": samples,
        "axes": "glTF, +Y up, m; image row 0 at the top",
    }))
}

pub fn run(args: &ViewArgs) -> Result<()> {
    view::check_samples(args.samples)?;
    if let Some(near) = args.near
        && !(near.is_finite() && near >= 0.0)
    {
        return Err(Error::Settings(format!("--near {near}: a distance ≥ 0 m is expected")).into());
    }
    if let Some(s) = &args.size {
        size(s)?;
    }
    if args.scale != "auto" {
        colour_scale(args, &[])?;
    }
    let outputs: Vec<&Path> = [
        Some(&args.output),
        args.png.as_ref(),
        args.false_colour.as_ref(),
        args.display.as_ref(),
    ]
    .into_iter()
    .flatten()
    .map(PathBuf::as_path)
    .collect();
    export::check_files(&[&args.file], &outputs)?;
    let main = super::formats::extension(
        &args.output,
        "-o",
        &["exr", "png"],
        "a view (.exr: luminance in cd/m²; .png: tone mapped as --png)",
    )?;
    let pngs = [
        ("--png", &args.png),
        ("--false-colour", &args.false_colour),
        ("--display", &args.display),
    ];
    for (flag, path) in pngs {
        if let Some(path) = path {
            super::formats::extension(path, flag, &["png"], "this picture")?;
        }
    }
    let baked = luxbake::readback::read(&args.file)?;
    if baked.summary.is_none() {
        return Err(Error::input(
            &args.file,
            "/scenes/0/extras/luxbake",
            "not a luxbake output: no run summary",
        )
        .into());
    }
    let camera = camera_of(args, &baked)?;
    let scene = import::load(&args.file, &ImportOptions::default())?;
    let inputs: Vec<&Path> = (scene.input_files.iter())
        .chain(&baked.resources)
        .map(PathBuf::as_path)
        .collect();
    export::check_files(&inputs, &outputs)?;

    let threads = args.threads.unwrap_or(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start worker threads")?;
    let options = ViewOptions {
        samples: args.samples,
        display: args.display.is_some(),
    };
    let v = pool.install(|| view::render(&baked, &scene, &camera, &options))?;
    if v.inside_solid {
        eprintln!(
            "warning: the camera at ({}, {}, {}) m seems to be inside a solid: every direction \
             from it meets the back of a surface first",
            v.camera.eye.x, v.camera.eye.y, v.camera.eye.z
        );
    }
    let (w, h) = (camera.width, camera.height);
    let rgb = v.rgb();
    let luminance = v.luminance();
    let exr = export::encode_view(&ViewImage {
        width: w,
        height: h,
        rgb: &rgb,
        luminance: &luminance,
        zip: args.zip,
        texts: vec![
            ("luxbake.camera".into(), camera_text(&camera, args.samples)),
            (
                "luxbake.tool".into(),
                concat!("luxbake ", env!("CARGO_PKG_VERSION")).into(),
            ),
            (
                "luxbake.units".into(),
                r#"{"R":"cd/m2","G":"cd/m2","B":"cd/m2","luminance":"cd/m2"}"#.into(),
            ),
        ],
    })
    .map_err(|m| Error::output(&args.output, m))?;
    let png = |path: &Path, img: &Rgb8Image| -> Result<Vec<u8>> {
        Ok(export::display::png_rgb8(img).map_err(|m| Error::output(path, m))?)
    };
    let tone_mapped = || tonemap::histogram_adjustment(&rgb, w, h, camera.yfov.to_degrees());
    let mut files: Vec<(&Path, Vec<u8>)> = match main.as_str() {
        "png" => vec![(&args.output, png(&args.output, &tone_mapped().image)?)],
        _ => vec![(&args.output, exr)],
    };
    if let Some(path) = &args.png {
        files.push((path, png(path, &tone_mapped().image)?));
    }
    if let Some(path) = &args.false_colour {
        let (values, unit): (Vec<f64>, &str) = match args.quantity {
            Quantity::Luminance => (luminance.iter().map(|&y| y as f64).collect(), "cd/m²"),
            Quantity::Illuminance => (v.illuminance().iter().map(|&e| e as f64).collect(), "lx"),
        };
        let scale = colour_scale(args, &values)?;
        let img = legend::false_colour(&values, w, h, &scale, unit, args.contours);
        files.push((path, png(path, &img)?));
    }
    if let Some(path) = &args.display {
        let img = Rgb8Image {
            width: w,
            height: h,
            pixels: v.display(),
        };
        files.push((path, png(path, &img)?));
    }
    let refs: Vec<(&Path, &[u8])> = files.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    export::atomic::write_atomic_all(&refs)?;
    Ok(())
}
