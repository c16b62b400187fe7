//! Padding: empty texels beside a chart take the mean of their filled neighbours, two rings
//! deep, so bilinear filtering at a chart's edge never reads an empty texel.
//!
//! Input: an atlas and which of its texels hold values. Output: the same atlas with the two
//! rings of empty texels around them filled (their `area` stays 0). Rings are filled one after
//! the other from the previous state, so the result does not depend on traversal order.

use crate::result::Atlas;

/// Rings of empty texels filled around each chart.
const RINGS: usize = 2;

pub(crate) fn dilate(a: &mut Atlas, mut filled: Vec<bool>) {
    let (w, h) = (a.width as usize, a.height as usize);
    for _ in 0..RINGS {
        let mut next = Vec::new();
        for row in 0..h {
            for col in 0..w {
                let k = row * w + col;
                if filled[k] {
                    continue;
                }
                let mut n = 0.0f32;
                let mut sum = [0.0f32; 9];
                for r in row.saturating_sub(1)..(row + 2).min(h) {
                    for c in col.saturating_sub(1)..(col + 2).min(w) {
                        let j = r * w + c;
                        if !filled[j] {
                            continue;
                        }
                        n += 1.0;
                        let v = values(a, j);
                        for (s, x) in sum.iter_mut().zip(v) {
                            *s += x;
                        }
                    }
                }
                if n > 0.0 {
                    next.push((k, sum.map(|s| s / n)));
                }
            }
        }
        for (k, v) in next {
            a.luminance[k] = [v[0], v[1], v[2]];
            a.illuminance[k] = v[3];
            a.illuminance_direct[k] = v[4];
            a.display[k] = [v[5], v[6], v[7]];
            filled[k] = true;
        }
    }
}

fn values(a: &Atlas, k: usize) -> [f32; 9] {
    let [r, g, b] = a.luminance[k];
    let [dr, dg, db] = a.display[k];
    [
        r,
        g,
        b,
        a.illuminance[k],
        a.illuminance_direct[k],
        dr,
        dg,
        db,
        0.0,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_rings_take_their_neighbours_mean_and_no_more() {
        let mut a = Atlas::new(7, 7);
        let k = 3 * 7 + 3;
        a.area[k] = 1.0;
        a.illuminance[k] = 100.0;
        let filled = a.area.iter().map(|x| *x > 0.0).collect();
        dilate(&mut a, filled);
        for row in 0..7usize {
            for col in 0..7usize {
                let d = row.abs_diff(3).max(col.abs_diff(3));
                let e = a.illuminance[row * 7 + col];
                assert_eq!(e, if d <= 2 { 100.0 } else { 0.0 }, "({row}, {col})");
                if d > 0 {
                    assert_eq!(a.area[row * 7 + col], 0.0);
                }
            }
        }
    }
}
