//! Gathered rows packed for storage. A row's coefficients are stored in 16 bits (sign, 5-bit
//! exponent, 10-bit mantissa) relative to the row's scale (the least power of two not below its
//! largest |coefficient|), its far-field and cluster links' shapes in 32 bits as made
//! ([`Link::stored`]); the node indices are stored as differences between consecutive ones in
//! variable-length bytes (7 bits a byte, zig-zag signed). A gather visits the tree depth first,
//! so a row's links come in ascending node order, near each other: most differences take one or
//! two bytes instead of four. 8 bytes a leaf link become about 3, 16 a far link about 7.
//!
//! Why 16 bits are enough: a coefficient comes back within 2⁻¹¹ of itself (4.9·10⁻⁴), rounded
//! to nearest, or as 0 when below 2⁻³¹ of its row's scale; what rounding takes from a row's sum
//! is given back to its largest link, so the sum (a closed receiver's coverage, 1) comes back
//! within half a step of that link. The solver balances the operator from the rows as stored,
//! so what it conserves is what it applies.
//!
//! Invariants: a row reads back its links in order, nodes and shapes exactly, coefficients as
//! [`quantised`]; packing a row read back gives the same bytes (rounding is idempotent: the
//! scale of the rounded row is the scale of the row); a row's bytes depend only on that row
//! (each list starts from node 0), so rows are copied as bytes.

use super::link::{self, Leaf, Link};

/// One row's leaf links, packed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leaves<'a> {
    /// The row's scale as a power of two.
    scale: i8,
    coeffs: &'a [u16],
    nodes: &'a [u8],
}

/// One row's far-field and cluster links, packed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarLinks<'a> {
    scale: i8,
    coeffs: &'a [u16],
    shapes: &'a [u32],
    nodes: &'a [u8],
}

/// The row's scale: the exponent of the least power of two not below its largest |c| once
/// that is rounded ([`encode_coeff`]; so a rounded row has its row's scale), 0 when all are zero.
/// Coefficients are form factors (at most a few), far inside the exponents' range.
fn row_scale(coeffs: impl Iterator<Item = f32>) -> i8 {
    let max = coeffs.fold(0.0f32, |m, c| m.max(c.abs()));
    if !(max > 0.0 && max.is_finite()) {
        return 0;
    }
    let first = ceil_log2(max);
    ceil_log2(decode_coeff(encode_coeff(max, first), first))
}

/// ⌈log₂ x⌉ kept within [−90, 120] (so [`decode_coeff`]'s exponents stay normal).
fn ceil_log2(x: f32) -> i8 {
    link::ceil_log2(x as f64).clamp(-90, 120) as i8
}

/// The smallest exponent (relative to the scale) a stored coefficient keeps; below it, 0.
const LOW: i32 = 31;

/// `c` stored relative to the scale 2^`scale` as 16 bits: sign, then |c|/2^scale's f32 exponent
/// (offset by [`LOW`]) and mantissa rounded to 10 bits; 0 for |c| ≤ 2^(scale − LOW). Decoding is
/// a shift and an add.
fn encode_coeff(c: f32, scale: i8) -> u16 {
    let x = c.abs() * f32::from_bits(((127 - scale as i32) as u32) << 23);
    let rounded = (x.to_bits() + 0x1000) >> 13;
    let low = ((127 - LOW) as u32) << 10;
    let magnitude = match rounded > low {
        true => (rounded - low).min(0x7fff) as u16,
        false => 0,
    };
    magnitude | (((c < 0.0) as u16) << 15)
}

fn decode_coeff(v: u16, scale: i8) -> f32 {
    let magnitude = (v & 0x7fff) as u32;
    if magnitude == 0 {
        return 0.0;
    }
    let offset = ((127 - LOW + scale as i32) as u32) << 10;
    f32::from_bits(((magnitude + offset) << 13) | (((v & 0x8000) as u32) << 16))
}

