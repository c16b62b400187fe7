//! Buildings: rows of 4 × 3 × 5 m rooms drawn as CAD and BIM tools export them (one floor slab
//! and one ceiling slab under every room, partitions as boxes or zero-thickness double-sided
//! quads) or as closed boxes of their own, an isotropic 1000 cd point light in room 0.
//! Oracles: a room behind closed partitions reads exactly 0 (no light passes an opaque
//! surface) at every vertex, texel and probe; Sumpner's balance Σ(1 − ρ)·E·A = Φ in each closed
//! room and over the building; the energy report's balance; and a room's vertex values do not
//! depend on what else is in the file. Axes: +Y up; metres, lux.

use glam::{DMat3, DVec2, DVec3};
use luxbake::bake::bake;
use luxbake::fixtures::building::{self, Partitions, Row, Slabs, VARIANTS};
use luxbake::probes::{Probe, ProbeOrigin};
use luxbake::progress::Silent;
use luxbake::result::BakeResult;
use luxbake::settings::{LightmapSettings, Settings};

/// Per room: Σ(1 − ρ)·E·A over the baked triangles whose front lies in it (lm), the largest
/// vertex illuminance in it (lx), and its area-mean illuminance (lx).
fn per_room(row: &Row, r: &BakeResult, rho: f64) -> Vec<(f64, f64, f64)> {
    let mut rooms = vec![(0.0, 0.0f64, 0.0, 0.0); row.rooms.len()];
    for s in &r.surfaces {
        for t in &s.triangles {
            let p = t.map(|v| s.positions[v as usize]);
            let cross = (p[1] - p[0]).cross(p[2] - p[0]);
            let a = cross.length() / 2.0;
            let front = (p[0] + p[1] + p[2]) / 3.0 + cross.normalize_or_zero() * 0.01;
            let Some(k) = row.room_of(front, 0.0) else {
                continue;
            };
            let e: Vec<f64> = t
                .iter()
                .map(|&v| s.illuminance[v as usize] as f64)
                .collect();
            let mean = e.iter().sum::<f64>() / 3.0;
            let room = &mut rooms[k];
            room.0 += (1.0 - rho) * mean * a;
            room.1 = e.iter().fold(room.1, |m, x| m.max(*x));
            room.2 += mean * a;
            room.3 += a;
        }
    }
    rooms
        .into_iter()
        .map(|(ab, max, ea, a)| (ab, max, ea / a))
        .collect()
}

