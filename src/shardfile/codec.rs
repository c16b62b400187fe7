//! Little-endian bytes: a writer and a reader that checks every count against the bytes left;
//! a file ends with a checksum of everything before it, so a changed byte is an error, never a
//! wrong value read on.

use glam::DVec3;

pub(super) const VERSION: u32 = 7;

pub(super) struct Writer(pub(super) Vec<u8>);

impl Writer {
    pub(super) fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(super) fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(super) fn f32(&mut self, x: f32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(super) fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub(super) fn vec3(&mut self, v: DVec3) {
        v.to_array().iter().for_each(|x| self.f64(*x));
    }
    pub(super) fn vec3s(&mut self, v: &[DVec3]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|x| self.vec3(*x));
    }
    /// A value as JSON (the meshing records: small, and their fields change with the code).
    pub(super) fn json(&mut self, v: &impl serde::Serialize) {
        let bytes = serde_json::to_vec(v).expect("a record serialises");
        self.u64(bytes.len() as u64);
        self.0.extend_from_slice(&bytes);
    }
    pub(super) fn u32s(&mut self, v: &[u32]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|x| self.u32(*x));
    }
}

pub(super) struct Reader<'a> {
    pub(super) bytes: &'a [u8],
    pub(super) at: usize,
}

impl Reader<'_> {
    pub(super) fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| format!("truncated at byte {}", self.at))?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }
    pub(super) fn header(&mut self, magic: &[u8; 8], what: &str) -> Result<(), String> {
        if self.take(8).ok() != Some(&magic[..]) {
            return Err(format!("not {what}"));
        }
        match self.u32()? {
            VERSION => Ok(()),
            v => Err(format!("version {v}, this bake reads version {VERSION}")),
        }
    }
    pub(super) fn end(&self) -> Result<(), String> {
        match self.at == self.bytes.len() {
            true => Ok(()),
            false => Err(format!("{} bytes left over", self.bytes.len() - self.at)),
        }
    }
    pub(super) fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    pub(super) fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    pub(super) fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    pub(super) fn f32(&mut self) -> Result<f32, String> {
        Ok(f32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    pub(super) fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    /// A count of items of at least `size` bytes each, checked against what is left.
    pub(super) fn len(&mut self, size: usize) -> Result<usize, String> {
        let n = self.u64()?;
        let left = (self.bytes.len() - self.at) as u64;
        match n.checked_mul(size as u64).is_some_and(|b| b <= left) {
            true => Ok(n as usize),
            false => Err(format!(
                "a count of {n} at byte {} runs past the end",
                self.at - 8
            )),
        }
    }
    pub(super) fn vec3(&mut self) -> Result<DVec3, String> {
        Ok(DVec3::new(self.f64()?, self.f64()?, self.f64()?))
    }
    pub(super) fn vec3s(&mut self) -> Result<Vec<DVec3>, String> {
        let n = self.len(24)?;
        (0..n).map(|_| self.vec3()).collect()
    }
    pub(super) fn u32s(&mut self) -> Result<Vec<u32>, String> {
        let n = self.len(4)?;
        (0..n).map(|_| self.u32()).collect()
    }
    pub(super) fn json<T: serde::de::DeserializeOwned>(&mut self) -> Result<T, String> {
        let n = self.len(1)?;
        serde_json::from_slice(self.take(n)?).map_err(|e| e.to_string())
    }
}

/// A 64-bit checksum of `bytes`: word by word, each step a bijection of the running value, so
/// any one changed word (or byte of the tail) changes it.
fn checksum(bytes: &[u8]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut words = bytes.chunks_exact(8);
    for w in &mut words {
        let w = u64::from_le_bytes(w.try_into().unwrap());
        h = (h ^ w).wrapping_mul(PRIME).rotate_left(29);
    }
    for &b in words.remainder() {
        h = (h ^ b as u64).wrapping_mul(PRIME);
    }
    h
}

/// `bytes` with their checksum appended (the file as written).
pub(super) fn seal(mut bytes: Vec<u8>) -> Vec<u8> {
    let sum = checksum(&bytes);
    bytes.extend_from_slice(&sum.to_le_bytes());
    bytes
}

/// The bytes before the checksum, when it matches them.
pub(super) fn unseal(bytes: &[u8]) -> Result<&[u8], String> {
    let Some(at) = bytes.len().checked_sub(8) else {
        return Err(format!("truncated: {} bytes", bytes.len()));
    };
    let (body, sum) = bytes.split_at(at);
    match checksum(body) == u64::from_le_bytes(sum.try_into().unwrap()) {
        true => Ok(body),
        false => Err(
            "damaged: its checksum does not match its bytes (changed or cut since it was written)"
                .into(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_changed_byte_or_cut_breaks_the_seal() {
        let body: Vec<u8> = (0..203u32).map(|i| (i * 37 % 251) as u8).collect();
        let sealed = seal(body.clone());
        assert_eq!(unseal(&sealed).unwrap(), &body[..]);
        for i in 0..sealed.len() {
            for bit in [0x01, 0x80] {
                let mut bad = sealed.clone();
                bad[i] ^= bit;
                assert!(unseal(&bad).is_err(), "byte {i} bit {bit:#x}");
            }
        }
        for n in 0..sealed.len() {
            assert!(unseal(&sealed[..n]).is_err(), "cut to {n}");
        }
    }
}
