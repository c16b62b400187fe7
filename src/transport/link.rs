//! What a gather row is made of: a receiver's links to nodes of a patch tree.

use glam::DVec3;

/// One source seen by a receiver.
///
/// Leaf and far-field links (`coeff > 0`): E += coeff × node mean + grad · node first moment.
/// Cluster links (`coeff < 0`, a node whose patches face the receiver from both sides):
/// with K = −coeff = cos θ·vis·V/(π d²) (V: the share it does not hide from itself) and w =
/// grad/K the unit direction from the node to the receiver, E += K × Σ weights(w)·S over the
/// node's exitance-weighted normal distribution (`geom::sh::Dist`). Scaling a row scales both
/// forms alike.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    pub node: u32,
    /// Form factor × visible fraction (negated for cluster links).
    pub coeff: f32,
    /// Far-field links: the form-factor density's gradient × visible fraction, applied to the
    /// node's first moment of exitance (zero for leaf patches, where exitance is uniform).
    /// Cluster links: K × the direction to the receiver.
    pub grad: [f32; 3],
}

impl Link {
    /// A link with gradient (or direction × K) `grad`, stored in single precision.
    pub fn new(node: u32, coeff: f64, grad: DVec3) -> Self {
        Link {
            node,
            coeff: coeff as f32,
            grad: [grad.x as f32, grad.y as f32, grad.z as f32],
        }
    }

    pub fn grad(&self) -> DVec3 {
        DVec3::new(
            self.grad[0] as f64,
            self.grad[1] as f64,
            self.grad[2] as f64,
        )
    }

    pub fn is_cluster(&self) -> bool {
        self.coeff < 0.0
    }

    /// For a cluster link: K and the unit direction from the node to the receiver.
    pub fn cluster(&self) -> (f64, DVec3) {
        (-self.coeff as f64, self.grad().normalize_or_zero())
    }
}

/// A link without a gradient — every link to one patch (a leaf of the tree, whose exitance is
/// uniform) — in 8 bytes instead of a [`Link`]'s 20. Most links are leaves, so their size
/// sets much of a bake's memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leaf {
    pub node: u32,
    pub coeff: f32,
}
