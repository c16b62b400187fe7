//! The files of a distributed bake (`bake::shard`): its [`State`] and each [`TaskResult`], as
//! little-endian binary with a magic tag and a version. Bytes in, bytes out: the CLI reads and
//! writes the files (atomically).

use crate::bake::PatchFlux;
use crate::bake::shard::{State, TaskResult};
use crate::transport::link::{Leaf, Link};
use crate::transport::links::{ReceiverLinks, RowRef, RowStats};
use crate::transport::sharing::Part;
use glam::DVec3;

const STATE_MAGIC: &[u8; 8] = b"LUXSTATE";
const TASK_MAGIC: &[u8; 8] = b"LUXTASKR";
const VERSION: u32 = 1;

/// The state's bytes.
pub fn state_bytes(s: &State) -> Vec<u8> {
    let mut w = Writer(Vec::new());
    w.0.extend_from_slice(STATE_MAGIC);
    w.u32(VERSION);
    w.u64(s.settings.len() as u64);
    w.0.extend_from_slice(s.settings.as_bytes());
    w.u64(s.fingerprint);
    w.vec3s(&s.vertex_direct);
    w.vec3s(&s.flux.per_patch);
    w.vec3(s.flux.back);
    w.u64(s.flux.per_source.len() as u64);
    s.flux.per_source.iter().for_each(|x| w.f64(*x));
    s.rays.iter().for_each(|x| w.u64(*x));
    w.u64(s.tasks.len() as u64);
    for &(a, b) in &s.tasks {
        w.u32(a);
        w.u32(b);
    }
    w.0
}

/// A state from its bytes (an error saying what is wrong when they are not one).
pub fn read_state(bytes: &[u8]) -> Result<State, String> {
    let mut r = Reader { bytes, at: 0 };
    r.header(STATE_MAGIC, "a luxbake state (state.bin)")?;
    let len = r.len(1)?;
    let settings = String::from_utf8(r.take(len)?.to_vec()).map_err(|e| e.to_string())?;
    let fingerprint = r.u64()?;
    let vertex_direct = r.vec3s()?;
    let per_patch = r.vec3s()?;
    let back = r.vec3()?;
    let sources = r.len(8)?;
    let per_source = (0..sources).map(|_| r.f64()).collect::<Result<_, _>>()?;
    let rays = [r.u64()?, r.u64()?];
    let n = r.len(8)?;
    let tasks = (0..n)
        .map(|_| Ok((r.u32()?, r.u32()?)))
        .collect::<Result<_, String>>()?;
    r.end()?;
    Ok(State {
        settings,
        fingerprint,
        vertex_direct,
        flux: PatchFlux {
            per_patch,
            back,
            per_source,
        },
        rays,
        tasks,
    })
}

/// A task result's bytes.
pub fn task_bytes(t: &TaskResult) -> Vec<u8> {
    let p = &t.part;
    let mut w = Writer(Vec::new());
    w.0.extend_from_slice(TASK_MAGIC);
    w.u32(VERSION);
    w.u32(t.task);
    w.u64(t.fingerprint);
    w.u64(t.rays);
    w.0.push(p.links.has_dark() as u8);
    w.u64(p.picks.len() as u64);
    for level in &p.picks {
        w.u32s(level);
    }
    for g in 0..p.links.rows() {
        let row = p.links.row(g);
        w.u64(row.leaves.len() as u64);
        for l in row.leaves {
            w.u32(l.node);
            w.f32(l.coeff);
        }
        w.u64(row.far.len() as u64);
        for l in row.far {
            w.u32(l.node);
            w.f32(l.coeff);
            l.grad.iter().for_each(|x| w.f32(*x));
        }
    }
    w.u64(p.stats.len() as u64);
    for s in &p.stats {
        w.f32(s.coverage);
        w.f32(s.back);
        w.0.push(s.closed as u8);
        w.f32(s.dark);
    }
    w.u32s(&p.receivers);
    w.u32s(&p.at);
    w.u64(p.terms.len() as u64);
    for &(g, x) in &p.terms {
        w.u32(g);
        w.f32(x);
    }
    w.0
}

