//! The files of a distributed bake (`bake::shard`): its [`State`] and each [`TaskResult`], as
//! little-endian binary with a magic tag and a version. Bytes in, bytes out: the CLI reads and
//! writes the files (atomically).

mod codec;
mod mesh;

use crate::bake::PatchFlux;
use crate::bake::shard::{State, TaskResult};
use crate::transport::link::{Leaf, Link};
use crate::transport::links::{ReceiverLinks, RowRef, RowStats};
use crate::transport::packed::PackedRows;
use crate::transport::sharing::Part;
use codec::{Reader, VERSION, Writer, seal, unseal};

const STATE_MAGIC: &[u8; 8] = b"LUXSTATE";
const TASK_MAGIC: &[u8; 8] = b"LUXTASKR";

/// The state's bytes.
pub fn state_bytes(s: &State) -> Vec<u8> {
    let mut w = Writer(Vec::new());
    w.0.extend_from_slice(STATE_MAGIC);
    w.u32(VERSION);
    w.u64(s.settings.len() as u64);
    w.0.extend_from_slice(s.settings.as_bytes());
    w.u64(s.scene);
    w.u64(s.fingerprint);
    mesh::write(&mut w, &s.mesh);
    w.vec3s(&s.flux.per_patch);
    w.vec3(s.flux.back);
    w.u64(s.flux.per_source.len() as u64);
    s.flux.per_source.iter().for_each(|x| w.f64(*x));
    s.flux.closure.iter().for_each(|x| w.f64(*x));
    s.flux.escaped.iter().for_each(|x| w.f64(*x));
    s.rays.iter().for_each(|x| w.u64(*x));
    w.u64(s.tasks.len() as u64);
    for &(a, b) in &s.tasks {
        w.u32(a);
        w.u32(b);
    }
    seal(w.0)
}

