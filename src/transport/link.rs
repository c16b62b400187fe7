//! What a gather row is made of: a receiver's links to nodes of a patch tree.

use glam::DVec3;

/// One source seen by a receiver.
///
/// Leaf and far-field links (`coeff > 0`): E += coeff × node mean + gradient · node first moment.
/// Cluster links (`coeff < 0`, a node whose patches face the receiver from both sides):
/// with K = −coeff = cos θ·vis·V/(π d²) (V: the share it does not hide from itself) and w the
/// unit direction from the node to the receiver, E += K × Σ weights(w)·S over the node's
/// exitance-weighted normal distribution (`geom::sh::Dist`). Scaling `coeff` scales a row's
/// links of both forms: what else they hold is relative to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    pub node: u32,
    /// Form factor × visible fraction (negated for cluster links).
    pub coeff: f32,
    /// A vector in 32 bits ([`shape_bits`]): far-field links, the form-factor density's gradient
    /// (per m³) × visible fraction, times A^(3/2) / coeff for the node's area A — a vector about
    /// the node's size over its distance, whatever the scene's scale — zero for leaf patches
    /// (uniform exitance); cluster links, the unit direction w.
    shape: u32,
}

impl Link {
    /// A leaf or far-field link to a node of area `area` (m²): coefficient `coeff` > 0 and
    /// gradient `grad` (zero for a leaf).
    pub(crate) fn far(node: u32, coeff: f64, grad: DVec3, area: f64) -> Self {
        let rel = match coeff > 0.0 && area > 0.0 {
            true => grad * (moment_scale(area) / coeff),
            false => DVec3::ZERO,
        };
        Link {
            node,
            coeff: coeff as f32,
            shape: shape_bits(rel),
        }
    }

    /// A link to a leaf patch (uniform exitance: no gradient).
    pub(crate) fn plain(node: u32, coeff: f64) -> Self {
        Link {
            node,
            coeff: coeff as f32,
            shape: 0,
        }
    }

    /// A cluster link: K > 0 and the unit direction `w` from the node to the receiver.
    pub(crate) fn cluster_link(node: u32, k: f64, w: DVec3) -> Self {
        Link {
            node,
            coeff: -k as f32,
            shape: shape_bits(w),
        }
    }

    /// A link from its stored parts ([`Link::stored`]).
    pub(crate) fn from_stored(node: u32, coeff: f32, shape: u32) -> Self {
        Link { node, coeff, shape }
    }

    /// The stored parts: node, coefficient, the shape's bits.
    pub(crate) fn stored(&self) -> (u32, f32, u32) {
        (self.node, self.coeff, self.shape)
    }

    /// The stored vector: for a far-field link the gradient × A^(3/2) / coeff, so the gradient
    /// term is coeff × this · first moment / [`moment_scale`] (`NodeField` keeps its moments
    /// divided by it; the solver's transpose divides its sums per node).
    pub(crate) fn relative(&self) -> DVec3 {
        let exponent = (self.shape >> 27) as i32 - SHAPE_LOW;
        let unit = exp2(exponent) / SHAPE_STEPS;
        let component = |k: u32| (((self.shape >> (18 - 9 * k)) << 23) as i32 >> 23) as f64;
        DVec3::new(component(0), component(1), component(2)) * unit
    }

    /// Whether the link carries a gradient (a far-field link) or direction (a cluster link).
    pub(crate) fn has_shape(&self) -> bool {
        self.shape & 0x07ff_ffff != 0
    }

    pub(crate) fn is_cluster(&self) -> bool {
        self.coeff < 0.0
    }

    /// For a cluster link: K and the unit direction from the node to the receiver.
    pub(crate) fn cluster(&self) -> (f64, DVec3) {
        (-self.coeff as f64, self.relative().normalize_or_zero())
    }
}

/// A^(3/2) of a node's area A (m²): what a far-field link's stored gradient is multiplied by,
/// and the first moments it applies to divided by, to make both scale-free.
pub(crate) fn moment_scale(area: f64) -> f64 {
    area * area.sqrt()
}

/// The exponents a shape's scale takes: 2^−27 … 2^4.
const SHAPE_LOW: i32 = 27;
const SHAPE_HIGH: i32 = 4;
/// Steps of a component's 9 signed bits across the scale.
const SHAPE_STEPS: f64 = 255.0;