/// A row's scale and its coefficients as stored: each rounded, and then the largest one
/// rounded again with what the rounding took from the row's sum added, so that the sum comes
/// back within half a step of the largest link rather than within the sum of every link's half
/// step. Where that would change the row's scale or the link's sign, the next largest (of the
/// four largest) takes it instead.
fn stored(coeffs: &[f32]) -> (i8, Vec<u16>) {
    let scale = row_scale(coeffs.iter().copied());
    let mut stored: Vec<u16> = coeffs.iter().map(|&c| encode_coeff(c, scale)).collect();
    let lost: f64 = (coeffs.iter().zip(&stored))
        .map(|(&c, &v)| c as f64 - decode_coeff(v, scale) as f64)
        .sum();
    if lost == 0.0 {
        return (scale, stored);
    }
    let largest = four_largest(coeffs);
    for &k in &largest {
        let mended = encode_coeff((decode_coeff(stored[k], scale) as f64 + lost) as f32, scale);
        let keeps_scale = ceil_log2(decode_coeff(mended, scale).abs()) == scale || k != largest[0];
        let below_scale =
            decode_coeff(mended, scale).abs() <= decode_coeff(stored[largest[0]], scale).abs();
        if (mended >> 15) == (stored[k] >> 15) && keeps_scale && (k == largest[0] || below_scale) {
            stored[k] = mended;
            break;
        }
    }
    (scale, stored)
}

/// The indices of the (up to) four largest |c|, largest first, ties by index: one pass.
fn four_largest(coeffs: &[f32]) -> Vec<usize> {
    let mut best: Vec<usize> = Vec::with_capacity(5);
    for k in 0..coeffs.len() {
        let at = best.partition_point(|&b| coeffs[b].abs() >= coeffs[k].abs());
        if at < 4 {
            best.insert(at, k);
            best.truncate(4);
        }
    }
    best
}

/// A row's coefficients as a packed row reads them back.
pub fn quantised(coeffs: &[f32]) -> Vec<f32> {
    let (scale, stored) = stored(coeffs);
    stored.iter().map(|&v| decode_coeff(v, scale)).collect()
}

impl<'a> Leaves<'a> {
    pub(crate) fn len(&self) -> usize {
        self.coeffs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// The links, in the order packed.
    pub(crate) fn iter(self) -> impl Iterator<Item = Leaf> + 'a {
        let mut nodes = Nodes::new(self.nodes);
        let scale = self.scale;
        (self.coeffs.iter()).map(move |&c| Leaf {
            node: nodes.next(),
            coeff: decode_coeff(c, scale),
        })
    }
}

impl<'a> FarLinks<'a> {
    pub(crate) fn len(&self) -> usize {
        self.coeffs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// The links, in the order packed.
    pub(crate) fn iter(self) -> impl Iterator<Item = Link> + 'a {
        let mut nodes = Nodes::new(self.nodes);
        let scale = self.scale;
        (self.coeffs.iter().zip(self.shapes))
            .map(move |(&c, &shape)| Link::from_stored(nodes.next(), decode_coeff(c, scale), shape))
    }
}

/// Decodes a list of node differences.
struct Nodes<'a> {
    bytes: &'a [u8],
    at: usize,
    node: u32,
}

impl<'a> Nodes<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Nodes {
            bytes,
            at: 0,
            node: 0,
        }
    }

    /// The next node (the caller asks for no more than were packed).
    #[inline]
    fn next(&mut self) -> u32 {
        let b = self.bytes[self.at];
        self.at += 1;
        let mut v = (b & 0x7f) as u64;
        let mut shift = 7;
        let mut more = b >= 0x80;
        while more {
            let b = self.bytes[self.at];
            self.at += 1;
            v |= ((b & 0x7f) as u64) << shift;
            shift += 7;
            more = b >= 0x80;
        }
        let d = ((v >> 1) as i64) ^ -((v & 1) as i64);
        self.node = (self.node as i64 + d) as u32;
        self.node
    }
}

