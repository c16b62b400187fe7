//! A plan laid out on the page once, as a device-neutral [`Drawing`] (page pixels, y down) that
//! [`super::svg`] and [`super::raster`] render alike.
//!
//! Layout: the name, a line of figures (E avg / min / max, U₀) and the frame's note on top; the plan
//! below at `size / (longer side)` px per metre, with the field's cells (runs of equal colour in
//! a row as one rectangle), the outline, the contours at the scale's levels inside the values'
//! range (marching squares on the cell centres: `picture::isolines`) and their labels; the legend
//! (colour bar, level labels, unit) on the right; a scale bar (1, 2 or 5 × 10^k m, about a
//! quarter of the longer side) under the plan. Labels sit on their line, centred at a point of
//! it, on a white box; candidate points along each line are tried in a fixed order and one is
//! taken only when its box overlaps no label placed before and stays inside the plan (a level
//! none of whose lines has room gets one label at its longest line's middle if that overlaps no
//! other), so labels never overlap at any size.

use super::Plan;
use crate::picture::contours::isolines;
use crate::picture::font::text_size;
use crate::picture::scale::ColourScale;
use glam::DVec2;

/// Horizontal placement of a text at its `x`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// What a plan is drawn from (page pixels, origin top-left, y down).
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A filled rectangle.
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: [u8; 3],
    },
    /// An open polyline of `width` px.
    Line {
        points: Vec<DVec2>,
        colour: [u8; 3],
        width: f64,
    },
    /// Text whose box's top is at `y`, `size` px high, placed at `x` by `anchor`.
    Text {
        x: f64,
        y: f64,
        size: u32,
        text: String,
        colour: [u8; 3],
        anchor: Anchor,
    },
}

/// A laid-out plan. `field` items (the field's cells and the legend's colour bar) come first; SVG
/// draws them with crisp edges, so that no seam shows between neighbours.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawing {
    pub width: u32,
    pub height: u32,
    pub title: String,
    /// The field's cells and the legend's colour bar.
    pub field: Vec<Item>,
    /// Everything else, in drawing order.
    pub items: Vec<Item>,
}

pub const WHITE: [u8; 3] = [255, 255, 255];
pub const BLACK: [u8; 3] = [0, 0, 0];
/// Cells with no data.
pub const NO_DATA: [u8; 3] = [200, 200, 200];
const CONTOUR: [u8; 3] = [40, 40, 40];

