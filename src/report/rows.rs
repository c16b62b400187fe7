//! Surface rows: area, reflectance and illuminance figures over a group of baked primitives, and
//! the working plane's figures over its probes.
//!
//! A lightmapped primitive's figures come from its texels (footprint-weighted), another's from
//! its vertices (area integrals of the piecewise-linear values): see [`super::sums`]; a row says
//! which ([`Source`]). Sums run in a fixed order (primitives in output order, texels in atlas
//! order, probe values sorted), so equal inputs give equal bits.

pub use super::sums::{Filter, Source};

use super::sums::Sums;
use crate::probes::ProbeGrid;
use crate::readback::{BakedOutput, PlaneInput, PlanePoint, Primitive};

/// One surface group's figures.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Row {
    pub name: String,
    /// m².
    pub area: f64,
    /// Area-weighted photometric reflectance.
    pub reflectance: f64,
    /// lx.
    pub e_avg: f64,
    pub e_min: f64,
    pub e_max: f64,
    pub e_direct_avg: f64,
    pub e_indirect_avg: f64,
    /// U₀ = E_min / E_avg (0 when E_avg is 0).
    pub uniformity: f64,
    /// U_d = E_min / E_max (0 when E_max is 0).
    pub uniformity_d: f64,
    /// cd/m².
    pub l_avg: f64,
    /// Area covered by another surface (m²: the floor under a desk leg), left out of every other
    /// figure of the row.
    pub covered_area: f64,
    /// What the figures were taken from.
    pub source: Source,
}

/// The working plane's figures (lx unless stated).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PlaneRow {
    /// Height above the floor (m), from the run's settings.
    pub height: Option<f64>,
    /// Grid spacing (m), from the run's settings.
    pub spacing: Option<f64>,
    /// Border zone (m): points closer than this to the edge of the plane's extent are left out.
    pub border: f64,
    /// The plane's extent `[x_min, z_min, x_max, z_max]` (m, +Y up): its points' extent grown by
    /// half the spacing (for a rectangular room, the room's inside), before the border.
    pub extent: [f64; 4],
    /// Number of points taken (inside the border), and of all points.
    pub points: usize,
    pub points_total: usize,
    pub e_avg: f64,
    pub e_min: f64,
    pub e_max: f64,
    pub e_direct_avg: f64,
    pub e_indirect_avg: f64,
    /// U₀ = E_min / E_avg.
    pub uniformity: f64,
    /// U_d = E_min / E_max.
    pub uniformity_d: f64,
}

/// One row per node with baked primitives, named by its path (`desk_dark/top`), in node order.
pub fn by_node(input: &BakedOutput, filter: &Filter) -> Vec<Row> {
    groups(
        input.nodes.len(),
        |p| p.node,
        input,
        filter,
        |i| input.node_path(i),
    )
}

/// One row per material with baked primitives, in material order (a lightmapped variant counts
/// as the material it was made from).
pub fn by_material(input: &BakedOutput, filter: &Filter) -> Vec<Row> {
    groups(
        input.materials.len(),
        |p| original(input, p.material),
        input,
        filter,
        |i| input.material_name(i),
    )
}

/// The material a lightmapped variant was made from, or `m` itself.
pub(crate) fn original(input: &BakedOutput, m: usize) -> usize {
    (input.materials.get(m))
        .and_then(|info| info.variant_of)
        .unwrap_or(m)
}

fn groups(
    n: usize,
    key: impl Fn(&Primitive) -> usize,
    input: &BakedOutput,
    filter: &Filter,
    name: impl Fn(usize) -> String,
) -> Vec<Row> {
    let mut members: Vec<Vec<&Primitive>> = vec![Vec::new(); n];
    for p in &input.primitives {
        if let Some(m) = members.get_mut(key(p)) {
            m.push(p);
        }
    }
    members
        .iter()
        .enumerate()
        // Named only when it has primitives: a node's path is as long as its depth.
        .filter(|(_, prims)| !prims.is_empty())
        .filter_map(|(i, prims)| row(input, &name(i), prims, filter))
        .collect()
}

/// The source of several rows together (`None` for no rows).
pub(crate) fn source_of(rows: &[Row]) -> Option<Source> {
    let first = rows.first()?.source;
    Some(if rows.iter().all(|r| r.source == first) {
        first
    } else {
        Source::TexelsAndVertices
    })
}

