//! Probe glyphs (`--probe-glyphs`): a small mesh per probe showing its illumination solid — an
//! arrow along the illumination vector **E** (shaft and cone, pointing along the flow of light)
//! and a sphere for the symmetric component ~E, both centred on the probe.
//!
//! Scale rule: with E_ref the largest scalar illuminance E_sr among the probes and s the glyph
//! scale ([`scale`]: 0.4 × the grid spacing — the smaller one when both `--probe-grid` and
//! `--working-plane` are given — or 0.15 m without a grid), the sphere's radius is s·~E/E_ref and
//! the arrow's length s·|**E**|/E_ref. So that every glyph stays visible the radius is at least
//! 0.05·s and the arrow at least 0.15·s long; there is no arrow when **E** = 0. The arrow's shaft
//! has radius 0.025·s, its head radius 0.07·s and length min(0.4·length, 0.25·s).
//!
//! Output: per probe, one mesh of two primitives (arrow, sphere) with POSITION, NORMAL and
//! COLOR_0 (a fixed shading, so the unlit glyphs look round), and two `KHR_materials_unlit`
//! materials (warm arrow, grey sphere). Glyphs exist only in the output: they are made after the
//! bake from its probe results, so they are never receivers, occluders or probes. The glyph
//! node's `extras.luxbake.glyph` records its sizes, s and E_ref.

use super::buffer::Binary;
use crate::probes::ProbeResult;
use crate::settings::Settings;
use glam::{DMat3, DMat4, DVec3};
use serde_json::{Value, json};

/// Segments around the sphere and the arrow; rings of the sphere (pole to pole).
const SEGMENTS: usize = 16;
const RINGS: usize = 8;
const ARROW_COLOR: [f64; 3] = [0.95, 0.45, 0.08];
const SPHERE_COLOR: [f64; 3] = [0.55, 0.55, 0.55];

/// The glyph scale s (m) for these settings (see the module docs).
pub fn scale(settings: &Settings) -> f64 {
    [settings.probe_grid, settings.working_plane]
        .into_iter()
        .flatten()
        .map(|g| 0.4 * g.spacing)
        .reduce(f64::min)
        .unwrap_or(0.15)
}

/// Glyph sizes: sphere radius and arrow length (m; `None`: no arrow).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sizes {
    pub radius: f64,
    pub arrow: Option<f64>,
}

/// What every glyph shares: the scale, E_ref and the two materials' indices.
pub struct Glyphs {
    pub scale: f64,
    pub reference: f64,
    arrow_material: usize,
    sphere_material: usize,
}

impl Glyphs {
    /// Set up glyphs of scale `s` for `probes`, appending their two materials to `materials`.
    pub(crate) fn new(s: f64, probes: &[ProbeResult], materials: &mut Vec<Value>) -> Glyphs {
        let reference = probes
            .iter()
            .map(|r| r.metrics.scalar)
            .filter(|e| e.is_finite())
            .fold(0.0, f64::max);
        let arrow_material = materials.len();
        materials.push(material("luxbake glyph: illumination vector", "vector"));
        materials.push(material("luxbake glyph: symmetric", "symmetric"));
        Glyphs {
            scale: s,
            reference,
            arrow_material,
            sphere_material: arrow_material + 1,
        }
    }

    /// The sizes of one probe's glyph.
    pub(crate) fn sizes(&self, r: &ProbeResult) -> Sizes {
        let s = self.scale;
        let (sym, mag) = (r.metrics.symmetric_mean, r.metrics.vector_magnitude);
        let rel = |e: f64| {
            if self.reference > 0.0 && e.is_finite() {
                e / self.reference
            } else {
                0.0
            }
        };
        Sizes {
            radius: s * rel(sym).max(0.05),
            arrow: (mag > 1e-9 * self.reference && mag.is_finite()).then(|| s * rel(mag).max(0.15)),
        }
    }

