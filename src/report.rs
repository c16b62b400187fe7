//! Per-surface lighting figures, like the seed paper's Table 2: for each group of baked
//! surfaces, its area and area-weighted average, minimum and maximum illuminance (total, direct,
//! indirect), uniformity and average luminance.
//!
//! Input: the scene and a [`BakeResult`] (values at vertices). Output: [`Row`]s. Averages are
//! area integrals of the piecewise-linear vertex values (each vertex weighs a third of the area
//! of its triangles); minimum and maximum are over vertices.

use crate::result::{BakeResult, BakedSurface};
use crate::scene::{Scene, luma};
use glam::DVec3;

/// One line of the table.
#[derive(Debug, Clone, serde::Serialize)]
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
    /// E_min / E_avg.
    pub uniformity: f64,
    /// cd/m².
    pub l_avg: f64,
}

/// Which triangles a row takes.
pub enum Filter {
    All,
    /// Only faces whose normal is within ~8° of this direction (e.g. +Y: upward faces).
    Facing(DVec3),
}

/// One row per named node, with the node names joined by `/` from the root (`desk_dark/top`);
/// nodes with no baked surface are skipped. Front and back faces both count.
pub fn by_node(scene: &Scene, result: &BakeResult, filter: &Filter) -> Vec<Row> {
    let mut parent = vec![None; scene.nodes.len()];
    for (i, n) in scene.nodes.iter().enumerate() {
        for &c in &n.children {
            parent[c] = Some(i);
        }
    }
    let path = |mut i: usize| {
        let mut names = Vec::new();
        loop {
            names.push(
                scene.nodes[i]
                    .name
                    .clone()
                    .unwrap_or_else(|| format!("node {i}")),
            );
            match parent[i] {
                Some(p) => i = p,
                None => break,
            }
        }
        names.reverse();
        names.join("/")
    };
    let mut rows = Vec::new();
    for (i, node) in scene.nodes.iter().enumerate() {
        let baked: Vec<&BakedSurface> = result
            .surfaces
            .iter()
            .filter(|b| node.surfaces.contains(&b.surface))
            .collect();
        if let Some(row) = row(scene, &path(i), &baked, filter) {
            rows.push(row);
        }
    }
    rows
}

/// The figures over the given baked surfaces (None when no triangle passes the filter).
pub fn row(scene: &Scene, name: &str, baked: &[&BakedSurface], filter: &Filter) -> Option<Row> {
    let (mut area, mut rho, mut e, mut ed, mut l) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for b in baked {
        let material = &scene.materials[scene.surfaces[b.surface].material];
        for t in &b.triangles {
            let p = t.map(|v| b.positions[v as usize]);
            let cross = (p[1] - p[0]).cross(p[2] - p[0]);
            let a = cross.length() / 2.0;
            if a <= 0.0 {
                continue;
            }
            if let Filter::Facing(d) = filter
                && cross.normalize().dot(d.normalize()) < 0.99
            {
                continue;
            }
            area += a;
            rho += a * luma(material.reflectance);
            for &v in t {
                let v = v as usize;
                let w = a / 3.0;
                e += w * b.illuminance[v] as f64;
                ed += w * b.illuminance_direct[v] as f64;
                l += w * b.luminance[v] as f64;
                lo = lo.min(b.illuminance[v] as f64);
                hi = hi.max(b.illuminance[v] as f64);
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
        uniformity: if e > 0.0 { lo / (e / area) } else { 0.0 },
        l_avg: l / area,
    })
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| surface | area m² | ρ | E avg lx | E min lx | E max lx | direct lx | indirect lx | U₀ | L avg cd/m² |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {:.2} | {:.2} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.2} | {:.1} |\n",
            r.name,
            r.area,
            r.reflectance,
            r.e_avg,
            r.e_min,
            r.e_max,
            r.e_direct_avg,
            r.e_indirect_avg,
            r.uniformity,
            r.l_avg
        ));
    }
    s
}