/// A task result from its bytes.
pub fn read_task(bytes: &[u8]) -> Result<TaskResult, String> {
    let mut r = Reader { bytes, at: 0 };
    r.header(TASK_MAGIC, "a luxbake task result (task-K.bin)")?;
    let task = r.u32()?;
    let fingerprint = r.u64()?;
    let rays = r.u64()?;
    let dark = r.u8()? != 0;
    let levels = r.len(8)?;
    let picks: Vec<Vec<u32>> = (0..levels).map(|_| r.u32s()).collect::<Result<_, _>>()?;
    let mut links = ReceiverLinks::empty(dark);
    for level in &picks {
        let mut rows: Vec<(Vec<Leaf>, Vec<Link>)> = Vec::with_capacity(level.len());
        for _ in level {
            let n = r.len(8)?;
            let leaves = (0..n)
                .map(|_| {
                    Ok(Leaf {
                        node: r.u32()?,
                        coeff: r.f32()?,
                    })
                })
                .collect::<Result<_, String>>()?;
            let n = r.len(20)?;
            let far = (0..n)
                .map(|_| {
                    Ok(Link {
                        node: r.u32()?,
                        coeff: r.f32()?,
                        grad: [r.f32()?, r.f32()?, r.f32()?],
                    })
                })
                .collect::<Result<_, String>>()?;
            rows.push((leaves, far));
        }
        let refs: Vec<RowRef> = (rows.iter())
            .map(|(leaves, far)| RowRef { leaves, far })
            .collect();
        links.append_rows(&refs);
    }
    let n = r.len(13)?;
    let stats = (0..n)
        .map(|_| {
            Ok(RowStats {
                coverage: r.f32()?,
                back: r.f32()?,
                closed: r.u8()? != 0,
                dark: r.f32()?,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let receivers = r.u32s()?;
    let at = r.u32s()?;
    let n = r.len(8)?;
    let terms = (0..n)
        .map(|_| Ok((r.u32()?, r.f32()?)))
        .collect::<Result<Vec<_>, String>>()?;
    r.end()?;
    let rows = links.rows();
    let sound = stats.len() == rows
        && at.len() == receivers.len() + 1
        && at.windows(2).all(|w| w[0] <= w[1])
        && at.last().is_some_and(|&e| e as usize == terms.len())
        && terms.iter().all(|&(g, _)| (g as usize) < rows);
    if !sound {
        return Err("its rows, stats and terms do not fit together".into());
    }
    Ok(TaskResult {
        task,
        fingerprint,
        rays,
        part: Part {
            links,
            stats,
            picks,
            receivers,
            at,
            terms,
        },
    })
}

struct Writer(Vec<u8>);

impl Writer {
    fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f32(&mut self, x: f32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn vec3(&mut self, v: DVec3) {
        v.to_array().iter().for_each(|x| self.f64(*x));
    }
    fn vec3s(&mut self, v: &[DVec3]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|x| self.vec3(*x));
    }
    fn u32s(&mut self, v: &[u32]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|x| self.u32(*x));
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| format!("truncated at byte {}", self.at))?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }
    fn header(&mut self, magic: &[u8; 8], what: &str) -> Result<(), String> {
        if self.take(8).ok() != Some(&magic[..]) {
            return Err(format!("not {what}"));
        }
        match self.u32()? {
            VERSION => Ok(()),
            v => Err(format!("version {v}, this bake reads version {VERSION}")),
        }
    }
    fn end(&self) -> Result<(), String> {
        match self.at == self.bytes.len() {
            true => Ok(()),
            false => Err(format!("{} bytes left over", self.bytes.len() - self.at)),
        }
    }
    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    fn f32(&mut self) -> Result<f32, String> {
        Ok(f32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    /// A count of items of at least `size` bytes each, checked against what is left.
    fn len(&mut self, size: usize) -> Result<usize, String> {
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
    fn vec3(&mut self) -> Result<DVec3, String> {
        Ok(DVec3::new(self.f64()?, self.f64()?, self.f64()?))
    }
    fn vec3s(&mut self) -> Result<Vec<DVec3>, String> {
        let n = self.len(24)?;
        (0..n).map(|_| self.vec3()).collect()
    }
    fn u32s(&mut self) -> Result<Vec<u32>, String> {
        let n = self.len(4)?;
        (0..n).map(|_| self.u32()).collect()
    }
}