/// Append `nodes` to `bytes` as differences, the first from 0.
fn encode(bytes: &mut Vec<u8>, nodes: impl IntoIterator<Item = u32>) {
    let mut last = 0i64;
    for node in nodes {
        let d = node as i64 - last;
        last = node as i64;
        let mut v = ((d << 1) ^ (d >> 63)) as u64;
        while v >= 0x80 {
            bytes.push((v as u8) | 0x80);
            v >>= 7;
        }
        bytes.push(v as u8);
    }
}

/// Rows packed one after another: row j is [`PackedRows::row`]`(j)`.
#[derive(Debug, Clone)]
pub struct PackedRows {
    /// Per row, where it starts: leaf links, their node bytes, far links, their node bytes;
    /// one more entry closes the last row.
    at: Vec<[u32; 4]>,
    /// Per row, its scale ([`row_scale`]).
    scales: Vec<i8>,
    leaf_coeffs: Vec<u16>,
    leaf_nodes: Vec<u8>,
    far_coeffs: Vec<u16>,
    far_shapes: Vec<u32>,
    far_nodes: Vec<u8>,
}

impl Default for PackedRows {
    fn default() -> Self {
        PackedRows {
            at: vec![[0; 4]],
            scales: Vec::new(),
            leaf_coeffs: Vec::new(),
            leaf_nodes: Vec::new(),
            far_coeffs: Vec::new(),
            far_shapes: Vec::new(),
            far_nodes: Vec::new(),
        }
    }
}

impl PackedRows {
    /// No rows, with room for `leaves` leaf links and `far` others in `rows` rows.
    pub(crate) fn with_capacity(rows: usize, leaves: usize, far: usize) -> Self {
        let mut at = Vec::with_capacity(rows + 1);
        at.push([0; 4]);
        PackedRows {
            at,
            scales: Vec::with_capacity(rows),
            leaf_coeffs: Vec::with_capacity(leaves),
            leaf_nodes: Vec::with_capacity(leaves * 2),
            far_coeffs: Vec::with_capacity(far),
            far_shapes: Vec::with_capacity(far),
            far_nodes: Vec::with_capacity(far * 2),
        }
    }

    /// Append one row: its leaf links and its other links.
    pub(crate) fn push(&mut self, leaves: &[Leaf], far: &[Link]) {
        let coeffs: Vec<f32> = (leaves.iter().map(|l| l.coeff))
            .chain(far.iter().map(|l| l.coeff))
            .collect();
        let (scale, stored) = stored(&coeffs);
        encode(&mut self.leaf_nodes, leaves.iter().map(|l| l.node));
        (self.leaf_coeffs).extend_from_slice(&stored[..leaves.len()]);
        encode(&mut self.far_nodes, far.iter().map(|l| l.node));
        self.far_coeffs.extend_from_slice(&stored[leaves.len()..]);
        (self.far_shapes).extend(far.iter().map(|l| l.stored().2));
        self.scales.push(scale);
        self.close_row();
    }

    /// Append a row packed elsewhere (its bytes copied).
    pub(crate) fn push_packed(&mut self, leaves: Leaves, far: FarLinks) {
        debug_assert_eq!(leaves.scale, far.scale);
        self.scales.push(leaves.scale);
        self.leaf_coeffs.extend_from_slice(leaves.coeffs);
        self.leaf_nodes.extend_from_slice(leaves.nodes);
        self.far_coeffs.extend_from_slice(far.coeffs);
        self.far_shapes.extend_from_slice(far.shapes);
        self.far_nodes.extend_from_slice(far.nodes);
        self.close_row();
    }

    fn close_row(&mut self) {
        self.at.push([
            self.leaf_coeffs.len() as u32,
            self.leaf_nodes.len() as u32,
            self.far_coeffs.len() as u32,
            self.far_nodes.len() as u32,
        ]);
    }