/// A state from its bytes (an error saying what is wrong when they are not one).
pub fn read_state(bytes: &[u8]) -> Result<State, String> {
    let bytes = unseal(bytes)?;
    let mut r = Reader { bytes, at: 0 };
    r.header(STATE_MAGIC, "a luxbake state (state.bin)")?;
    let len = r.len(1)?;
    let settings = String::from_utf8(r.take(len)?.to_vec()).map_err(|e| e.to_string())?;
    let scene = r.u64()?;
    let fingerprint = r.u64()?;
    let mesh = mesh::read(&mut r)?;
    let per_patch = r.vec3s()?;
    let back = r.vec3()?;
    let sources = r.len(8)?;
    let per_source = (0..sources).map(|_| r.f64()).collect::<Result<_, _>>()?;
    let closure = (0..sources).map(|_| r.f64()).collect::<Result<_, _>>()?;
    let escaped = (0..sources).map(|_| r.f64()).collect::<Result<_, _>>()?;
    let rays = [r.u64()?, r.u64()?];
    let n = r.len(8)?;
    let tasks: Vec<(u32, u32)> = (0..n)
        .map(|_| Ok((r.u32()?, r.u32()?)))
        .collect::<Result<_, String>>()?;
    r.end()?;
    let m = &mesh.mesh;
    let sound = per_patch.len() == m.patches.len()
        && tasks
            .iter()
            .all(|&(a, b)| a < b && b as usize <= m.groups.len());
    if !sound || fingerprint != crate::bake::shard::fingerprint(m) {
        return Err("its mesh, light and tasks do not fit together".into());
    }
    Ok(State {
        settings,
        scene,
        fingerprint,
        mesh,
        flux: PatchFlux {
            per_patch,
            back,
            per_source,
            closure,
            escaped,
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
    w.u64(t.direct_rays);
    w.vec3s(&t.direct);
    w.0.push(p.links.has_dark() as u8);
    w.u64(p.picks.len() as u64);
    for level in &p.picks {
        w.u32s(level);
    }
    for g in 0..p.links.rows() {
        let row = p.links.row(g);
        w.u64(row.leaves.len() as u64);
        for l in row.leaves.iter() {
            w.u32(l.node);
            w.f32(l.coeff);
        }
        w.u64(row.far.len() as u64);
        for l in row.far.iter() {
            let (node, coeff, shape) = l.stored();
            w.u32(node);
            w.f32(coeff);
            w.u32(shape);
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
    seal(w.0)
}

/// A task result from its bytes.
pub fn read_task(bytes: &[u8]) -> Result<TaskResult, String> {
    let bytes = unseal(bytes)?;
    let mut r = Reader { bytes, at: 0 };
    r.header(TASK_MAGIC, "a luxbake task result (task-K.bin)")?;
    let task = r.u32()?;
    let fingerprint = r.u64()?;
    let rays = r.u64()?;
    let direct_rays = r.u64()?;
    let direct = r.vec3s()?;
    let dark = r.u8()? != 0;
    let levels = r.len(8)?;
    let picks: Vec<Vec<u32>> = (0..levels).map(|_| r.u32s()).collect::<Result<_, _>>()?;
    let mut links = ReceiverLinks::empty(dark);
    for level in &picks {
        let mut rows = PackedRows::default();
        for _ in level {
            let n = r.len(8)?;
            let leaves = (0..n)
                .map(|_| {
                    Ok(Leaf {
                        node: r.u32()?,
                        coeff: r.f32()?,
                    })
                })
                .collect::<Result<Vec<_>, String>>()?;
            let n = r.len(12)?;
            let far = (0..n)
                .map(|_| {
                    let (node, coeff) = (r.u32()?, r.f32()?);
                    Ok(Link::from_stored(node, coeff, r.u32()?))
                })
                .collect::<Result<Vec<_>, String>>()?;
            rows.push(&leaves, &far);
        }
        let refs: Vec<RowRef> = (0..rows.rows())
            .map(|j| {
                let (leaves, far) = rows.row(j);
                RowRef { leaves, far }
            })
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
        && direct.len() == receivers.len()
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
        direct,
        direct_rays,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::shard;
    use crate::fixtures::contacts::cubes_on_floor;
    use crate::progress::Silent;
    use crate::settings::Settings;
    use glam::{DVec2, DVec3};

    /// A plan of cubes standing on a floor (covered parts), its groups given texture
    /// coordinates and one patch marked double-sided, so every field of the mesh is written.
    fn state() -> State {
        let scene = cubes_on_floor(0.5, 0.0).scene;
        let mut s = shard::plan(&scene, &Settings::default(), 3, &Silent).unwrap();
        let m = &mut s.mesh.mesh;
        assert!(
            m.groups.iter().any(|g| g.covered.is_some()),
            "no covered part"
        );
        let uv = |p: &[DVec3]| Some(p.iter().map(|p| DVec2::new(p.x, p.z)).collect::<Vec<_>>());
        for g in &mut m.groups {
            let points: Vec<DVec3> = (m.receivers[g.receivers.clone()].iter())
                .map(|r| r.position)
                .collect();
            g.uv1 = uv(&points);
            if let Some(c) = &mut g.covered {
                c.uv0 = uv(&c.positions);
            }
        }
        m.patches[0].double_sided = true;
        s
    }

    #[test]
    fn a_state_reads_back_to_the_same_bytes() {
        let s = state();
        let bytes = state_bytes(&s);
        let back = read_state(&bytes).unwrap();
        assert_eq!(back.mesh.mesh.receivers.len(), s.mesh.mesh.receivers.len());
        assert_eq!(back.mesh.adaptive, s.mesh.adaptive);
        assert_eq!(back.mesh.contacts, s.mesh.contacts);
        assert_eq!((back.scene, back.fingerprint), (s.scene, s.fingerprint));
        assert!(back.mesh.mesh.patches[0].double_sided);
        assert!(
            state_bytes(&back) == bytes,
            "written again, the bytes differ"
        );
    }

    #[test]
    fn a_damaged_state_is_refused() {
        let bytes = state_bytes(&state());
        // Cut short anywhere.
        for end in [0, 10, bytes.len() / 3, bytes.len() - 1] {
            assert!(read_state(&bytes[..end]).is_err(), "cut at {end}");
        }
        // A patch's first vertex index beyond the receivers: found, not used.
        let s = state();
        let (nr, at) = (s.mesh.mesh.receivers.len(), patch_offset(&s));
        let mut bad = bytes.clone();
        assert_eq!(bad[at..at + 4], s.mesh.mesh.patches[0].v[0].to_le_bytes());
        bad[at..at + 4].copy_from_slice(&(nr as u32 + 7).to_le_bytes());
        let e = read_state(&bad).err().unwrap();
        assert!(e.contains("checksum"), "{e}");
        // Sealed again (as a writer with a bug would), the structure is still checked.
        let bad = seal(bad[..bad.len() - 8].to_vec());
        let e = read_state(&bad).err().unwrap();
        assert!(e.contains("do not fit together"), "{e}");
        // A flipped bit in the first receiver's point (its position and normal come first):
        // the mesh's fingerprint no longer matches the one written.
        let first = at - 8 - 76 * nr;
        let mut bad = bytes.clone();
        bad[first + 48] ^= 1;
        let bad = seal(bad[..bad.len() - 8].to_vec());
        let e = read_state(&bad).err().unwrap();
        assert!(e.contains("do not fit together"), "{e}");
    }

    /// Where the first patch's first vertex index is in the state's bytes.
    fn patch_offset(s: &State) -> usize {
        let mut w = Writer(Vec::new());
        w.0.extend_from_slice(STATE_MAGIC);
        w.u32(VERSION);
        w.u64(s.settings.len() as u64);
        w.0.extend_from_slice(s.settings.as_bytes());
        w.u64(s.scene);
        w.u64(s.fingerprint);
        w.f64(s.mesh.mesh.patch_size);
        w.json(&s.mesh.adaptive);
        w.json(&s.mesh.contacts);
        w.0.len() + 8 + 76 * s.mesh.mesh.receivers.len() + 8
    }
}
