//! Reading glTF accessors (dense and sparse) into `f64` values, with every range checked.
//!
//! Inputs: an accessor, the loaded buffers, the number of components the caller expects and the
//! JSON pointer of the element that uses the accessor (for messages). Output: `count × dims`
//! values, element after element. Integer components are converted as the spec says: normalised
//! ones to [0, 1] / [−1, 1], others as their integer value.
//! Invariants: never panics or reads out of range on malformed input — a wrong element type, a
//! stride smaller than an element, data outside its bufferView or buffer, or a sparse index
//! ≥ count is an error naming the user's pointer and `/accessors/N`.

use super::buffers::view_bytes;
use crate::Result;
use crate::import::context::Ctx;
use ::gltf::accessor::{DataType, Dimensions};

/// Largest element count accepted for an accessor without a bufferView (all zeros + sparse).
const MAX_VIEWLESS_COUNT: usize = 1 << 26;

/// Read `accessor`, which must have `dims` components per element.
pub(super) fn read(
    ctx: &Ctx,
    buffers: &[Vec<u8>],
    accessor: &::gltf::Accessor,
    dims: usize,
    at: &str,
) -> Result<Vec<f64>> {
    let name = format!("accessor /accessors/{}", accessor.index());
    let err = |m: String| ctx.err(at, format!("{name}: {m}"));
    let actual_dims = match accessor.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        _ => 0,
    };
    if actual_dims != dims {
        return Err(err(format!(
            "has type {:?} but {dims} component(s) are expected here",
            accessor.dimensions()
        )));
    }
    let kind = accessor.data_type();
    let normalized = accessor.normalized();
    let elem = kind.size() * dims;
    let count = accessor.count();
    let total = count
        .checked_mul(dims)
        .ok_or_else(|| err(format!("count {count} is too large")))?;
    let mut out;
    if let Some(view) = accessor.view() {
        let bytes = view_bytes(buffers, &view).map_err(&err)?;
        let stride = view.stride().unwrap_or(elem);
        if stride < elem {
            return Err(err(format!(
                "byteStride {stride} of /bufferViews/{} is smaller than one element ({elem} bytes)",
                view.index()
            )));
        }
        let start = accessor.offset();
        let needed = range_end(start, stride, count, elem).filter(|&e| e <= bytes.len());
        if needed.is_none() {
            return Err(err(format!(
                "{count} elements of {elem} bytes (stride {stride}) from byteOffset {start} do \
                 not fit in /bufferViews/{} ({} bytes)",
                view.index(),
                bytes.len()
            )));
        }
        out = Vec::with_capacity(total);
        for i in 0..count {
            let base = start + i * stride;
            for c in 0..dims {
                out.push(component(bytes, base + c * kind.size(), kind, normalized));
            }
        }
    } else {
        if count > MAX_VIEWLESS_COUNT {
            return Err(err(format!(
                "count {count} without a bufferView is too large"
            )));
        }
        out = vec![0.0; total];
    }
    if let Some(sparse) = accessor.sparse() {
        apply_sparse(buffers, &sparse, kind, normalized, dims, count, &mut out).map_err(err)?;
    }
    Ok(out)
}

/// Read an index-like accessor (unsigned integers) as `u32`s.
pub(super) fn read_indices(
    ctx: &Ctx,
    buffers: &[Vec<u8>],
    accessor: &::gltf::Accessor,
    at: &str,
) -> Result<Vec<u32>> {
    if !matches!(
        accessor.data_type(),
        DataType::U8 | DataType::U16 | DataType::U32
    ) || accessor.normalized()
    {
        return Err(ctx.err(
            at,
            format!(
                "accessor /accessors/{}: indices must be unsigned byte, short or int",
                accessor.index()
            ),
        ));
    }
    let values = read(ctx, buffers, accessor, 1, at)?;
    Ok(values.into_iter().map(|v| v as u32).collect())
}

/// End of `count` elements of `elem` bytes, `stride` apart, from `start`; `None` on overflow.
fn range_end(start: usize, stride: usize, count: usize, elem: usize) -> Option<usize> {
    if count == 0 {
        return Some(start);
    }
    stride
        .checked_mul(count - 1)?
        .checked_add(elem)?
        .checked_add(start)
}

/// One component at byte `at` (caller guarantees it is in range).
fn component(bytes: &[u8], at: usize, kind: DataType, normalized: bool) -> f64 {
    let b = &bytes[at..];
    match kind {
        DataType::I8 => {
            let v = b[0] as i8 as f64;
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = b[0] as f64;
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([b[0], b[1]]) as f64;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = u16::from_le_bytes([b[0], b[1]]) as f64;
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
    }
}

fn apply_sparse(
    buffers: &[Vec<u8>],
    sparse: &::gltf::accessor::sparse::Sparse,
    kind: DataType,
    normalized: bool,
    dims: usize,
    count: usize,
    out: &mut [f64],
) -> Result<(), String> {
    let n = sparse.count();
    let indices = sparse.indices();
    let index_kind = match indices.index_type() {
        ::gltf::accessor::sparse::IndexType::U8 => DataType::U8,
        ::gltf::accessor::sparse::IndexType::U16 => DataType::U16,
        ::gltf::accessor::sparse::IndexType::U32 => DataType::U32,
    };
    let index_bytes = view_bytes(buffers, &indices.view())?;
    let index_start = indices.offset();
    if range_end(index_start, index_kind.size(), n, index_kind.size())
        .is_none_or(|e| e > index_bytes.len())
    {
        return Err(format!(
            "{n} sparse indices do not fit in /bufferViews/{}",
            indices.view().index()
        ));
    }
    let values = sparse.values();
    let value_bytes = view_bytes(buffers, &values.view())?;
    let elem = kind.size() * dims;
    let value_start = values.offset();
    if range_end(value_start, elem, n, elem).is_none_or(|e| e > value_bytes.len()) {
        return Err(format!(
            "{n} sparse values do not fit in /bufferViews/{}",
            values.view().index()
        ));
    }
    for k in 0..n {
        let index = component(
            index_bytes,
            index_start + k * index_kind.size(),
            index_kind,
            false,
        ) as usize;
        if index >= count {
            return Err(format!("sparse index {index} ≥ count {count}"));
        }
        for c in 0..dims {
            out[index * dims + c] = component(
                value_bytes,
                value_start + k * elem + c * kind.size(),
                kind,
                normalized,
            );
        }
    }
    Ok(())
}