    /// Release the spare capacity (the rows are complete).
    pub(crate) fn shrink(&mut self) {
        self.leaf_nodes.shrink_to_fit();
        self.far_nodes.shrink_to_fit();
    }

    pub(crate) fn rows(&self) -> usize {
        self.at.len() - 1
    }

    /// Number of links in all rows, leaves included.
    pub(crate) fn links(&self) -> usize {
        self.leaf_coeffs.len() + self.far_coeffs.len()
    }

    /// Row `j`: its leaf links and its other links.
    pub(crate) fn row(&self, j: usize) -> (Leaves<'_>, FarLinks<'_>) {
        let ([l0, b0, f0, c0], [l1, b1, f1, c1]) = (self.at[j], self.at[j + 1]);
        let span = |a: u32, b: u32| a as usize..b as usize;
        (
            Leaves {
                scale: self.scales[j],
                coeffs: &self.leaf_coeffs[span(l0, l1)],
                nodes: &self.leaf_nodes[span(b0, b1)],
            },
            FarLinks {
                scale: self.scales[j],
                coeffs: &self.far_coeffs[span(f0, f1)],
                shapes: &self.far_shapes[span(f0, f1)],
                nodes: &self.far_nodes[span(c0, c1)],
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// Rows of ascending, descending, repeated and extreme node indices come back with their
    /// nodes and shapes exact and their coefficients as [`quantised`], and rows copied as bytes
    /// read the same.
    #[test]
    fn rows_come_back() {
        let rows: Vec<Vec<u32>> = vec![
            vec![],
            vec![0, 1, 2, 130, 131, 20_000, 2_000_000, u32::MAX],
            vec![u32::MAX, 0, 7, 7, 3, 1 << 31],
            vec![5],
        ];
        let leaves = |r: &[u32]| -> Vec<Leaf> {
            (r.iter().enumerate())
                .map(|(k, &node)| Leaf {
                    node,
                    coeff: 0.125 * k as f32 - 1e-9,
                })
                .collect()
        };
        let far = |r: &[u32]| -> Vec<Link> {
            (r.iter().rev().enumerate())
                .map(|(k, &node)| match k % 3 {
                    0 => Link::plain(node, 0.5),
                    1 => Link::far(node, 0.25, DVec3::new(0.1, -0.2, 0.3), 2.0),
                    _ => Link::cluster_link(node, 0.75, DVec3::new(0.0, 0.6, 0.8)),
                })
                .collect()
        };
        let mut packed = PackedRows::default();
        for r in &rows {
            packed.push(&leaves(r), &far(r));
        }
        let mut copied = PackedRows::default();
        for j in 0..packed.rows() {
            let (l, f) = packed.row(j);
            copied.push_packed(l, f);
        }
        assert_eq!(packed.rows(), rows.len());
        for (j, r) in rows.iter().enumerate() {
            let (l, f) = packed.row(j);
            let (want_l, want_f) = (leaves(r), far(r));
            let all: Vec<f32> = (want_l.iter().map(|x| x.coeff))
                .chain(want_f.iter().map(|x| x.coeff))
                .collect();
            let q = quantised(&all);
            let got_l: Vec<Leaf> = l.iter().collect();
            let got_f: Vec<Link> = f.iter().collect();
            assert_eq!((got_l.len(), got_f.len()), (r.len(), r.len()));
            for (k, (got, want)) in got_l.iter().zip(&want_l).enumerate() {
                assert_eq!((got.node, got.coeff), (want.node, q[k]), "row {j}");
            }
            for (k, (got, want)) in got_f.iter().zip(&want_f).enumerate() {
                let (node, coeff, shape) = got.stored();
                let (w_node, _, w_shape) = want.stored();
                assert_eq!(
                    (node, coeff, shape),
                    (w_node, q[r.len() + k], w_shape),
                    "row {j}"
                );
            }
            assert_eq!(copied.row(j), packed.row(j));
        }
        // Neighbouring nodes take one byte each.
        let mut near = PackedRows::default();
        let run: Vec<Leaf> = (1000..1100).map(|node| Leaf { node, coeff: 1.0 }).collect();
        near.push(&run, &[]);
        assert_eq!(near.leaf_nodes.len(), 2 + 99);
    }

    /// Every coefficient within 2⁻¹¹ of itself, or 2⁻³¹ of its row's scale when small (the bound
    /// the module states), but for the largest, which also takes what the others' rounding took
    /// from the sum; signs kept; the row's sum within half a step of the largest; a row read back
    /// and packed again gives the same bytes, also where the largest coefficient rounds to a
    /// power of two from above or below.
    #[test]
    fn coefficients_keep_half_precision_and_repack_to_the_same_bytes() {
        let mut rows: Vec<Vec<f32>> = vec![
            vec![0.0; 3],
            vec![1.0, 0.5, -0.25],
            vec![0.5 * (1.0 + 2f32.powi(-13)), 0.3, 1e-9],
            vec![0.5 * (1.0 - 2f32.powi(-13)), -0.1, 0.2],
            vec![3.7e-6, 1.2e-7, -2.0e-6],
            vec![2.5, 0.99, 1e-12],
        ];
        // Spreads of magnitudes from 10⁻⁸ to 1, and 300 links of one size, as rows have.
        let mut x = 0.618f64;
        let mut next = || {
            x = (x * 997.0 + 0.123).fract();
            x
        };
        rows.push((0..500).map(|_| 10f64.powf(-8.0 * next()) as f32).collect());
        rows.push((0..300).map(|_| (0.003 + 0.0005 * next()) as f32).collect());
        for c in &rows {
            let leaves: Vec<Leaf> = (c.iter().enumerate())
                .map(|(k, &coeff)| Leaf {
                    node: k as u32,
                    coeff,
                })
                .collect();
            let far: Vec<Link> = c.iter().map(|&v| Link::plain(7, v as f64)).collect();
            let mut once = PackedRows::default();
            once.push(&leaves, &far);
            let (l, f) = once.row(0);
            let back_l: Vec<Leaf> = l.iter().collect();
            let back_f: Vec<Link> = f.iter().collect();
            let scale = 2f32.powi(row_scale(c.iter().copied()) as i32);
            let max = c.iter().fold(0.0f32, |m, v| m.max(v.abs()));
            // The scale is not below the largest once rounded (nor twice it).
            assert!(max <= scale * (1.0 + 2f32.powi(-11)), "{max} {scale}");
            assert!(scale <= 2.0 * max || max == 0.0, "{max} {scale}");
            let largest = c.iter().position(|v| v.abs() == max).unwrap_or(0);
            let total: f64 = c.iter().map(|&v| v.abs() as f64).sum();
            let back: Vec<f32> = back_l.iter().map(|x| x.coeff).collect();
            for (k, (&got, &want)) in back.iter().zip(c).enumerate() {
                let mut bound = (want.abs() * 2f32.powi(-11)).max(scale * 2f32.powi(-31));
                if k == largest {
                    bound += (total * 2f64.powi(-11)) as f32;
                }
                assert!(
                    (got - want).abs() <= bound,
                    "{got} vs {want} (scale {scale})"
                );
                assert!(got * want >= 0.0, "{got} vs {want}");
            }
            // The row holds `c` twice (as leaves and as far links).
            let sum = |v: &[f32]| v.iter().map(|&x| x as f64).sum::<f64>();
            let far_back: Vec<f32> = back_f.iter().map(|x| x.stored().1).collect();
            let off = (sum(&back) + sum(&far_back) - 2.0 * sum(c)).abs();
            assert!(
                off <= scale as f64 * 2f64.powi(-11),
                "sum off by {off} (scale {scale})"
            );
            let mut twice = PackedRows::default();
            twice.push(&back_l, &back_f);
            assert_eq!(twice.row(0), once.row(0), "{c:?}");
        }
    }
}
