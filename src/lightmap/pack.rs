//! Placeholder shelf packer (replaced by the measured packer).

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    pub w: u32,
    pub h: u32,
}
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Place {
    pub atlas: usize,
    pub x: u32,
    pub y: u32,
}
pub struct Packing {
    pub atlases: Vec<(u32, u32)>,
    pub places: Vec<Vec<Place>>,
}
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooBig {
    pub group: usize,
}

struct Shelves {
    x: u32,
    y: u32,
    row: u32,
    used: (u32, u32),
}

pub fn pack(groups: &[Vec<Rect>], max_edge: u32) -> Result<Packing, TooBig> {
    let mut atlases: Vec<Shelves> = Vec::new();
    let mut places = Vec::new();
    for (g, rects) in groups.iter().enumerate() {
        let mut order: Vec<usize> = (0..rects.len()).collect();
        order.sort_by_key(|&i| (std::cmp::Reverse(rects[i].h), i));
        let try_in = |s: &Shelves| -> Option<(Shelves, Vec<(usize, u32, u32)>)> {
            let mut s = Shelves { ..*s };
            let mut out = Vec::new();
            for &i in &order {
                let r = rects[i];
                if r.w > max_edge || r.h > max_edge {
                    return None;
                }
                if s.x + r.w > max_edge {
                    s.y += s.row;
                    s.x = 0;
                    s.row = 0;
                }
                if s.y + r.h > max_edge {
                    return None;
                }
                out.push((i, s.x, s.y));
                s.x += r.w;
                s.row = s.row.max(r.h);
                s.used = (s.used.0.max(s.x), s.used.1.max(s.y + r.h));
            }
            Some((s, out))
        };
        let mut done = None;
        for (a, s) in atlases.iter().enumerate() {
            if let Some(r) = try_in(s) {
                done = Some((a, r));
                break;
            }
        }
        if done.is_none() {
            let empty = Shelves {
                x: 0,
                y: 0,
                row: 0,
                used: (0, 0),
            };
            let r = try_in(&empty).ok_or(TooBig { group: g })?;
            atlases.push(empty);
            done = Some((atlases.len() - 1, r));
        }
        let (a, (s, out)) = done.unwrap();
        atlases[a] = s;
        let mut p = vec![
            Place {
                atlas: a,
                x: 0,
                y: 0
            };
            rects.len()
        ];
        for (i, x, y) in out {
            p[i] = Place { atlas: a, x, y };
        }
        places.push(p);
    }
    Ok(Packing {
        atlases: atlases
            .iter()
            .map(|s| {
                (
                    s.used.0.div_ceil(4).max(1) * 4,
                    s.used.1.div_ceil(4).max(1) * 4,
                )
            })
            .collect(),
        places,
    })
}