    /// Add probe `r`'s glyph: its mesh (vertices mapped by `frame`, from probe-centred probe axes
    /// into the space of the node that will hold the glyph node) and the glyph node, named after
    /// the probe. Returns the node's index.
    pub(crate) fn add(
        &self,
        r: &ProbeResult,
        frame: DMat4,
        binary: &mut Binary,
        nodes: &mut Vec<Value>,
        meshes: &mut Vec<Value>,
    ) -> usize {
        let sizes = self.sizes(r);
        let mut primitives = Vec::new();
        if let Some(len) = sizes.arrow {
            let dir = DVec3::from_array(r.metrics.vector).normalize();
            let part = arrow(dir, len, self.scale);
            primitives.push(part.write(frame, self.arrow_material, binary));
        }
        let part = sphere(sizes.radius);
        primitives.push(part.write(frame, self.sphere_material, binary));
        let name = format!("{}_glyph", r.probe.name);
        meshes.push(json!({"name": name, "primitives": primitives}));
        let mut glyph = json!({
            "sphereRadius": sizes.radius,
            "scale": self.scale,
            "referenceScalar": self.reference,
        });
        if let Some(len) = sizes.arrow {
            glyph["arrowLength"] = json!(len);
        }
        nodes.push(json!({
            "name": name,
            "mesh": meshes.len() - 1,
            "extras": {"luxbake": {"glyph": glyph}},
        }));
        nodes.len() - 1
    }
}

fn material(name: &str, kind: &str) -> Value {
    let color = if kind == "vector" {
        ARROW_COLOR
    } else {
        SPHERE_COLOR
    };
    json!({
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [color[0], color[1], color[2], 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 1.0,
        },
        "extensions": {"KHR_materials_unlit": {}},
        "extras": {"luxbake": {"glyph": kind}},
    })
}

