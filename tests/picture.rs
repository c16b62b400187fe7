//! `luxbake::picture` end to end: tone mapping (Ward Larson et al. 1997 histogram adjustment)
//! against its defining properties, false-colour images with legends and contours, all written
//! as PNG through `export::display::png_rgb8` into a temporary folder (or into
//! `$LUXBAKE_PICTURE_DIR` when set, to look at them).

mod support;

use luxbake::export::display::png_rgb8;
use luxbake::picture::contours::isolines;
use luxbake::picture::legend::false_colour;
use luxbake::picture::scale::ColourScale;
use luxbake::picture::tonemap::{
    BINS, LD_MAX, LD_MIN, TOLERANCE, ToneCurve, foveal, histogram_adjustment, tone_curve, tvi,
};
use luxbake::picture::{Rgb8Image, srgb8};
use std::path::PathBuf;

/// Where the PNGs go: `$LUXBAKE_PICTURE_DIR`, else a temporary folder kept for the test's life.
fn out_dir() -> (PathBuf, Option<tempfile::TempDir>) {
    match std::env::var_os("LUXBAKE_PICTURE_DIR") {
        Some(d) => {
            std::fs::create_dir_all(&d).unwrap();
            (PathBuf::from(d), None)
        }
        None => {
            let t = tempfile::tempdir().unwrap();
            (t.path().to_path_buf(), Some(t))
        }
    }
}

fn save(img: &Rgb8Image, name: &str) -> Vec<u8> {
    let (dir, _keep) = out_dir();
    let bytes = png_rgb8(img).unwrap();
    std::fs::write(dir.join(name), &bytes).unwrap();
    bytes
}

fn grey(l: f64) -> [f32; 3] {
    [l as f32; 3]
}

/// A log ramp from 10⁻² to 10⁴ cd/m² across 600 columns, 60 rows; with 60° of view that is one
/// pixel per degree, so every pixel is its own foveal sample.
fn hdr_ramp() -> (Vec<[f32; 3]>, u32, u32) {
    let (w, h) = (600u32, 60u32);
    let rgb = (0..w * h)
        .map(|k| grey(10f64.powf(-2.0 + 6.0 * f64::from(k % w) / f64::from(w - 1))))
        .collect();
    (rgb, w, h)
}

/// A synthetic room, 320 × 240, 60° of view: a dark floor and corner (0.05 … 5 cd/m²), walls
/// of 20 … 200 cd/m², a bluish window of 2000 … 8000 cd/m², a reddish luminaire of 2·10⁴
/// cd/m², a checked picture on the wall, and "sky" with no hit (0) in a corner.
fn room() -> (Vec<[f32; 3]>, u32, u32) {
    let (w, h) = (320u32, 240u32);
    let mut rgb = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let (fx, fy) = (f64::from(x) / f64::from(w), f64::from(y) / f64::from(h));
            let c: [f64; 3] = if fx > 0.9 && fy < 0.1 {
                [0.0; 3] // no hit
            } else if (0.45..0.55).contains(&fx) && (0.05..0.09).contains(&fy) {
                [2.4e4, 1.9e4, 1.5e4] // luminaire
            } else if (0.65..0.88).contains(&fx) && (0.2..0.55).contains(&fy) {
                let l = 2000.0 + 6000.0 * (1.0 - fy);
                [0.85 * l, 0.97 * l, 1.25 * l] // window
            } else if (0.15..0.35).contains(&fx) && (0.3..0.5).contains(&fy) {
                let dark = ((x / 8) + (y / 8)) % 2 == 0;
                let l = if dark { 8.0 } else { 90.0 };
                [l * 1.2, l * 0.9, l * 0.6] // a checked picture
            } else if fy > 0.7 {
                let l = 0.05 * 100f64.powf((fy - 0.7) / 0.3) * (0.3 + fx);
                [l * 1.1, l, l * 0.85] // floor, darkening to the front left
            } else {
                let l = 20.0 + 180.0 * (1.0 - (fx - 0.5).abs() * 2.0) * (1.0 - fy);
                [l; 3] // walls
            };
            rgb.push(c.map(|v| v as f32));
        }
    }
    (rgb, w, h)
}

