//! Soft shadows of a luminous opening: direct light at a receiver that sees part of a luminaire.
//!
//! Input: the opening (a rectangle in photometric X, Y with half sizes `half`), the receiver
//! point, a visibility test and the near-field and shadow ratios. Output: calls `emit(q, share,
//! fraction)` for pieces of the opening that together cover it once (shares summing to 1), each
//! with the fraction of it seen from the receiver.
//!
//! The rectangle is halved along its longer side; each half gets rays to the two new corner
//! points and inherits the other two, so every piece knows whether its four corners are seen. A
//! piece whose corners agree is taken as wholly seen or hidden once it is small enough for the
//! near field (side ≤ `coarse` × its distance: one sub-source); a piece across the shadow edge
//! is halved further, down to `fine` × its distance; there the edge's crossings of its sides are
//! found by bisection and the piece counts the part of it on the seen side of the line through
//! them. So rays go where the edge crosses the opening, and a straight edge is resolved well
//! below `fine` whatever its direction.

use glam::DVec3;

/// Most halvings: a piece is at least 2⁻⁷ of the opening's side along each axis.
const MAX_DEPTH: u32 = 14;

/// Bisection steps locating a shadow edge on a side of a piece (to 2⁻⁶ of the side): cheaper
/// than halving the pieces further, which doubles the pieces the edge crosses at every level.
const EDGE_STEPS: u32 = 5;

/// How finely to split: near-field and shadow ratios (side / distance).
pub struct Ratios {
    pub coarse: f64,
    pub fine: f64,
}

/// Integrate the opening with half sizes `half` over its visibility from `p`: `world` maps a
/// point of the opening (photometric X, Y) to world space, `sees` traces from `p` to a world
/// point, `emit(q, share, fraction)` receives each piece.
pub(crate) fn integrate(
    half: [f64; 2],
    p: DVec3,
    ratios: &Ratios,
    world: &dyn Fn([f64; 2]) -> DVec3,
    sees: &mut dyn FnMut(DVec3) -> bool,
    emit: &mut dyn FnMut(DVec3, f64, f64),
) {
    let [x, y] = half;
    let corners = [[-x, -y], [x, -y], [x, y], [-x, y]].map(|c| sees(world(c)));
    let mut run = Run {
        p,
        ratios,
        world,
        sees,
        emit,
    };
    run.piece([0.0, 0.0], half, 1.0, 0, corners);
}

struct Run<'a> {
    p: DVec3,
    ratios: &'a Ratios,
    world: &'a dyn Fn([f64; 2]) -> DVec3,
    sees: &'a mut dyn FnMut(DVec3) -> bool,
    emit: &'a mut dyn FnMut(DVec3, f64, f64),
}