/// A number as the title shows it: three significant digits, at most two decimals.
pub(crate) fn figure(v: f64) -> String {
    let a = v.abs();
    if a >= 100.0 || a == 0.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

/// The plan laid out.
pub fn draw(plan: &Plan) -> Drawing {
    let page = Page::new(plan);
    let (text, big, margin, left) = (page.text, page.big, page.margin, page.left);
    let unit = plan.quantity.unit();
    let sym = plan.quantity.symbol();
    let figures = format!(
        "{sym} avg {} {unit}, min {}, max {}, U\u{2080} = min/avg = {:.2}",
        figure(plan.avg),
        figure(plan.min),
        figure(plan.max),
        plan.uniformity()
    );
    let title = format!("{}: {figures}", plan.name);
    let note = plan.frame.note();
    let mut items = Vec::new();
    heading(&page, [&plan.name, &figures, &note], &mut items);
    let (mut cells, no_data) = field_cells(plan, &page);
    for [a, b] in &plan.outline {
        items.push(Item::Line {
            points: vec![page.to_page(*a), page.to_page(*b)],
            colour: BLACK,
            width: 2.0,
        });
    }
    contours(plan, &page, &mut items);
    // A frame round the plan.
    let plan_box = page.plan_box();
    items.push(Item::Line {
        points: vec![
            plan_box[0],
            DVec2::new(plan_box[1].x, plan_box[0].y),
            plan_box[1],
            DVec2::new(plan_box[0].x, plan_box[1].y),
            plan_box[0],
        ],
        colour: [120, 120, 120],
        width: 1.0,
    });
    let legend = legend(plan, &page, no_data, &mut cells, &mut items);
    let y = scale_bar(plan, &page, &mut items);

    let width = (legend.x + legend.label_w.max(legend.bar_w) + margin)
        .max(left + width(&plan.name, big) + margin)
        .max(left + width(&figures, text) + margin)
        .max(left + width(&note, text) + margin)
        .ceil();
    let height = (y + margin).max(legend.bottom + margin).ceil();
    Drawing {
        width: width as u32,
        height: height as u32,
        title,
        field: cells,
        items,
    }
}

/// The page's measures: text sizes (px), the margin, and where the plan sits at how many px per
/// metre.
struct Page {
    text: u32,
    big: u32,
    margin: f64,
    /// Page px per metre.
    k: f64,
    /// The plan's top-left corner on the page, and its width and height (px).
    left: f64,
    top: f64,
    pw: f64,
    ph: f64,
    /// The field's origin (m), drawn at (left, top).
    origin: DVec2,
}

impl Page {
    /// The plan at `size / (longer side)` px per metre, under three lines of heading.
    fn new(plan: &Plan) -> Page {
        let size = plan.size as f64;
        let text = ((size / 60.0).round() as u32).clamp(11, 40);
        let big = text + text / 3;
        let margin = (text as f64 * 1.5).round();
        let extent = plan.field.extent();
        let k = size / extent.max_element();
        let (pw, ph) = (extent.x * k, extent.y * k);
        let line = text as f64 * 1.6;
        let top = margin + big as f64 + text as f64 * 0.6 + 2.0 * line + margin;
        Page {
            text,
            big,
            margin,
            k,
            left: margin,
            top,
            pw,
            ph,
            origin: plan.field.origin,
        }
    }

    /// A point of the plane (m) on the page.
    fn to_page(&self, p: DVec2) -> DVec2 {
        DVec2::new(self.left, self.top) + (p - self.origin) * self.k
    }

    /// The plan's corners on the page: top-left, bottom-right.
    fn plan_box(&self) -> [DVec2; 2] {
        [
            DVec2::new(self.left, self.top),
            DVec2::new(self.left + self.pw, self.top + self.ph),
        ]
    }
}

/// The name on the first line, the figures and the note below it: three short lines, so the
/// page's width is the plan's and the legend's, not a long title's.
fn heading(page: &Page, [name, figures, note]: [&str; 3], items: &mut Vec<Item>) {
    let (text, big, margin, left) = (page.text, page.big, page.margin, page.left);
    let line = text as f64 * 1.6;
    items.push(Item::Text {
        x: left,
        y: margin,
        size: big,
        text: name.to_string(),
        colour: BLACK,
        anchor: Anchor::Start,
    });
    for (k, t) in [figures, note].into_iter().enumerate() {
        items.push(Item::Text {
            x: left,
            y: margin + big as f64 + text as f64 * 0.6 + k as f64 * line,
            size: text,
            text: t.to_string(),
            colour: BLACK,
            anchor: Anchor::Start,
        });
    }
}

/// The field: runs of one colour along each row, and whether any cell has no data.
fn field_cells(plan: &Plan, page: &Page) -> (Vec<Item>, bool) {
    let (field, left, top) = (&plan.field, page.left, page.top);
    let mut cells = Vec::new();
    let colour = |v: f64| {
        if v.is_finite() {
            plan.scale.colour(v)
        } else {
            NO_DATA
        }
    };
    let ck = field.cell * page.k;
    let mut no_data = false;
    for r in 0..field.h {
        let row = &field.values[r * field.w..(r + 1) * field.w];
        let mut c = 0;
        while c < field.w {
            let fill = colour(row[c]);
            no_data |= !row[c].is_finite();
            let start = c;
            while c < field.w && colour(row[c]) == fill {
                c += 1;
            }
            let (x0, y0) = (left + start as f64 * ck, top + r as f64 * ck);
            cells.push(Item::Rect {
                x: x0,
                y: y0,
                w: left + c as f64 * ck - x0,
                h: top + (r + 1) as f64 * ck - y0,
                fill,
            });
        }
    }
    (cells, no_data)
}

/// The contours at the scale's levels inside the values' range, then their labels on white
/// boxes.
fn contours(plan: &Plan, page: &Page, items: &mut Vec<Item>) {
    let (field, text) = (&plan.field, page.text);
    let unit = plan.quantity.unit();
    let (lo, hi) = finite_range(&field.values);
    let mut labels = Labels {
        plan_box: page.plan_box(),
        placed: Vec::new(),
        labels: Vec::new(),
    };
    for level in plan.scale.levels() {
        if !(level > lo && level < hi) {
            continue;
        }
        let mut lines: Vec<Vec<DVec2>> = isolines(&field.values, field.w, field.h, level)
            .into_iter()
            .map(|l| l.into_iter().map(|g| page.to_page(field.at(g))).collect())
            .collect();
        for l in &lines {
            items.push(Item::Line {
                points: l.clone(),
                colour: CONTOUR,
                width: 1.0,
            });
        }
        let label = format!("{} {unit}", plan.scale.label(level));
        let half = DVec2::new(width(&label, text) / 2.0 + 2.0, text as f64 / 2.0 + 1.0);
        lines.sort_by(|a, b| length(b).total_cmp(&length(a)));
        labels.level(&lines, half, &label);
    }
    for (p, half, label) in labels.labels {
        items.push(Item::Rect {
            x: p.x - half.x,
            y: p.y - half.y,
            w: 2.0 * half.x,
            h: 2.0 * half.y,
            fill: WHITE,
        });
        items.push(Item::Text {
            x: p.x,
            y: p.y - half.y + 1.0,
            size: text,
            text: label,
            colour: BLACK,
            anchor: Anchor::Middle,
        });
    }
}

/// Contour labels placed so far: each box, and (centre, half size, text).
struct Labels {
    plan_box: [DVec2; 2],
    placed: Vec<[DVec2; 2]>,
    labels: Vec<(DVec2, DVec2, String)>,
}

impl Labels {
    /// Labels `label` (box half size `half`) on a level's `lines`, longest first: on each of the
    /// four longest with room, at the first candidate point whose box is free and in the plan.
    fn level(&mut self, lines: &[Vec<DVec2>], half: DVec2, label: &str) {
        let mut any = false;
        for l in lines.iter().take(4) {
            if length(l) < 3.0 * half.x {
                continue;
            }
            let spot = [0.5, 0.25, 0.75, 0.125, 0.375, 0.625, 0.875]
                .into_iter()
                .map(|f| point_along(l, f))
                .find(|&p| {
                    let b = [p - half, p + half];
                    inside(&b, &self.plan_box) && !self.placed.iter().any(|q| overlap(&b, q))
                });
            if let Some(p) = spot {
                self.placed.push([p - half, p + half]);
                self.labels.push((p, half, label.to_string()));
                any = true;
            }
        }
        // A level none of whose lines had room for a label on a free spot: at its longest
        // line's middle, if that overlaps no label either (else the legend alone names it).
        if !any && let Some(l) = lines.first().filter(|l| l.len() > 1) {
            let p = point_along(l, 0.5);
            let b = [p - half, p + half];
            if !self.placed.iter().any(|q| overlap(&b, q)) {
                self.placed.push(b);
                self.labels.push((p, half, label.to_string()));
            }
        }
    }
}

/// Where the legend went: the colour bar's x and width, the widest of the bar and its labels,
/// and its bottom (px).
struct Legend {
    x: f64,
    bar_w: f64,
    label_w: f64,
    bottom: f64,
}

/// The legend right of the plan: the colour bar from hi (top) to lo (into `cells`), the levels
/// beside it, the unit above, and a "no data" swatch under it if `no_data`.
fn legend(
    plan: &Plan,
    page: &Page,
    no_data: bool,
    cells: &mut Vec<Item>,
    items: &mut Vec<Item>,
) -> Legend {
    let (text, top) = (page.text, page.top);
    let unit = plan.quantity.unit();
    let sym = plan.quantity.symbol();
    let bar_x = page.left + page.pw + 2.0 * page.margin;
    let bar_w = text as f64 * 1.5;
    let bar_top = top + text as f64 * 1.5;
    let bar_h = (page.ph - text as f64 * 1.5).max(12.0 * text as f64);
    let s = &plan.scale;
    colour_bar(s, [bar_x, bar_top, bar_w, bar_h], cells);
    items.push(Item::Text {
        x: bar_x,
        y: top,
        size: text,
        text: if s.log {
            format!("{sym} ({unit}, log)")
        } else {
            format!("{sym} ({unit})")
        },
        colour: BLACK,
        anchor: Anchor::Start,
    });
    let mut label_w = width(&format!("{sym} ({unit}, log)"), text);
    for (level, l) in s.levels().into_iter().zip(s.legend_labels()) {
        let y = bar_top + bar_h * (1.0 - s.position(level));
        items.push(Item::Line {
            points: vec![
                DVec2::new(bar_x + bar_w, y),
                DVec2::new(bar_x + bar_w + 5.0, y),
            ],
            colour: BLACK,
            width: 1.0,
        });
        label_w = label_w.max(bar_w + 8.0 + width(&l, text));
        items.push(Item::Text {
            x: bar_x + bar_w + 8.0,
            y: y - text as f64 / 2.0,
            size: text,
            text: l,
            colour: BLACK,
            anchor: Anchor::Start,
        });
    }
    let mut bottom = bar_top + bar_h;
    if no_data {
        items.push(Item::Rect {
            x: bar_x,
            y: bottom + text as f64,
            w: bar_w,
            h: text as f64,
            fill: NO_DATA,
        });
        items.push(Item::Text {
            x: bar_x + bar_w + 8.0,
            y: bottom + text as f64,
            size: text,
            text: "no data".into(),
            colour: BLACK,
            anchor: Anchor::Start,
        });
        bottom += 2.0 * text as f64;
    }
    Legend {
        x: bar_x,
        bar_w,
        label_w,
        bottom,
    }
}

/// The colour bar of scale `s` at `[x, top, width, height]` (px), hi at the top, as 256 strips
/// where strips of one colour (a band) are one rectangle.
fn colour_bar(s: &ColourScale, [bar_x, bar_top, bar_w, bar_h]: [f64; 4], cells: &mut Vec<Item>) {
    let strips = 256;
    let mut start = 0;
    for i in 0..strips {
        // Top strip = hi; each strip shows the colour at its centre's position on the scale.
        let colour_of = |i: usize| s.colour(value_at(s, 1.0 - (i as f64 + 0.5) / strips as f64));
        if i + 1 < strips && colour_of(i + 1) == colour_of(start) {
            continue;
        }
        let y0 = bar_top + bar_h * start as f64 / strips as f64;
        cells.push(Item::Rect {
            x: bar_x,
            y: y0,
            w: bar_w,
            h: bar_top + bar_h * (i + 1) as f64 / strips as f64 - y0,
            fill: colour_of(start),
        });
        start = i + 1;
    }
}

/// The scale bar under the plan, about a quarter of its longer side; returns its y (px).
fn scale_bar(plan: &Plan, page: &Page, items: &mut Vec<Item>) -> f64 {
    let text = page.text;
    let metres = scale_bar_length(plan.field.extent().max_element());
    let (x0, x1) = (page.left, page.left + metres * page.k);
    let y = page.top + page.ph + page.margin;
    let tick = text as f64 / 2.0;
    items.push(Item::Line {
        points: vec![
            DVec2::new(x0, y - tick),
            DVec2::new(x0, y),
            DVec2::new(x1, y),
            DVec2::new(x1, y - tick),
        ],
        colour: BLACK,
        width: 2.0,
    });
    items.push(Item::Text {
        x: x1 + 6.0,
        y: y - text as f64 * 0.8,
        size: text,
        text: format!("{} m", figure_m(metres)),
        colour: BLACK,
        anchor: Anchor::Start,
    });
    y
}

/// A text's width (px) on either page: the bitmap font's, or about 0.55 em a character for the
/// SVG's proportional fonts, whichever is wider.
fn width(t: &str, size: u32) -> f64 {
    let chars = t.chars().count() as f64;
    (text_size(t, size).0 as f64).max(0.55 * size as f64 * chars)
}

/// The value at position `t` (0..1) of the scale: the inverse of `ColourScale::position`.
pub(crate) fn value_at(s: &ColourScale, t: f64) -> f64 {
    if s.log {
        s.lo * (s.hi / s.lo).powf(t)
    } else {
        s.lo + (s.hi - s.lo) * t
    }
}

/// The largest 1, 2 or 5 × 10^k m at most a quarter of `extent` (m).
pub(crate) fn scale_bar_length(extent: f64) -> f64 {
    let x = extent / 4.0;
    let base = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * base)
        .find(|&v| v <= x * (1.0 + 1e-12))
        .unwrap_or(base)
}

