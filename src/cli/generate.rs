//! `bake generate openplan [--size small|medium|large] [--triangles N] [--seed S] -o OUT` and
//! `bake generate building -o OUT`: write a scene built in code (the benchmark's open-plan
//! office; the building floor of closed rooms) as an input glTF for `bake`.

use anyhow::Result;
use clap::{Args, Subcommand, ValueEnum};
use luxbake::fixtures::{OpenPlan, open_plan};
use std::path::PathBuf;
use std::time::Instant;

/// Generate a test scene.
#[derive(Args, Debug)]
pub struct GenerateArgs {
    #[command(subcommand)]
    scene: GenerateScene,
}

#[derive(Subcommand, Debug)]
enum GenerateScene {
    /// An open-plan office floor: desk clusters, chairs, screens, columns, meeting rooms,
    /// linear fittings, downlights, spots and emissive panels (deterministic from the seed).
    Openplan(OpenplanArgs),
    /// A building floor of closed rooms: cellular offices on both sides of a corridor, a
    /// meeting room, thick and zero-thickness partitions, doors open and shut, shared slabs
    /// (no parameters: always the same scene).
    Building(BuildingArgs),
}

#[derive(Args, Debug)]
struct BuildingArgs {
    /// Output file: .gltf (+ .bin beside it) or .glb.
    #[arg(short, long)]
    output: PathBuf,
    /// Print nothing on success.
    #[arg(short, long)]
    quiet: bool,
}

#[derive(Args, Debug)]
struct OpenplanArgs {
    /// Preset: about 10⁴, 10⁵ or 10⁶ triangles (13.5 × 10.1, 20 × 15, 60 × 45 m).
    #[arg(long, value_enum, default_value_t = SizeArg::Medium)]
    size: SizeArg,
    /// Triangle target instead of the preset's (the floor grows with it), 1 to 10⁷.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=MAX_TRIANGLES))]
    triangles: Option<u64>,
    /// Seed of the small random variations (chair turns, missing chairs, colours).
    #[arg(long, default_value_t = luxbake::fixtures::openplan::DEFAULT_SEED)]
    seed: u64,
    /// Output file: .gltf (+ .bin beside it) or .glb.
    #[arg(short, long)]
    output: PathBuf,
    /// Print nothing on success.
    #[arg(short, long)]
    quiet: bool,
}

/// The largest `--triangles`: a 10⁷-triangle floor bakes in 24 GiB (issue 29); 10⁸ would not
/// even be written (its buffers alone are several GiB).
const MAX_TRIANGLES: u64 = 10_000_000;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SizeArg {
    Small,
    Medium,
    Large,
}

pub fn run(args: &GenerateArgs) -> Result<()> {
    match &args.scene {
        GenerateScene::Openplan(a) => openplan(a),
        GenerateScene::Building(a) => building(a),
    }
}

fn building(args: &BuildingArgs) -> Result<()> {
    let start = Instant::now();
    luxbake::export::check(&args.output, &luxbake::scene::Scene::default(), &[])?;
    let scene = luxbake::fixtures::building_floor::building_floor();
    luxbake::export::write_scene(&args.output, &scene)?;
    if !args.quiet {
        let g = &scene.extras.as_ref().map(|e| e["generator"].clone());
        let g = g.as_ref().unwrap_or(&serde_json::Value::Null);
        let rooms = g["rooms"].as_array().map_or(&[][..], |r| r.as_slice());
        let lit = rooms
            .iter()
            .filter(|r| r["lit"] == true && r["name"] != "corridor")
            .count();
        let doors: Vec<&serde_json::Value> = rooms
            .iter()
            .filter(|r| r["name"] != "corridor")
            .flat_map(|r| r["doors"].as_array().into_iter().flatten())
            .collect();
        let open = doors.iter().filter(|d| d["open"] == true).count();
        eprintln!(
            "building floor: {} rooms ({lit} lit) along a lit corridor, {} doors ({open} open), \
             {} linear fittings, {} downlights, {} emissive panels, {} triangles; written in \
             {:.2} s → {}",
            rooms.len().saturating_sub(1),
            doors.len(),
            g["linearLuminaires"],
            g["downlights"],
            g["emissivePanels"],
            g["triangles"],
            start.elapsed().as_secs_f64(),
            args.output.display()
        );
    }
    Ok(())
}

fn openplan(args: &OpenplanArgs) -> Result<()> {
    let start = Instant::now();
    let preset = match args.size {
        SizeArg::Small => OpenPlan::small(),
        SizeArg::Medium => OpenPlan::medium(),
        SizeArg::Large => OpenPlan::large(),
    };
    let target = args
        .triangles
        .map_or(preset.target_triangles, |n| n as usize);
    luxbake::export::check(&args.output, &luxbake::scene::Scene::default(), &[])?;
    let scene = open_plan(&OpenPlan::new(target, args.seed));
    luxbake::export::write_scene(&args.output, &scene)?;
    if !args.quiet {
        let g = &scene.extras.as_ref().map(|e| e["generator"].clone());
        let g = g.as_ref().unwrap_or(&serde_json::Value::Null);
        let (lo, hi) = (
            &g["chairDetail"][0]["triangles"],
            &g["chairDetail"][1]["triangles"],
        );
        let chair = if lo == hi {
            format!("{lo}")
        } else {
            format!("{lo}–{hi}")
        };
        eprintln!(
            "open-plan office {} × {} m (seed {}): {} triangles (target {target}), {} desks, {} \
             chairs of {chair} triangles, {} meeting rooms, {} columns",
            g["floorPlate"][0],
            g["floorPlate"][1],
            args.seed,
            g["triangles"],
            g["desks"],
            g["chairs"],
            g["meetingRooms"],
            g["columns"],
        );
        eprintln!(
            "  {} linear fittings, {} downlights, {} spots, {} emissive panels; written in {:.2} s \
             → {}",
            g["linearLuminaires"],
            g["downlights"],
            g["spots"],
            g["emissivePanels"],
            start.elapsed().as_secs_f64(),
            args.output.display()
        );
    }
    Ok(())
}
