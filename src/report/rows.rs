//! Surface rows: area, reflectance and illuminance figures over a group of baked primitives, and
//! the working plane's figures over its probes.
//!
//! Averages are area integrals of the piecewise-linear vertex values divided by the area (each
//! vertex of a triangle weighs a third of its area); minimum and maximum are over the vertices
//! of the triangles taken. Sums run in a fixed order (primitives in output order, probe values
//! sorted), so equal inputs give equal bits.

use crate::baked::{BakedOutput, PlaneInput, PlanePoint, Primitive};
use crate::probes::ProbeGrid;
use glam::DVec3;

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
    /// E_min / E_avg (0 when E_avg is 0).
    pub uniformity: f64,
    /// cd/m².
    pub l_avg: f64,
}

/// Which triangles a row takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    All,
    /// Only faces whose normal is within ~8° of this direction (e.g. +Y: upward faces).
    Facing(DVec3),
}

/// The working plane's figures (lx unless stated).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PlaneRow {
    /// Height above the floor (m), from the run's settings.
    pub height: Option<f64>,
    /// Grid spacing (m), from the run's settings.
    pub spacing: Option<f64>,
    /// Number of points.
    pub points: usize,
    pub e_avg: f64,
    pub e_min: f64,
    pub e_max: f64,
    pub e_direct_avg: f64,
    pub e_indirect_avg: f64,
    pub uniformity: f64,
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

/// One row per material with baked primitives, in material order.
pub fn by_material(input: &BakedOutput, filter: &Filter) -> Vec<Row> {
    groups(
        input.materials.len(),
        |p| p.material,
        input,
        filter,
        |i| input.material_name(i),
    )
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
        .filter_map(|(i, prims)| row(input, &name(i), prims, filter))
        .collect()
}

/// The figures over `prims` (None when no triangle with area passes the filter).
pub fn row(input: &BakedOutput, name: &str, prims: &[&Primitive], filter: &Filter) -> Option<Row> {
    let (mut area, mut rho, mut e, mut ed, mut l) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in prims {
        let reflectance = input
            .materials
            .get(p.material)
            .map_or(0.0, |m| m.reflectance);
        for t in &p.triangles {
            let [a, b, c] = t.map(|v| p.positions[v as usize]);
            let cross = (b - a).cross(c - a);
            let w = cross.length() / 2.0;
            if w <= 0.0 {
                continue;
            }
            if let Filter::Facing(d) = filter
                && cross.normalize().dot(d.normalize()) < 0.99
            {
                continue;
            }
            area += w;
            rho += w * reflectance;
            for &v in t {
                let v = v as usize;
                let (ev, edv) = (p.illuminance[v] as f64, p.illuminance_direct[v] as f64);
                e += w / 3.0 * ev;
                ed += w / 3.0 * edv;
                l += w / 3.0 * p.luminance[v] as f64;
                lo = lo.min(ev);
                hi = hi.max(ev);
            }
        }
    }
    (area > 0.0).then(|| Row {
        name: name.to_string(),
        area,
        reflectance: rho / area,
        e_avg: e / area,
        e_min: lo,
        e_max: hi,
        e_direct_avg: ed / area,
        e_indirect_avg: (e - ed) / area,
        uniformity: ratio(lo, e / area),
        l_avg: l / area,
    })
}

/// The working plane's figures: plain means over its points (a regular grid); `grid`: its height
/// and spacing, when known.
pub fn plane(input: &PlaneInput, grid: Option<ProbeGrid>) -> PlaneRow {
    let points = &input.points;
    let mean = |get: fn(&PlanePoint) -> f32| {
        let mut v: Vec<f32> = points.iter().map(get).collect();
        v.sort_by(f32::total_cmp);
        v.iter().map(|&x| x as f64).sum::<f64>() / v.len().max(1) as f64
    };
    let total = points.iter().map(|p| p.total as f64);
    let e_min = total.clone().fold(f64::INFINITY, f64::min);
    let e_max = total.fold(f64::NEG_INFINITY, f64::max);
    let e_avg = mean(|p| p.total);
    PlaneRow {
        height: grid.map(|g| g.height),
        spacing: grid.map(|g| g.spacing),
        points: points.len(),
        e_avg,
        e_min,
        e_max,
        e_direct_avg: mean(|p| p.direct),
        e_indirect_avg: mean(|p| p.indirect),
        uniformity: ratio(e_min, e_avg),
    }
}

/// a / b, or 0 when b is not positive.
pub(crate) fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 { a / b } else { 0.0 }
}