/// A length in metres without trailing zeros (0.5, 2, 0.02).
fn figure_m(m: f64) -> String {
    let s = format!("{m:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The finite values' range (NaN, NaN when there are none).
fn finite_range(v: &[f64]) -> (f64, f64) {
    let f = v.iter().copied().filter(|x| x.is_finite());
    let lo = f.clone().fold(f64::INFINITY, f64::min);
    let hi = f.fold(f64::NEG_INFINITY, f64::max);
    if lo <= hi {
        (lo, hi)
    } else {
        (f64::NAN, f64::NAN)
    }
}

fn length(l: &[DVec2]) -> f64 {
    l.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// The point at fraction `f` of the polyline's length.
fn point_along(l: &[DVec2], f: f64) -> DVec2 {
    let mut rest = f * length(l);
    for w in l.windows(2) {
        let d = w[0].distance(w[1]);
        if d >= rest && d > 0.0 {
            return w[0] + (w[1] - w[0]) * (rest / d);
        }
        rest -= d;
    }
    *l.last().unwrap_or(&DVec2::ZERO)
}

fn overlap(a: &[DVec2; 2], b: &[DVec2; 2]) -> bool {
    a[0].x < b[1].x && b[0].x < a[1].x && a[0].y < b[1].y && b[0].y < a[1].y
}

fn inside(a: &[DVec2; 2], b: &[DVec2; 2]) -> bool {
    a[0].x >= b[0].x && a[0].y >= b[0].y && a[1].x <= b[1].x && a[1].y <= b[1].y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_lengths_and_figures() {
        assert_eq!(scale_bar_length(8.0), 2.0);
        assert_eq!(scale_bar_length(5.0), 1.0);
        assert_eq!(scale_bar_length(0.5), 0.1);
        assert_eq!(scale_bar_length(30.0), 5.0);
        assert_eq!(figure_m(0.5), "0.5");
        assert_eq!(figure_m(2.0), "2");
        assert_eq!(figure(312.4), "312");
        assert_eq!(figure(12.34), "12.3");
        let l = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(2.0, 2.0)];
        assert_eq!(point_along(&l, 0.75), DVec2::new(2.0, 1.0));
    }
}