/// A vector in 32 bits: a shared scale 2^e (5 bits, the least power of two not below its
/// largest |component|, within 2^−27 … 2^4) and each component in 9 signed bits, round(x/2^e ×
/// 255). Each component comes back within 2^e/510 < 1/255 of the largest, so the vector within
/// √3/255 (0.7 %) of its length. Non-finite components count as 0; beyond 2^4, clamped.
fn shape_bits(v: DVec3) -> u32 {
    let v = v.to_array().map(|x| if x.is_finite() { x } else { 0.0 });
    let max = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if max == 0.0 {
        return 0;
    }
    let exponent = ceil_log2(max).clamp(-SHAPE_LOW, SHAPE_HIGH);
    let unit = exp2(exponent) / SHAPE_STEPS;
    let bits =
        v.map(|x| ((x / unit).round().clamp(-SHAPE_STEPS, SHAPE_STEPS) as i32 as u32) & 0x1ff);
    (((exponent + SHAPE_LOW) as u32) << 27) | (bits[0] << 18) | (bits[1] << 9) | bits[2]
}

/// 2^e exactly, for e within the normal range (from its bits: `powi` is a library call on the
/// solver's hot path, where every far-field link is read each iteration).
fn exp2(e: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&e));
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// ⌈log₂ x⌉ for a positive normal `x`, exactly (from its bits: no rounding of a logarithm).
pub(crate) fn ceil_log2(x: f64) -> i32 {
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32 - 1023;
    exponent + (bits & 0x000f_ffff_ffff_ffff != 0) as i32
}

/// A link without a gradient — every link to one patch (a leaf of the tree, whose exitance is
/// uniform): a node and a coefficient, stored without a shape ([`super::packed`]). Most links
/// are leaves, so their size sets much of a bake's memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leaf {
    pub node: u32,
    pub coeff: f32,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient a far link applies, for its node of area `area`.
    fn decoded(l: &Link, area: f64) -> DVec3 {
        l.relative() * (l.coeff as f64 / moment_scale(area))
    }

    #[test]
    fn exp2_is_powi_bit_for_bit_over_the_shapes_exponents() {
        for e in -SHAPE_LOW - 2..=SHAPE_HIGH + 2 {
            assert_eq!(exp2(e).to_bits(), 2f64.powi(e).to_bits(), "2^{e}");
        }
    }

    /// A far link's gradient comes back within 0.7 % of its length at every scene scale (a node 1 mm
    /// to 100 m across, 10 node sizes away), and a cluster link's direction likewise.
    #[test]
    fn gradients_keep_their_length_to_under_a_percent_at_any_scale() {
        for size in [1e-3, 1.0, 100.0] {
            let (area, dist) = (size * size, 10.0 * size);
            // The density's gradient is about the density (coeff / area) over the distance.
            let coeff = 0.3 * area / (dist * dist);
            let grad = DVec3::new(3.0, -1.0, 0.5) * coeff / (area * dist);
            let l = Link::far(7, coeff, grad, area);
            let back = decoded(&l, area);
            assert!(
                (back - grad).length() <= 7e-3 * grad.length(),
                "size {size}: {back} against {grad}"
            );
            assert!(l.has_shape() && !l.is_cluster());
        }
        // Kilometre-sized nodes far away, millimetre ones close: still inside the scales' range.
        for (size, dist) in [(1e3, 1e7), (1e-3, 1.5e-3)] {
            let (area, coeff) = (size * size, 1e-3);
            let grad = DVec3::new(0.0, 2.0, -1.0) * coeff / (area * dist);
            let back = decoded(&Link::far(1, coeff, grad, area), area);
            assert!(
                (back - grad).length() <= 7e-3 * grad.length(),
                "{size} at {dist}"
            );
        }
        let leaf = Link::far(3, 0.2, DVec3::ZERO, 0.01);
        assert!(!leaf.has_shape() && leaf.relative() == DVec3::ZERO);
        let w = DVec3::new(0.48, -0.6, 0.64);
        let (k, back) = Link::cluster_link(9, 0.25, w).cluster();
        assert!((k - 0.25).abs() < 1e-7 && (back - w).length() < 7e-3);
        // Components of every sign and size, and a largest just above and at a power of two.
        for v in [
            DVec3::new(0.5000001, -0.25, 1e-9),
            DVec3::new(-1.0, 0.5, 0.5),
            DVec3::new(1e-7, -3e-8, 2e-8),
            DVec3::new(12.0, -15.9, 0.01),
        ] {
            let back = Link::far(1, 1.0, v, 1.0).relative();
            let max = v.abs().max_element();
            assert!(
                (back - v).abs().max_element() <= max / 255.0 * 1.0001,
                "{v} → {back}"
            );
        }
    }
}