impl Run<'_> {
    /// The piece centred on `c` with half sizes `h`; `seen`: its corners (−,−), (+,−), (+,+),
    /// (−,+) in photometric X, Y.
    fn piece(&mut self, c: [f64; 2], h: [f64; 2], share: f64, depth: u32, seen: [bool; 4]) {
        let q = (self.world)(c);
        let dist = (q - self.p).length();
        let longer = if h[0] >= h[1] { 0 } else { 1 };
        let side = 2.0 * h[longer];
        let count = seen.iter().filter(|s| **s).count();
        let agree = count == 0 || count == 4;
        let ratio = if agree {
            self.ratios.coarse
        } else {
            self.ratios.fine
        };
        if depth >= MAX_DEPTH || side <= ratio * dist {
            let fraction = match agree {
                true => count as f64 / 4.0,
                false => self.seen_share(c, h, seen),
            };
            (self.emit)(q, share, fraction);
            return;
        }
        // The two new corners on the split line, at the ends of the other axis.
        let other = 1 - longer;
        let mut a = c;
        a[other] -= h[other];
        let mut b = c;
        b[other] += h[other];
        let (sa, sb) = ((self.sees)((self.world)(a)), (self.sees)((self.world)(b)));
        let [s0, s1, s2, s3] = seen;
        let (low, high) = match longer {
            // Split across X: a = (cx, −y), b = (cx, +y).
            0 => ([s0, sa, sb, s3], [sa, s1, s2, sb]),
            // Split across Y: a = (−x, cy), b = (+x, cy).
            _ => ([s0, s1, sb, sa], [sa, sb, s2, s3]),
        };
        let mut hh = h;
        hh[longer] /= 2.0;
        let (mut cl, mut ch) = (c, c);
        cl[longer] -= hh[longer];
        ch[longer] += hh[longer];
        self.piece(cl, hh, share / 2.0, depth + 1, low);
        self.piece(ch, hh, share / 2.0, depth + 1, high);
    }

    /// The share of the piece (centre `c`, half sizes `h`, corners `seen`) that is seen, when a
    /// straight shadow edge crosses it: the edge's crossing of each of the two sides whose ends
    /// disagree is found by bisection ([`EDGE_STEPS`] rays a side) and the seen part is the
    /// polygon they cut off. Any other pattern (two opposite corners seen) counts its corners.
    fn seen_share(&mut self, c: [f64; 2], h: [f64; 2], seen: [bool; 4]) -> f64 {
        let corner = [
            [c[0] - h[0], c[1] - h[1]],
            [c[0] + h[0], c[1] - h[1]],
            [c[0] + h[0], c[1] + h[1]],
            [c[0] - h[0], c[1] + h[1]],
        ];
        let crossed = (0..4).filter(|&k| seen[k] != seen[(k + 1) % 4]).count();
        if crossed != 2 {
            return seen.iter().filter(|s| **s).count() as f64 / 4.0;
        }
        // Walk round the piece: its seen corners, and where the edge crosses its sides.
        // At most three seen corners and two crossings.
        let (mut polygon, mut len) = ([[0.0; 2]; 5], 0);
        let mut push = |v: [f64; 2]| {
            polygon[len] = v;
            len += 1;
        };
        for k in 0..4 {
            let next = (k + 1) % 4;
            if seen[k] {
                push(corner[k]);
            }
            if seen[k] != seen[next] {
                let (mut from, mut to) = (0.0, 1.0);
                let at = |t: f64| {
                    [
                        corner[k][0] + (corner[next][0] - corner[k][0]) * t,
                        corner[k][1] + (corner[next][1] - corner[k][1]) * t,
                    ]
                };
                for _ in 0..EDGE_STEPS {
                    let mid = (from + to) / 2.0;
                    if (self.sees)((self.world)(at(mid))) == seen[k] {
                        from = mid;
                    } else {
                        to = mid;
                    }
                }
                push(at((from + to) / 2.0));
            }
        }
        let twice_area: f64 = (0..len)
            .map(|i| {
                let (a, b) = (polygon[i], polygon[(i + 1) % len]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum();
        (twice_area.abs() / 2.0 / (4.0 * h[0] * h[1])).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square at z = 1 above the origin, the part beyond a straight line hidden, the line
    /// in several places and directions: the pieces cover it once, and the seen share is the
    /// visible area to well below the fine ratio: pieces of 1/16 of a side, in which an edge is
    /// placed to 1/64 of the piece, so the share is within 1/1024 of the area (asserted to 1/250).
    #[test]
    fn a_straight_edge_is_resolved_below_the_fine_ratio() {
        for (edge, dir) in [
            (-0.37, 0.0),
            (0.0, 0.0),
            (0.21, 0.0),
            (0.5, 0.0),
            (0.1, 0.3),
            (-0.2, 1.1),
        ] {
            // Seen where (x, y)·(cos, sin) ≥ edge.
            let (c, s) = (f64::cos(dir), f64::sin(dir));
            let (mut total, mut lit, mut rays) = (0.0, 0.0, 0);
            integrate(
                [0.5, 0.5],
                DVec3::ZERO,
                &Ratios {
                    coarse: 0.5,
                    fine: 0.06,
                },
                &|c| DVec3::new(c[0], c[1], 1.0),
                &mut |q| {
                    rays += 1;
                    q.x * c + q.y * s >= edge
                },
                &mut |_, share, fraction| {
                    total += share;
                    lit += share * fraction;
                },
            );
            // The visible area, by a fine grid.
            let n = 2000;
            let want = (0..n * n)
                .filter(|k| {
                    let (x, y) = ((k % n) as f64 + 0.5, (k / n) as f64 + 0.5);
                    (x / n as f64 - 0.5) * c + (y / n as f64 - 0.5) * s >= edge
                })
                .count() as f64
                / (n * n) as f64;
            assert!(
                (total - 1.0f64).abs() < 1e-12,
                "pieces cover the opening once"
            );
            assert!(
                (lit - want).abs() < 4e-3,
                "edge {edge} dir {dir}: {lit} against {want}"
            );
            // Along the edge only: a grid as fine as the edge's placement would take 65 536.
            assert!(rays < 500, "edge {edge} dir {dir}: {rays} rays");
        }
    }

    /// Wholly seen: no piece is split below the near-field ratio, and every piece is lit.
    #[test]
    fn an_open_opening_stays_at_the_near_field_split() {
        let mut pieces = Vec::new();
        integrate(
            [0.75, 0.1],
            DVec3::new(0.0, 0.0, -2.0),
            &Ratios {
                coarse: 0.1,
                fine: 0.0125,
            },
            &|c| DVec3::new(c[0], c[1], 0.0),
            &mut |_| true,
            &mut |q, share, fraction| pieces.push((q, share, fraction)),
        );
        assert_eq!(pieces.len(), 8, "1.5 m at 2 m: halved to 0.1875 m");
        assert!(pieces.iter().all(|(_, s, f)| *s == 0.125 && *f == 1.0));
    }
}
