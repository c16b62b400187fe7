//! The binary glTF container (`.glb`): a 12-byte header, a JSON chunk, an optional BIN chunk.
//!
//! Input: the whole file. Output: the JSON chunk and the BIN chunk, borrowed from the input.
//! Invariant: never panics or reads past the end, whatever the bytes; a truncated or malformed
//! container gives a message saying what is wrong. Unknown chunk types are skipped (the spec
//! tells readers to ignore them).

const MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// The chunks of a GLB file.
#[derive(Debug)]
pub(crate) struct Glb<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

/// True when `bytes` starts like a GLB file.
pub(crate) fn is_glb(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Split a GLB file into its chunks.
pub(crate) fn parse(bytes: &[u8]) -> Result<Glb<'_>, String> {
    if bytes.len() < 12 {
        return Err(format!(
            "truncated GLB: the header needs 12 bytes, the file has {}",
            bytes.len()
        ));
    }
    if !is_glb(bytes) {
        return Err("not a GLB file (no 'glTF' magic)".into());
    }
    let version = u32_at(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(format!("GLB version {version} is not supported (only 2)"));
    }
    let length = u32_at(bytes, 8).unwrap_or(0) as usize;
    if length > bytes.len() {
        return Err(format!(
            "truncated GLB: the header declares {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    if length < 12 {
        return Err(format!("malformed GLB: declared length {length} < 12"));
    }
    let data = &bytes[..length];
    let mut offset = 12;
    let mut json = None;
    let mut bin = None;
    let mut index = 0;
    while offset < data.len() {
        let (Some(chunk_length), Some(chunk_type)) =
            (u32_at(data, offset), u32_at(data, offset + 4))
        else {
            return Err(format!(
                "truncated GLB: chunk {index} header at byte {offset} is cut off"
            ));
        };
        let start = offset + 8;
        let end = start
            .checked_add(chunk_length as usize)
            .filter(|&e| e <= data.len())
            .ok_or_else(|| {
                format!(
                    "truncated GLB: chunk {index} declares {chunk_length} bytes but only {} remain",
                    data.len() - start
                )
            })?;
        let body = &data[start..end];
        match (index, chunk_type) {
            (0, CHUNK_JSON) => json = Some(body),
            (0, _) => return Err("malformed GLB: the first chunk is not JSON".into()),
            (_, CHUNK_BIN) if bin.is_none() => bin = Some(body),
            (_, CHUNK_JSON | CHUNK_BIN) => {
                return Err(format!("malformed GLB: chunk {index} repeats JSON or BIN"));
            }
            _ => {}
        }
        // Chunks are 4-byte aligned; tolerate writers that forget the final padding.
        offset = end.div_ceil(4) * 4;
        index += 1;
    }
    let json = json.ok_or("malformed GLB: no JSON chunk")?;
    Ok(Glb { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
        out.extend_from_slice(json);
        if let Some(bin) = bin {
            out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
            out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
            out.extend_from_slice(bin);
        }
        let n = out.len() as u32;
        out[8..12].copy_from_slice(&n.to_le_bytes());
        out
    }

    #[test]
    fn round_trip_and_truncation() {
        let bytes = glb(b"{}  ", Some(&[1, 2, 3, 4]));
        let g = parse(&bytes).unwrap();
        assert_eq!(g.json, b"{}  ");
        assert_eq!(g.bin, Some(&[1u8, 2, 3, 4][..]));
        for cut in 0..bytes.len() {
            assert!(parse(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        // A header that lies about the length of a chunk.
        let mut bad = bytes.clone();
        bad[12..16].copy_from_slice(&1000u32.to_le_bytes());
        assert!(parse(&bad).unwrap_err().contains("truncated"));
    }
}