#[test]
fn uniform_image_is_one_grey() {
    for l in [0.02, 1.0, 150.0, 3e4] {
        let rgb = vec![grey(l); 40 * 30];
        let t = histogram_adjustment(&rgb, 40, 30, 50.0);
        let first = t.image.pixels[0];
        assert!(t.image.pixels.iter().all(|&p| p == first), "{l}");
        assert!(first[0] > 0 && first[0] == first[1] && first[1] == first[2]);
        assert!((t.adaptation_cd_m2 - l).abs() < 1e-6 * l);
        // the visibility-matching linear scale: Ld = L · ΔLt(10)/ΔLt(L)
        let ld = l * tvi(10.0) / tvi(l);
        assert_eq!(first[0], srgb8(ld / LD_MAX), "{l}");
    }
    // brighter adaptation in the Weber range keeps the same grey
    let a = histogram_adjustment(&[grey(200.0); 16], 4, 4, 50.0)
        .image
        .pixels[0];
    let b = histogram_adjustment(&[grey(2e4); 16], 4, 4, 50.0)
        .image
        .pixels[0];
    assert_eq!(a, b);
}

#[test]
fn brighter_world_never_darker_display() {
    let (rgb, w, h) = room();
    let (curve, _) = tone_curve(&foveal(&rgb, w, h, 60.0));
    let mut last = 0.0;
    for k in 0..=4000 {
        let lw = 10f64.powf(-3.0 + 8.0 * f64::from(k) / 4000.0);
        let ld = curve.display(lw);
        assert!(ld >= last, "{lw}: {ld} < {last}");
        last = ld;
    }
    // and on the pixels: greys sorted by luminance have non-decreasing bytes
    let t = histogram_adjustment(&rgb, w, h, 60.0);
    let mut greys: Vec<(f32, u8)> = rgb
        .iter()
        .zip(&t.image.pixels)
        .filter(|(c, _)| c[0] == c[1] && c[1] == c[2])
        .map(|(c, p)| (c[0], p[0]))
        .collect();
    greys.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(greys.len() > 10_000);
    assert!(greys.windows(2).all(|p| p[0].1 <= p[1].1));
}

#[test]
fn high_dynamic_range_is_compressed_with_both_ends_visible() {
    let (rgb, w, h) = hdr_ramp();
    let t = histogram_adjustment(&rgb, w, h, 60.0);
    let row: Vec<u8> = (0..w).map(|x| t.image.get(x, 30)[0]).collect();
    // 100 columns per decade: count the distinct greys in the bottom and the top decade
    let levels = |r: &[u8]| {
        let mut v = r.to_vec();
        v.dedup();
        v.len()
    };
    let (bottom, top) = (levels(&row[..100]), levels(&row[500..]));
    eprintln!(
        "greys: bottom decade {bottom} ({} … {}), top decade {top} ({} … {})",
        row[0], row[99], row[500], row[599]
    );
    assert!(bottom >= 10 && top >= 10, "{bottom} and {top} greys");
    assert!(
        row[99] >= row[0] + 15 && row[599] >= row[500] + 15,
        "{row:?}"
    );
    assert_eq!(row[599], 255);
    assert_eq!(row[0], srgb8(LD_MIN / LD_MAX));
    // a linear exposure with 10⁴ white would show the bottom decade black
    assert_eq!(srgb8(0.1 / 1e4), 0);
    assert!(
        (t.adaptation_cd_m2 - 10.0).abs() < 0.1,
        "{}",
        t.adaptation_cd_m2
    );
    save(&t.image, "tonemap-ramp.png");
}

