//! A [`SavedMesh`] (the patch mesh and its meshing records) as bytes, and back with every
//! index checked: a damaged state cannot make a task index out of bounds.

use super::codec::{Reader, Writer};
use crate::bake::SavedMesh;
use crate::patches::{CoveredPart, Group, Patch, PatchMesh, Side, Vertex};
use glam::DVec2;

pub(super) fn write(w: &mut Writer, saved: &SavedMesh) {
    let m = &saved.mesh;
    w.f64(m.patch_size);
    w.json(&saved.adaptive);
    w.json(&saved.contacts);
    w.u64(m.receivers.len() as u64);
    for v in &m.receivers {
        [v.position, v.normal, v.point]
            .iter()
            .for_each(|x| w.vec3(*x));
        w.u32(v.group);
    }
    w.u64(m.patches.len() as u64);
    for p in &m.patches {
        p.v.iter().for_each(|x| w.u32(*x));
        w.u32(p.group);
        w.f64(p.area);
        w.vec3(p.normal);
        w.0.push(p.double_sided as u8);
    }
    w.u64(m.groups.len() as u64);
    for g in &m.groups {
        w.u64(g.surface as u64);
        w.0.push(matches!(g.side, Side::Back) as u8);
        w.u64(g.material as u64);
        for r in [&g.receivers, &g.patches] {
            w.u64(r.start as u64);
            w.u64(r.end as u64);
        }
        uvs(w, &g.uv0);
        uvs(w, &g.uv1);
        w.f64(g.area);
        w.0.push(g.covered.is_some() as u8);
        if let Some(c) = &g.covered {
            w.vec3s(&c.positions);
            w.vec3s(&c.normals);
            uvs(w, &c.uv0);
            uvs(w, &c.uv1);
            w.u64(c.triangles.len() as u64);
            c.triangles.iter().flatten().for_each(|x| w.u32(*x));
        }
    }
}

fn uvs(w: &mut Writer, uv: &Option<Vec<DVec2>>) {
    w.0.push(uv.is_some() as u8);
    if let Some(uv) = uv {
        w.u64(uv.len() as u64);
        uv.iter().for_each(|p| {
            w.f64(p.x);
            w.f64(p.y)
        });
    }
}

pub(super) fn read(r: &mut Reader) -> Result<SavedMesh, String> {
    let patch_size = r.f64()?;
    let adaptive = r.json()?;
    let contacts = r.json()?;
    let n = r.len(76)?;
    let receivers = (0..n)
        .map(|_| {
            Ok(Vertex {
                position: r.vec3()?,
                normal: r.vec3()?,
                point: r.vec3()?,
                group: r.u32()?,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let n = r.len(45)?;
    let patches = (0..n)
        .map(|_| {
            Ok(Patch {
                v: [r.u32()?, r.u32()?, r.u32()?],
                group: r.u32()?,
                area: r.f64()?,
                normal: r.vec3()?,
                double_sided: r.u8()? != 0,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let n = r.len(52)?;
    let groups = (0..n).map(|_| group(r)).collect::<Result<Vec<_>, _>>()?;
    let mesh = PatchMesh {
        groups,
        patches,
        receivers,
        patch_size,
        zone: Vec::new(), // found again on restore (`transport::zones`)
    };
    check(&mesh)?;
    Ok(SavedMesh {
        mesh,
        adaptive,
        contacts,
    })
}

fn group(r: &mut Reader) -> Result<Group, String> {
    let surface = r.u64()? as usize;
    let side = match r.u8()? {
        0 => Side::Front,
        _ => Side::Back,
    };
    let material = r.u64()? as usize;
    let receivers = r.u64()? as usize..r.u64()? as usize;
    let patches = r.u64()? as usize..r.u64()? as usize;
    let (uv0, uv1) = (read_uvs(r)?, read_uvs(r)?);
    let area = r.f64()?;
    let covered = match r.u8()? {
        0 => None,
        _ => {
            let positions = r.vec3s()?;
            let normals = r.vec3s()?;
            let (uv0, uv1) = (read_uvs(r)?, read_uvs(r)?);
            let n = r.len(12)?;
            let triangles = (0..n)
                .map(|_| Ok([r.u32()?, r.u32()?, r.u32()?]))
                .collect::<Result<Vec<_>, String>>()?;
            let fits =
                |uv: &Option<Vec<DVec2>>| uv.as_ref().is_none_or(|u| u.len() == positions.len());
            let sound = normals.len() == positions.len()
                && fits(&uv0)
                && fits(&uv1)
                && triangles
                    .iter()
                    .flatten()
                    .all(|&i| (i as usize) < positions.len());
            if !sound {
                return Err("a covered part's triangles and vertices do not fit together".into());
            }
            Some(CoveredPart {
                positions,
                normals,
                uv0,
                uv1,
                triangles,
            })
        }
    };
    Ok(Group {
        surface,
        side,
        material,
        receivers,
        patches,
        uv0,
        uv1,
        area,
        covered,
    })
}

fn read_uvs(r: &mut Reader) -> Result<Option<Vec<DVec2>>, String> {
    match r.u8()? {
        0 => Ok(None),
        _ => {
            let n = r.len(16)?;
            let uv = (0..n).map(|_| Ok(DVec2::new(r.f64()?, r.f64()?)));
            Ok(Some(uv.collect::<Result<_, String>>()?))
        }
    }
}

/// Every index in range: patches' vertices and groups, receivers' groups, groups' ranges and
/// texture coordinates (one per receiver of the group).
fn check(m: &PatchMesh) -> Result<(), String> {
    let (nr, np, ng) = (m.receivers.len(), m.patches.len(), m.groups.len());
    let ranges = m.groups.iter().all(|g| {
        let fits =
            |uv: &Option<Vec<DVec2>>| uv.as_ref().is_none_or(|u| u.len() == g.receivers.len());
        g.receivers.start <= g.receivers.end
            && g.receivers.end <= nr
            && g.patches.start <= g.patches.end
            && g.patches.end <= np
            && fits(&g.uv0)
            && fits(&g.uv1)
    });
    // A group's patches are its own and use its receivers only.
    let patches = ranges
        && m.groups.iter().enumerate().all(|(k, g)| {
            m.patches[g.patches.clone()].iter().all(|p| {
                p.group as usize == k && p.v.iter().all(|&i| g.receivers.contains(&(i as usize)))
            })
        })
        && m.patches.iter().all(|p| (p.group as usize) < ng);
    let receivers = m.receivers.iter().all(|v| (v.group as usize) < ng);
    match ranges && patches && receivers {
        true => Ok(()),
        false => Err("its mesh's patches, receivers and groups do not fit together".into()),
    }
}