/// The figures over `prims` (None when nothing with area passes the filter), from texels where
/// a primitive has them.
pub(crate) fn row(
    input: &BakedOutput,
    name: &str,
    prims: &[&Primitive],
    filter: &Filter,
) -> Option<Row> {
    row_from(input, name, prims, filter, true)
}

/// [`row`], from texels only when `texels` (else from vertices throughout).
pub fn row_from(
    input: &BakedOutput,
    name: &str,
    prims: &[&Primitive],
    filter: &Filter,
    texels: bool,
) -> Option<Row> {
    let mut s = Sums::default();
    for p in prims {
        s.add(input, p, filter, texels);
    }
    let area = s.area;
    let covered_area = s.covered;
    (area > 0.0).then(|| {
        let (lo, hi) = (s.lo.unwrap_or(0.0), s.hi.unwrap_or(0.0));
        Row {
            name: name.to_string(),
            area,
            reflectance: s.rho / area,
            e_avg: s.e / area,
            e_min: lo,
            e_max: hi,
            e_direct_avg: s.ed / area,
            e_indirect_avg: (s.e - s.ed) / area,
            uniformity: ratio(lo, s.e / area),
            uniformity_d: ratio(lo, hi),
            l_avg: s.l / area,
            covered_area,
            source: s.source(),
        }
    })
}

/// The working plane's figures: plain means over its points (a regular grid) at least `border` m
/// inside its extent (the points' extent grown by half the spacing: EN 12464-1's border zone);
/// `grid`: its height and spacing, when known. `None` when the border leaves no point.
pub(crate) fn plane(input: &PlaneInput, grid: Option<ProbeGrid>, border: f64) -> Option<PlaneRow> {
    let extent = plane_extent(&input.points, grid.map_or(0.0, |g| g.spacing));
    let inside = |p: &&PlanePoint| inside_border(extent, border, p.position);
    let points: Vec<&PlanePoint> = input.points.iter().filter(inside).collect();
    if points.is_empty() {
        return None;
    }
    let mean = |get: fn(&PlanePoint) -> f32| {
        let mut v: Vec<f32> = points.iter().map(|p| get(p)).collect();
        v.sort_by(f32::total_cmp);
        v.iter().map(|&x| x as f64).sum::<f64>() / v.len().max(1) as f64
    };
    let total = points.iter().map(|p| p.total as f64);
    let e_min = total.clone().fold(f64::INFINITY, f64::min);
    let e_max = total.fold(f64::NEG_INFINITY, f64::max);
    let e_avg = mean(|p| p.total);
    Some(PlaneRow {
        height: grid.map(|g| g.height),
        spacing: grid.map(|g| g.spacing),
        border,
        extent,
        points: points.len(),
        points_total: input.points.len(),
        e_avg,
        e_min,
        e_max,
        e_direct_avg: mean(|p| p.direct),
        e_indirect_avg: mean(|p| p.indirect),
        uniformity: ratio(e_min, e_avg),
        uniformity_d: ratio(e_min, e_max),
    })
}

/// Whether `p` lies at least `border` m inside `extent` (`[x_min, z_min, x_max, z_max]`, +Y up),
/// with a millimetre's slack: grid points sit at computed, rounded places.
pub(crate) fn inside_border(extent: [f64; 4], border: f64, p: glam::DVec3) -> bool {
    let b = border - 1e-3;
    p.x - extent[0] >= b && p.z - extent[1] >= b && extent[2] - p.x >= b && extent[3] - p.z >= b
}

/// `[x_min, z_min, x_max, z_max]` of `points` grown by half of `spacing` (m).
pub(crate) fn plane_extent(points: &[PlanePoint], spacing: f64) -> [f64; 4] {
    let mut e = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in points {
        e = [
            e[0].min(p.position.x),
            e[1].min(p.position.z),
            e[2].max(p.position.x),
            e[3].max(p.position.z),
        ];
    }
    let h = spacing / 2.0;
    [e[0] - h, e[1] - h, e[2] + h, e[3] + h]
}

/// a / b, or 0 when b is not positive.
pub(crate) fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 { a / b } else { 0.0 }
}
