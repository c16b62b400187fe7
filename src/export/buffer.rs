//! The output's single binary buffer, with its `bufferViews` and `accessors`.
//!
//! Input: typed arrays (vertex attributes, indices, encoded images, photometric files) in the order the document is
//! built. Output: the buffer bytes plus the `bufferViews` and `accessors` JSON arrays.
//! Invariants: one bufferView per accessor or image; every view starts at a multiple of 4 bytes
//! and the buffer length is a multiple of 4 (zero padding); `byteStride` is never written;
//! vertex data gets target ARRAY_BUFFER, indices ELEMENT_ARRAY_BUFFER, images and other files no
//! target;
//! `min`/`max` are the exact extremes of the stored `f32` values.

use serde_json::{Map, Value, json};

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;

/// Builder of the binary buffer and the JSON that describes it.
#[derive(Debug, Default)]
pub struct Binary {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Binary {
    /// Append `bytes` as a new bufferView; returns its index.
    fn push_view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        debug_assert_eq!(self.data.len() % 4, 0);
        let mut view = Map::new();
        view.insert("buffer".into(), json!(0));
        view.insert("byteOffset".into(), json!(self.data.len()));
        view.insert("byteLength".into(), json!(bytes.len()));
        if let Some(t) = target {
            view.insert("target".into(), json!(t));
        }
        self.data.extend_from_slice(bytes);
        self.data.resize(self.data.len().next_multiple_of(4), 0);
        self.views.push(Value::Object(view));
        self.views.len() - 1
    }

    fn push_accessor(&mut self, view: usize, component: u32, count: usize, kind: &str) -> usize {
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": component,
            "count": count,
            "type": kind,
        }));
        self.accessors.len() - 1
    }

    fn float_accessor<const N: usize>(
        &mut self,
        values: &[[f32; N]],
        kind: &str,
        min_max: bool,
    ) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = self.push_view(&bytes, Some(ARRAY_BUFFER));
        let index = self.push_accessor(view, FLOAT, values.len(), kind);
        if min_max {
            let mut min = [f32::INFINITY; N];
            let mut max = [f32::NEG_INFINITY; N];
            for v in values {
                for i in 0..N {
                    min[i] = min[i].min(v[i]);
                    max[i] = max[i].max(v[i]);
                }
            }
            let acc = self.accessors[index]
                .as_object_mut()
                .expect("accessor object");
            let widen = |v: [f32; N]| v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
            acc.insert("min".into(), json!(widen(min)));
            acc.insert("max".into(), json!(widen(max)));
        }
        index
    }

    /// A float VEC3 vertex attribute; `min_max` adds the bounds (required for POSITION).
    pub(crate) fn vec3(&mut self, values: &[[f32; 3]], min_max: bool) -> usize {
        self.float_accessor(values, "VEC3", min_max)
    }

    /// A float VEC2 vertex attribute (texture coordinates).
    pub(crate) fn vec2(&mut self, values: &[[f32; 2]]) -> usize {
        self.float_accessor(values, "VEC2", false)
    }

    /// A float SCALAR vertex attribute.
    pub(crate) fn scalar(&mut self, values: &[f32]) -> usize {
        let wrapped: Vec<[f32; 1]> = values.iter().map(|&v| [v]).collect();
        self.float_accessor(&wrapped, "SCALAR", false)
    }

    /// Triangle indices: unsigned short when `vertex_count` < 65536, else unsigned int.
    pub(crate) fn indices(&mut self, triangles: &[[u32; 3]], vertex_count: usize) -> usize {
        let flat = triangles.iter().flatten();
        let (bytes, component): (Vec<u8>, u32) = if vertex_count < 65536 {
            let b = flat.flat_map(|&i| (i as u16).to_le_bytes()).collect();
            (b, UNSIGNED_SHORT)
        } else {
            (flat.flat_map(|&i| i.to_le_bytes()).collect(), UNSIGNED_INT)
        };
        let view = self.push_view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.push_accessor(view, component, triangles.len() * 3, "SCALAR")
    }

    /// Encoded image bytes as a bufferView without target; returns the view index.
    pub(crate) fn image(&mut self, bytes: &[u8]) -> usize {
        self.blob(bytes)
    }

    /// Any other bytes (photometric files) as a bufferView without target; returns its index.
    pub(crate) fn blob(&mut self, bytes: &[u8]) -> usize {
        self.push_view(bytes, None)
    }

    /// The buffer bytes (length a multiple of 4), the bufferViews and the accessors.
    pub(crate) fn finish(self) -> (Vec<u8>, Vec<Value>, Vec<Value>) {
        (self.data, self.views, self.accessors)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_are_aligned_and_bounds_exact() {
        let mut b = Binary::default();
        let i = b.indices(&[[0, 1, 2]], 3);
        let p = b.vec3(&[[0.1, -2.0, 3.0], [1.0, 0.5, -0.25]], true);
        let (data, views, accessors) = b.finish();
        assert_eq!(data.len(), 8 + 24);
        assert_eq!(views[0]["byteLength"], 6);
        assert_eq!(views[1]["byteOffset"], 8);
        assert_eq!(accessors[i]["componentType"], UNSIGNED_SHORT);
        assert_eq!(accessors[p]["min"][0], f64::from(0.1f32));
        assert_eq!(accessors[p]["max"][1], 0.5);
        let mut b = Binary::default();
        let big = b.indices(&[[0, 1, 70000]], 70001);
        let (data, _, accessors) = b.finish();
        assert_eq!(accessors[big]["componentType"], UNSIGNED_INT);
        assert_eq!(&data[8..12], &70000u32.to_le_bytes());
    }
}