/// The largest lightmap texel illuminance over the triangles whose front lies in a room
/// without light: each triangle's lightmap UVs sampled at its centroid and near each corner.
fn dark_texel_max(row: &Row, r: &BakeResult) -> f64 {
    let maps = r.lightmaps.as_ref().expect("lightmaps baked");
    let mut max = 0.0f64;
    for s in &r.surfaces {
        let (Some(atlas), Some(uv)) = (s.lightmap, s.uv1.as_ref()) else {
            continue;
        };
        let atlas = &maps.atlases[atlas];
        let end = s.covered_from.map_or(s.triangles.len(), |c| c as usize);
        for t in &s.triangles[..end] {
            let p = t.map(|v| s.positions[v as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if row
                .room_of((p[0] + p[1] + p[2]) / 3.0 + n * 0.01, 0.0)
                .is_none_or(|k| k == 0)
            {
                continue;
            }
            let q = t.map(|v| uv[v as usize]);
            for w in [
                [1.0 / 3.0; 3],
                [0.8, 0.1, 0.1],
                [0.1, 0.8, 0.1],
                [0.1, 0.1, 0.8],
            ] {
                let at: DVec2 = q[0] * w[0] + q[1] * w[1] + q[2] * w[2];
                let col = ((at.x * atlas.width as f64) as u32).min(atlas.width - 1);
                let row = ((at.y * atlas.height as f64) as u32).min(atlas.height - 1);
                max = max.max(atlas.illuminance[(row * atlas.width + col) as usize] as f64);
            }
        }
    }
    max
}

/// Probes in every room: a 3 × 3 grid at 1.2 m, and one 2 mm from a corner of the floor
/// against the partition toward room 0.
fn probes(row: &Row) -> Vec<Probe> {
    let mut out = Vec::new();
    for (k, (lo, hi)) in row.rooms.iter().enumerate() {
        let size = *hi - *lo;
        let mut at = |name: String, position: DVec3| {
            out.push(Probe {
                name,
                position,
                world_from_probe: DMat3::IDENTITY,
                origin: ProbeOrigin::File {
                    line: out.len() + 1,
                },
                toward: None,
            })
        };
        for (i, j) in (0..9).map(|n| (n / 3, n % 3)) {
            let p = *lo
                + DVec3::new(
                    size.x * (i as f64 + 0.5) / 3.0,
                    1.2,
                    size.z * (j as f64 + 0.5) / 3.0,
                );
            at(format!("room{k}_{i}{j}"), p);
        }
        at(
            format!("room{k}_corner"),
            *lo + DVec3::new(0.002, 0.002, 0.002),
        );
    }
    out
}

#[test]
fn closed_rooms_read_zero_and_close_energy_however_the_floor_is_drawn() {
    let settings = Settings {
        lightmaps: Some(LightmapSettings {
            texel_size: Some(0.1),
            ..LightmapSettings::default()
        }),
        ..Settings::default()
    };
    let mut failed = Vec::new();
    for (name, slabs) in VARIANTS {
        for rho in [0.5, 0.9] {
            let row = building::row(slabs, 3, rho, 1000.0, &[]);
            let settings = Settings {
                extra_probes: probes(&row),
                ..settings.clone()
            };
            let r = bake(&row.scene, &settings, &Silent).expect("bake");
            let rooms = per_room(&row, &r, rho);
            let lit_mean = rooms[0].2;
            let limit = 1e-6 * lit_mean;
            let balance = r.summary.energy.balance_error_relative;
            let texel = dark_texel_max(&row, &r);
            let probe = (r.probes.iter())
                .filter(|p| row.room_of(p.probe.position, 0.0).is_some_and(|k| k > 0))
                .flat_map(|p| p.cubic.total)
                .fold(0.0f64, f64::max);
            let sumpner = rooms[0].0 / row.flux[0] - 1.0;
            let dark = rooms[1].1.max(rooms[2].1);
            eprintln!(
                "{name}, ρ {rho}: dark rooms' max vertex {dark:.2e} lx, texel {texel:.2e}, probe \
                 {probe:.2e} (lit mean {lit_mean:.1} lx); balance {balance:.1e}; Sumpner {:+.3} %",
                100.0 * sumpner
            );
            let dark_probes = (r.probes.iter())
                .filter(|p| row.room_of(p.probe.position, 0.0).is_some_and(|k| k > 0))
                .count();
            assert!(
                dark_probes >= 20,
                "{name}: {dark_probes} probes in the dark rooms"
            );
            for (what, v) in [("vertex", dark), ("texel", texel), ("probe", probe)] {
                if v > limit {
                    failed.push(format!(
                        "{name}, ρ {rho}: a dark room's {what} reads {v:.3e} lx"
                    ));
                }
            }
            // Measured about 10⁻⁹ at every ρ (1.7·10⁻⁴ at ρ 0.9 with thin partitions while the
            // slab under the outer walls' corner was left uncovered).
            if balance > 1e-4 {
                failed.push(format!("{name}, ρ {rho}: balance error {balance:.2e}"));
            }
            // The lit room is the building's only closed room with light: Sumpner holds in it,
            // and so over the whole building.
            if sumpner.abs() > 0.005 {
                failed.push(format!(
                    "{name}, ρ {rho}: Σ(1 − ρ)·E·A off Φ by {sumpner:+.2e}"
                ));
            }
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn a_room_bakes_alike_alone_and_beside_closed_neighbours() {
    // The same patch size for all three (the automatic one follows the scene's size): room 0's
    // mesh is then the same, and its values differ by the solver's tolerance only.
    let settings = Settings {
        patch_size: Some(0.4),
        // Adaptive meshing judges edges against the whole scene's mean light, so the automatic
        // mesh of room 0 depends on its neighbours (open, see issue 55's note).
        uniform_patches: true,
        ..Settings::default()
    };
    let room0 = |gap: f64, count: usize| {
        let row = building::row(Slabs::Separate { gap }, count, 0.8, 1000.0, &[]);
        let r = bake(&row.scene, &settings, &Silent).expect("bake");
        let mut values = Vec::new();
        for s in &r.surfaces {
            for (p, e) in s.positions.iter().zip(&s.illuminance) {
                if row.room_of(*p, 1e-9) == Some(0) {
                    values.push((p.to_array().map(f64::to_bits), s.side, *e as f64));
                }
            }
        }
        values.sort_by(|a, b| {
            (a.0, a.1 as u8)
                .cmp(&(b.0, b.1 as u8))
                .then(a.2.total_cmp(&b.2))
        });
        values
    };
    let alone = room0(0.12, 1);
    let mean = alone.iter().map(|v| v.2).sum::<f64>() / alone.len() as f64;
    for (gap, count) in [(0.12, 3), (6.0, 3)] {
        let beside = room0(gap, count);
        assert_eq!(alone.len(), beside.len(), "gap {gap}: vertex count");
        let worst = (alone.iter().zip(&beside))
            .map(|(a, b)| {
                assert_eq!((a.0, a.1), (b.0, b.1), "gap {gap}: the same vertices");
                (a.2 - b.2).abs()
            })
            .fold(0.0, f64::max);
        eprintln!("gap {gap}: largest vertex difference {worst:.2e} lx (mean {mean:.1} lx)");
        assert!(worst <= 1e-3 * mean, "gap {gap}: {worst:.3e} lx off");
    }
}

#[test]
fn light_passes_an_open_door_and_energy_closes_over_the_building() {
    // Rooms 0 and 1 joined by an open door (box or zero-thickness partitions): room 1 is lit
    // through it, room 2 behind a closed partition reads 0, and Sumpner holds over rooms 0 and 1
    // together (one closed space).
    for partitions in [Partitions::Box, Partitions::Thin] {
        let row = building::row(Slabs::Shared(partitions), 3, 0.7, 1000.0, &[true]);
        let r = bake(&row.scene, &Settings::default(), &Silent).expect("bake");
        let rooms = per_room(&row, &r, 0.7);
        let sumpner = (rooms[0].0 + rooms[1].0) / row.flux[0] - 1.0;
        eprintln!(
            "{partitions:?}, door open: room 1 mean {:.2} lx, room 2 max {:.2e} lx, Sumpner \
             {:+.3} %",
            rooms[1].2,
            rooms[2].1,
            100.0 * sumpner
        );
        assert!(
            rooms[1].2 > 0.02 * rooms[0].2,
            "{partitions:?}: room 1 {:?}",
            rooms[1]
        );
        assert!(
            rooms[2].1 <= 1e-6 * rooms[0].2,
            "{partitions:?}: room 2 {:?}",
            rooms[2]
        );
        assert!(
            sumpner.abs() < 0.005,
            "{partitions:?}: Sumpner {sumpner:+.2e}"
        );
        let balance = r.summary.energy.balance_error_relative;
        assert!(balance <= 2e-4, "{partitions:?}: balance {balance:.2e}");
    }
}