/// A triangle mesh in probe axes, centred on the probe.
#[derive(Debug, Default)]
struct Part {
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl Part {
    fn vertex(&mut self, p: DVec3, n: DVec3) -> u32 {
        self.positions.push(p);
        self.normals.push(n);
        (self.positions.len() - 1) as u32
    }

    /// A disc fan facing `n` (counter-clockwise seen from `n`'s side).
    fn disc(&mut self, centre: DVec3, n: DVec3, ring: &[DVec3]) {
        let c = self.vertex(centre, n);
        let first = self.positions.len() as u32;
        for &p in ring {
            self.vertex(p, n);
        }
        let k = ring.len() as u32;
        for i in 0..k {
            let (a, b) = (first + i, first + (i + 1) % k);
            self.triangles.push(oriented([c, a, b], &self.positions, n));
        }
    }

    /// The primitive JSON, its data written to `binary` after mapping by `frame`.
    fn write(&self, frame: DMat4, material: usize, binary: &mut Binary) -> Value {
        let normal_from = DMat3::from_mat4(frame).inverse().transpose();
        let flip = frame.determinant() < 0.0;
        let f32x3 = |v: DVec3| v.to_array().map(|x| x as f32);
        let positions: Vec<[f32; 3]> = self
            .positions
            .iter()
            .map(|&p| f32x3(frame.transform_point3(p)))
            .collect();
        let normals: Vec<[f32; 3]> = self
            .normals
            .iter()
            .map(|&n| f32x3((normal_from * n).normalize_or(DVec3::Y)))
            .collect();
        // Fixed grey shading for unlit viewers (the colour is the material's base colour):
        // brighter toward a light from above and in front.
        let key = DVec3::new(0.3, 1.0, 0.5).normalize();
        let colors: Vec<[f32; 3]> = self
            .normals
            .iter()
            .map(|n| {
                let k = 0.55 + 0.45 * n.dot(key).max(0.0);
                [k as f32; 3]
            })
            .collect();
        let triangles: Vec<[u32; 3]> = if flip {
            self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
        } else {
            self.triangles.clone()
        };
        json!({
            "attributes": {
                "POSITION": binary.vec3(&positions, true),
                "NORMAL": binary.vec3(&normals, false),
                "COLOR_0": binary.vec3(&colors, false),
            },
            "indices": binary.indices(&triangles, positions.len()),
            "material": material,
            "mode": 4,
        })
    }
}

/// Wind `t` so it faces `n` (its geometric normal points to `n`'s side).
fn oriented(t: [u32; 3], p: &[DVec3], n: DVec3) -> [u32; 3] {
    let [a, b, c] = t.map(|i| p[i as usize]);
    if (b - a).cross(c - a).dot(n) >= 0.0 {
        t
    } else {
        [t[0], t[2], t[1]]
    }
}

/// A UV sphere of radius `r` (single vertices at the poles: no degenerate triangles).
fn sphere(r: f64) -> Part {
    let mut part = Part::default();
    let top = part.vertex(DVec3::Y * r, DVec3::Y);
    for i in 1..RINGS {
        let theta = std::f64::consts::PI * i as f64 / RINGS as f64;
        for j in 0..SEGMENTS {
            let phi = std::f64::consts::TAU * j as f64 / SEGMENTS as f64;
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            part.vertex(n * r, n);
        }
    }
    let bottom = part.vertex(-DVec3::Y * r, -DVec3::Y);
    let at = |ring: usize, j: usize| 1 + ((ring - 1) * SEGMENTS + j % SEGMENTS) as u32;
    let mut tris = Vec::new();
    for j in 0..SEGMENTS {
        tris.push([top, at(1, j), at(1, j + 1)]);
        tris.push([bottom, at(RINGS - 1, j + 1), at(RINGS - 1, j)]);
        for ring in 1..RINGS - 1 {
            let (a, b) = (at(ring, j), at(ring, j + 1));
            let (c, d) = (at(ring + 1, j), at(ring + 1, j + 1));
            tris.push([a, c, d]);
            tris.push([a, d, b]);
        }
    }
    // Face outward whatever the parametrisation's handedness.
    part.triangles = tris
        .into_iter()
        .map(|t| {
            let centroid: DVec3 = t.iter().map(|&i| part.positions[i as usize]).sum();
            oriented(t, &part.positions, centroid)
        })
        .collect();
    part
}

/// An arrow from the centre along unit `d`, `len` long, for glyph scale `s`.
fn arrow(d: DVec3, len: f64, s: f64) -> Part {
    let (shaft_r, head_r) = (0.025 * s, 0.07 * s);
    let head = (0.4 * len).min(0.25 * s);
    let neck = len - head;
    let (u, v) = d.any_orthonormal_pair();
    let radial: Vec<DVec3> = (0..SEGMENTS)
        .map(|j| {
            let phi = std::f64::consts::TAU * j as f64 / SEGMENTS as f64;
            u * phi.cos() + v * phi.sin()
        })
        .collect();
    let mut part = Part::default();
    // Shaft side.
    let base = part.positions.len() as u32;
    for &n in &radial {
        part.vertex(n * shaft_r, n);
        part.vertex(n * shaft_r + d * neck, n);
    }
    for j in 0..SEGMENTS as u32 {
        let k = (j + 1) % SEGMENTS as u32;
        let (a0, a1, b0, b1) = (
            base + 2 * j,
            base + 2 * j + 1,
            base + 2 * k,
            base + 2 * k + 1,
        );
        for t in [[a0, b0, b1], [a0, b1, a1]] {
            let n = part.normals[t[0] as usize] + part.normals[t[2] as usize];
            let t = oriented(t, &part.positions, n);
            part.triangles.push(t);
        }
    }
    // Caps: the shaft's foot, the head's base.
    let ring = |r: f64, at: f64| radial.iter().map(|&n| n * r + d * at).collect::<Vec<_>>();
    part.disc(DVec3::ZERO, -d, &ring(shaft_r, 0.0));
    part.disc(d * neck, -d, &ring(head_r, neck));
    // Cone: one tip vertex per segment so every face gets its own slanted normal.
    let slant = |n: DVec3| (n * head + d * head_r).normalize();
    let first = part.positions.len() as u32;
    for &n in &radial {
        part.vertex(n * head_r + d * neck, slant(n));
    }
    for j in 0..SEGMENTS {
        let mid = (radial[j] + radial[(j + 1) % SEGMENTS]).normalize();
        let tip = part.vertex(d * len, slant(mid));
        let (a, b) = (first + j as u32, first + ((j + 1) % SEGMENTS) as u32);
        let t = oriented([a, b, tip], &part.positions, mid);
        part.triangles.push(t);
    }
    part
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No degenerate triangle; each faces the way its vertex normals say; unit normals.
    fn well_formed(p: &Part) {
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 1e-12, "degenerate triangle {t:?}");
            let vn: DVec3 = t.iter().map(|&i| p.normals[i as usize]).sum();
            assert!(n.dot(vn) > 0.0, "triangle {t:?} faces against its normals");
        }
        for n in &p.normals {
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn sphere_faces_outward_and_arrow_points_along_e() {
        let s = sphere(0.1);
        well_formed(&s);
        assert_eq!(s.triangles.len(), 2 * SEGMENTS * (RINGS - 1));
        let d = DVec3::new(0.2, -1.0, 0.3).normalize();
        let a = arrow(d, 0.5, 0.4);
        well_formed(&a);
        let along: Vec<f64> = a.positions.iter().map(|p| p.dot(d)).collect();
        let far = along.iter().copied().fold(f64::MIN, f64::max);
        assert!((far - 0.5).abs() < 1e-12, "the tip is `len` along E");
        assert!(
            along.iter().all(|&x| x >= -1e-12),
            "the arrow starts at the probe"
        );
    }
}