#[test]
fn low_range_is_linear() {
    // 20 … 150 cd/m²: less than the display's two decades
    let (w, h) = (50u32, 20u32);
    let rgb: Vec<[f32; 3]> = (0..w * h)
        .map(|k| grey(20.0 + 130.0 * f64::from(k % w) / f64::from(w - 1)))
        .collect();
    let (curve, adaptation) = tone_curve(&foveal(&rgb, w, h, 20.0));
    let ToneCurve::Linear { scale } = curve else {
        panic!("{curve:?}")
    };
    assert!((scale - tvi(10.0) / tvi(adaptation)).abs() < 1e-15);
    let t = histogram_adjustment(&rgb, w, h, 20.0);
    for (c, p) in rgb.iter().zip(&t.image.pixels) {
        // ratios kept: every byte is the sRGB code of the same multiple of Lw
        assert_eq!(p[0], srgb8(scale * f64::from(c[0]) / LD_MAX));
    }
    // decoded, ratios agree within the rounding of a byte
    let decode = |b: u8| {
        let v = f64::from(b) / 255.0;
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let (a, b) = (t.image.get(0, 0)[0], t.image.get(w - 1, 0)[0]);
    assert!(
        (decode(b) / decode(a) - 7.5).abs() < 0.1,
        "{}",
        decode(b) / decode(a)
    );
}

#[test]
fn ceiling_holds_as_the_paper_states() {
    // f(b_i) ≤ ΔLt(Ld)/ΔLt(Lw) · (Lw/Ld) · T·Δb / log10(Ldmax/Ldmin) for every bin, i.e. the
    // display slope dLd/dLw ≤ ΔLt(Ld)/ΔLt(Lw), within the iteration's 2.5 % tolerance.
    for (name, (rgb, w, h), vfov) in [("ramp", hdr_ramp(), 60.0), ("room", room(), 60.0)] {
        let (curve, _) = tone_curve(&foveal(&rgb, w, h, vfov));
        let ToneCurve::Histogram {
            b_min,
            b_max,
            counts,
            ..
        } = &curve
        else {
            panic!("{name}: {curve:?}")
        };
        let total: f64 = counts.iter().sum();
        let db = (b_max - b_min) / BINS as f64;
        let range = (LD_MAX / LD_MIN).log10();
        let mut worst: f64 = 0.0;
        for (i, f) in counts.iter().enumerate() {
            let lw = 10f64.powf(b_min + (i as f64 + 0.5) * db);
            let ld = curve.display(lw);
            let slope = range * f / (total * db) * ld / lw; // dLd/dLw
            worst = worst.max(slope / (tvi(ld) / tvi(lw)));
        }
        assert!(worst <= 1.0 / (1.0 - TOLERANCE), "{name}: {worst}");
        eprintln!("{name}: largest slope / ceiling = {worst:.4}");
    }
}

#[test]
fn tone_mapping_is_deterministic_and_keeps_black_and_hue() {
    let (rgb, w, h) = room();
    let a = histogram_adjustment(&rgb, w, h, 60.0);
    let b = histogram_adjustment(&rgb, w, h, 60.0);
    assert_eq!(a.image, b.image);
    assert_eq!(
        save(&a.image, "tonemap-room.png"),
        png_rgb8(&b.image).unwrap()
    );
    // no hit stays black; the window stays bluish, the picture reddish
    assert_eq!(a.image.get(w - 1, 0), [0, 0, 0]);
    let window = a
        .image
        .get((0.75 * f64::from(w)) as u32, (0.45 * f64::from(h)) as u32);
    assert!(window[2] > window[0], "{window:?}");
    let picture = a.image.get(
        (0.2 * f64::from(w)) as u32 + 4,
        (0.3 * f64::from(h)) as u32 + 12,
    );
    assert!(picture[0] > picture[2], "{picture:?}");
}

/// A field with a peak: cd/m² from about 3 at the corners to 3000 in the middle.
fn peak(w: u32, h: u32) -> Vec<f64> {
    (0..w * h)
        .map(|k| {
            let (x, y) = (f64::from(k % w), f64::from(k / w));
            let r2 = ((x - 0.45 * f64::from(w)).powi(2) + (y - 0.55 * f64::from(h)).powi(2))
                / f64::from(h * h);
            if x < 20.0 && y < 20.0 {
                f64::NAN
            } else {
                3000.0 * (-6.0 * r2).exp() + 2.0
            }
        })
        .collect()
}

#[test]
fn false_colour_with_legend_and_contours() {
    let (w, h) = (400u32, 300u32);
    let v = peak(w, h);
    let log = ColourScale::auto(&v, true, 8);
    assert_eq!((log.lo, log.hi), (10.0, 10_000.0)); // values 39 … 3002
    let img = false_colour(&v, w, h, &log, "cd/m²", true);
    assert!(img.width > w + 40 && img.height == h);
    // a pixel away from band edges has its scale colour; no data is dark grey
    assert_eq!(img.get(200, 10), log.colour(v[(10 * w + 200) as usize]));
    assert_eq!(img.get(5, 5), [64, 64, 64]);
    save(&img, "false-colour-log.png");

    let lin = ColourScale::auto(&v, false, 6);
    assert_eq!((lin.lo, lin.hi), (0.0, 3000.0)); // 6 bands of 500 (1-2-5), the 98th percentile below 3000
    let img = false_colour(&v, w, h, &lin, "lx", false);
    save(&img, "false-colour-linear.png");
    // the legend of a small image grows below it rather than crowding its labels
    let small = false_colour(&v[..(40 * 30) as usize], 40, 30, &lin, "lx", false);
    assert!(small.height > 30);
    save(&small, "false-colour-small.png");
    let smooth = ColourScale { steps: 0, ..log };
    save(
        &false_colour(&v, w, h, &smooth, "cd/m²", false),
        "false-colour-smooth.png",
    );
}

#[test]
fn isolines_drawn_over_a_field() {
    let (w, h) = (200u32, 150u32);
    let v = peak(w, h);
    let scale = ColourScale::fixed(0.0, 3200.0, false, 8).unwrap();
    let mut img = false_colour(&v, w, h, &scale, "lx", false);
    let mut n = 0;
    for level in scale.levels() {
        for line in isolines(&v, w as usize, h as usize, level) {
            n += 1;
            for s in line.windows(2) {
                // sample (col, row) is the pixel's centre
                let half = glam::DVec2::splat(0.5);
                img.line(s[0] + half, s[1] + half, [0, 0, 0]);
            }
        }
    }
    assert!(n >= 7, "{n} isolines");
    save(&img, "isolines.png");
}

#[test]
fn font_sheet() {
    use luxbake::picture::font::{draw_text, text_size};
    let lines = [
        "0123456789 .,-+/²³%:()µ",
        "ABCDEFGHIJKLMNOPQRSTUVWXYZ",
        "abcdefghijklmnopqrstuvwxyz",
        "E = 512 lx  L: 1.5k cd/m²  U0 ≥ 0.6 [±3 %]",
        "Ward Larson 1997; quality? 'draft'! €",
    ];
    let mut img = Rgb8Image::new(560, 5 * 32 + 8, [255; 3]);
    for (k, line) in lines.iter().enumerate() {
        let hh = if k < 3 { 27 } else { 18 };
        let (w, h) = text_size(line, hh);
        assert_eq!(
            (w, h),
            (line.chars().count() as u32 * 6 * hh / 9 - hh / 9, hh)
        );
        assert!(w <= 556, "{line}: {w}");
        draw_text(&mut img, 4, 4 + 32 * k as i64, line, hh, [0; 3]);
    }
    save(&img, "font.png");
}

/// Issue 57's acceptance: on samples/office (draft bake, camera `camera_interior`, 300 × 200)
/// the automatic illuminance range of the false-colour view spans the room's 2nd–98th
/// percentile within one band at each end, and every level is a whole multiple of a 1-2-5
/// step (so every tick label is one: 0, 100, 200 … not 23.7 or 4 217). Before, the bright
/// spot of the picture set it (0 … 2 500 lx, the room in two bands).
#[test]
fn the_office_illuminance_scale_spans_its_2nd_to_98th_percentile_in_1_2_5_steps() {
    let lit = support::cli::office_draft("picture-office-scale", &[]);
    let baked = luxbake::readback::read(&lit).unwrap();
    let scene = luxbake::import::load(&lit, &Default::default()).unwrap();
    let camera =
        luxbake::view::named_camera(&baked, "camera_interior", Some((300, 200)), None).unwrap();
    let view = luxbake::view::render(&baked, &scene, &camera, &Default::default()).unwrap();
    let mut e: Vec<f64> = (view.illuminance().iter())
        .map(|&x| f64::from(x))
        .filter(|x| x.is_finite())
        .collect();
    let s = ColourScale::auto(&e, false, 0);
    e.sort_by(f64::total_cmp);
    let at = |q: f64| e[((q * e.len() as f64).ceil() as usize).clamp(1, e.len()) - 1];
    let (p2, p98) = (at(0.02), at(0.98));
    let step = (s.hi - s.lo) / f64::from(s.bands());
    let mantissa = step / 10f64.powf(step.log10().floor());
    assert!(
        [1.0, 2.0, 5.0, 10.0]
            .iter()
            .any(|m| (mantissa - m).abs() < 1e-9),
        "{s:?}"
    );
    assert!(
        s.lo <= p2 && p2 < s.lo + step,
        "{s:?}: 2nd percentile {p2} lx"
    );
    assert!(
        s.hi - step < p98 && p98 <= s.hi,
        "{s:?}: 98th percentile {p98} lx"
    );
    for level in s.levels() {
        let k = level / step;
        assert!((k - k.round()).abs() < 1e-9, "{level} lx");
    }
    assert!(s.open_high, "the picture's spot lies above the range");
    eprintln!("office illuminance scale {s:?}, percentiles 2/98: {p2} / {p98} lx");
}
