//! Gathered rows packed for storage. A row's leaf links keep their coefficients as `f32`; its
//! far-field and cluster links their coefficients and half-precision shapes ([`Link::stored`]);
//! the node indices of both are stored as differences between consecutive ones in
//! variable-length bytes (7 bits a byte, zig-zag signed). A gather visits the tree depth first,
//! so a row's links come in ascending node order, near each other: most differences take one
//! or two bytes instead of four. 8 bytes a leaf link become about 5, 16 a far link about 11.
//!
//! Invariant: a row reads back exactly the links packed, in order; a row's bytes depend only on
//! that row (each list starts from node 0), so rows are copied as bytes.

use super::link::{Leaf, Link};

/// One row's leaf links, packed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leaves<'a> {
    coeffs: &'a [f32],
    nodes: &'a [u8],
}

/// One row's far-field and cluster links, packed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarLinks<'a> {
    coeffs: &'a [f32],
    shapes: &'a [[u16; 3]],
    nodes: &'a [u8],
}

impl<'a> Leaves<'a> {
    pub fn len(&self) -> usize {
        self.coeffs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// The links, in the order packed.
    pub fn iter(self) -> impl Iterator<Item = Leaf> + 'a {
        let mut nodes = Nodes::new(self.nodes);
        (self.coeffs.iter()).map(move |&coeff| Leaf {
            node: nodes.next(),
            coeff,
        })
    }
}

impl<'a> FarLinks<'a> {
    pub fn len(&self) -> usize {
        self.coeffs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.coeffs.is_empty()
    }

    /// The links, in the order packed.
    pub fn iter(self) -> impl Iterator<Item = Link> + 'a {
        let mut nodes = Nodes::new(self.nodes);
        (self.coeffs.iter().zip(self.shapes))
            .map(move |(&coeff, &shape)| Link::from_stored(nodes.next(), coeff, shape))
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
    leaf_coeffs: Vec<f32>,
    leaf_nodes: Vec<u8>,
    far_coeffs: Vec<f32>,
    far_shapes: Vec<[u16; 3]>,
    far_nodes: Vec<u8>,
}

impl Default for PackedRows {
    fn default() -> Self {
        PackedRows {
            at: vec![[0; 4]],
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
    pub fn with_capacity(rows: usize, leaves: usize, far: usize) -> Self {
        let mut at = Vec::with_capacity(rows + 1);
        at.push([0; 4]);
        PackedRows {
            at,
            leaf_coeffs: Vec::with_capacity(leaves),
            leaf_nodes: Vec::with_capacity(leaves * 2),
            far_coeffs: Vec::with_capacity(far),
            far_shapes: Vec::with_capacity(far),
            far_nodes: Vec::with_capacity(far * 2),
        }
    }

    /// Append one row: its leaf links and its other links.
    pub fn push(&mut self, leaves: &[Leaf], far: &[Link]) {
        encode(&mut self.leaf_nodes, leaves.iter().map(|l| l.node));
        self.leaf_coeffs.extend(leaves.iter().map(|l| l.coeff));
        encode(&mut self.far_nodes, far.iter().map(|l| l.node));
        for l in far {
            let (_, coeff, shape) = l.stored();
            self.far_coeffs.push(coeff);
            self.far_shapes.push(shape);
        }
        self.close_row();
    }

    /// Append a row packed elsewhere (its bytes copied).
    pub fn push_packed(&mut self, leaves: Leaves, far: FarLinks) {
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
    pub fn shrink(&mut self) {
        self.leaf_nodes.shrink_to_fit();
        self.far_nodes.shrink_to_fit();
    }

    pub fn rows(&self) -> usize {
        self.at.len() - 1
    }

    /// Number of links in all rows, leaves included.
    pub fn links(&self) -> usize {
        self.leaf_coeffs.len() + self.far_coeffs.len()
    }

    /// Row `j`: its leaf links and its other links.
    pub fn row(&self, j: usize) -> (Leaves<'_>, FarLinks<'_>) {
        let ([l0, b0, f0, c0], [l1, b1, f1, c1]) = (self.at[j], self.at[j + 1]);
        let span = |a: u32, b: u32| a as usize..b as usize;
        (
            Leaves {
                coeffs: &self.leaf_coeffs[span(l0, l1)],
                nodes: &self.leaf_nodes[span(b0, b1)],
            },
            FarLinks {
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

    /// Rows of ascending, descending, repeated and extreme node indices come back exactly, and
    /// rows copied as bytes read the same.
    #[test]
    fn rows_come_back_exactly() {
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
            assert_eq!(l.iter().collect::<Vec<_>>(), leaves(r), "row {j}");
            assert_eq!(f.iter().collect::<Vec<_>>(), far(r), "row {j}");
            assert_eq!((l.len(), f.len()), (r.len(), r.len()));
            assert_eq!(copied.row(j), packed.row(j));
        }
        // Neighbouring nodes take one byte each.
        let mut near = PackedRows::default();
        let run: Vec<Leaf> = (1000..1100).map(|node| Leaf { node, coeff: 1.0 }).collect();
        near.push(&run, &[]);
        assert_eq!(near.leaf_nodes.len(), 2 + 99);
    }
}
