//! `tumble-bench rays`: what a ray cast costs through the broad phase's tree, against a scan of
//! every shape, on a scene after it has run (issue 18's target: a ray across `many_pyramids` in
//! microseconds). Both ways must find the same nearest hit for every ray; the figures are ratios
//! taken in one run, interleaved, with the machine beside them.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use tumble_physics::collision::{Ray, ray_cast};
use tumble_physics::{Aabb, Limits, QueryFilter, Vec2, World};

/// Arguments of `tumble-bench rays`.
#[derive(Debug, Args)]
pub struct RaysArgs {
    /// A scene file or built-in name.
    #[arg(long, value_name = "SCENE", default_value = "many_pyramids")]
    pub scene: String,
    /// Steps to run the scene before casting (the rays then meet it as a game would).
    #[arg(long, value_name = "N", default_value_t = 60)]
    pub steps: u32,
    /// Rays per timed batch.
    #[arg(long, value_name = "N", default_value_t = 2000,
          value_parser = clap::value_parser!(u32).range(1..))]
    pub rays: u32,
    /// Timed batches of each way, interleaved.
    #[arg(long, value_name = "N", default_value_t = 7,
          value_parser = clap::value_parser!(u32).range(1..))]
    pub repeats: u32,
    /// Write the markdown to FILE instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The nearest hit by testing every shape: (fraction bits, shape slot).
fn scan(world: &World, origin: Vec2, translation: Vec2) -> Option<(u32, u32)> {
    let mut best: Option<(u32, u32)> = None;
    for v in world.shapes().filter(|v| !v.sensor) {
        let local = Ray {
            origin: v.transform.apply_inv(origin),
            translation: v.transform.q.apply_inv(translation),
            max_fraction: 1.0,
        };
        if let Some(h) = ray_cast(v.shape, &local) {
            let key = (h.fraction.to_bits(), v.id.index);
            // Fractions are >= 0, so their bits order as they do.
            if best.is_none_or(|b| key < b) {
                best = Some(key);
            }
        }
    }
    best
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Runs the comparison and writes the table.
pub fn run(args: &RaysArgs) -> Result<()> {
    let scene = crate::scenes::resolve(&args.scene)?;
    let mut world = World::from_scene(&scene, &Limits::default())
        .with_context(|| format!("{}: cannot build the world", args.scene))?;
    world.set_thread_count(1);
    for _ in 0..args.steps {
        world.step(scene.dt, scene.substeps);
    }
    let shapes = world.shapes().count();
    // Proxies whose fat box changed in the last step: the tree is refitted at the next step's
    // start, so a query tests these one by one.
    let moved = world.profile().moved;
    let Some(bounds) = world
        .shapes()
        .map(|v| v.shape.aabb(v.transform))
        .reduce(|a, b| a.union(&b))
    else {
        bail!("{}: no shapes to cast at", args.scene);
    };
    // Rays across the scene from its left side to its right, at heights drawn evenly over
    // its lower half (where the pyramids stand), each sloping at most 10°: they cross the
    // whole scene and stop at the first thing in the way.
    let Aabb { min, max } = bounds;
    let width = max.x - min.x;
    let rays: Vec<(Vec2, Vec2)> = (0..args.rays)
        .map(|i| {
            let u = (i as f32 + 0.5) / args.rays as f32;
            let y = min.y + 0.5 * (max.y - min.y) * u;
            let slope = ((i * 7919) % 21) as f32 / 10.0 - 1.0;
            let origin = Vec2::new(min.x - 1.0, y);
            (
                origin,
                Vec2::new(width + 2.0, slope * 0.176 * (width + 2.0)),
            )
        })
        .collect();
    let filter = QueryFilter::default();
    let mut hits = 0;
    for &(o, d) in &rays {
        let tree = world
            .cast_ray_closest(o, d, &filter)
            .map(|h| (h.fraction.to_bits(), h.shape.shape.index));
        if tree != scan(&world, o, d) {
            bail!("the tree and the scan disagree on the ray from {o} along {d}");
        }
        hits += usize::from(tree.is_some());
    }
    let (mut tree_us, mut scan_us, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    let load_before = crate::machine::load_average();
    for _ in 0..args.repeats {
        let t = Instant::now();
        let mut found = 0usize;
        for &(o, d) in &rays {
            found += usize::from(world.cast_ray_closest(o, d, &filter).is_some());
        }
        let tree = t.elapsed().as_secs_f64() * 1e6 / rays.len() as f64;
        let t = Instant::now();
        for &(o, d) in &rays {
            found += usize::from(scan(&world, o, d).is_some());
        }
        let brute = t.elapsed().as_secs_f64() * 1e6 / rays.len() as f64;
        assert_eq!(found, 2 * hits);
        tree_us.push(tree);
        scan_us.push(brute);
        ratios.push(brute / tree);
    }
    let spread = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(0.0, f64::max);
        format!("{lo:.2}–{hi:.2}")
    };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Ray casts: the tree against a scan of every shape\n\n\
         `tumble-bench rays --scene {} --steps {} --rays {} --repeats {}`: the scene run {} \
         steps on one thread, then {} rays cast across it from left to right (heights spread \
         over its lower half, slopes within ±10°), each for its nearest hit, by \
         `World::cast_ray_closest` (the broad phase's tree) and by testing every shape; both \
         found the same hit (shape and fraction, bit for bit) for every ray ({} of {} hit \
         something). Batches interleaved, one thread; µs per ray.\n",
        args.scene, args.steps, args.rays, args.repeats, args.steps, args.rays, hits, args.rays
    );
    crate::machine::write_host_rows(&mut md);
    crate::machine::write_build_row(&mut md);
    let load_after = crate::machine::load_average();
    let _ = writeln!(
        md,
        "| load average (1, 5, 15 min) | {load_before} → {load_after} |"
    );
    let _ = writeln!(md, "| shapes | {shapes} |");
    let _ = writeln!(
        md,
        "| proxies moved in the last step (tested one by one) | {moved} |\n"
    );
    let _ = writeln!(md, "| | median µs / ray | spread |\n|---|---|---|");
    let _ = writeln!(
        md,
        "| tree (`cast_ray_closest`) | {:.2} | {} |",
        median(&mut tree_us.clone()),
        spread(&tree_us)
    );
    let _ = writeln!(
        md,
        "| scan of every shape | {:.1} | {} |",
        median(&mut scan_us.clone()),
        spread(&scan_us)
    );
    let _ = writeln!(
        md,
        "| scan / tree, per batch | {:.0}× | {} |",
        median(&mut ratios.clone()),
        spread(&ratios)
    );
    match &args.out {
        Some(path) => {
            std::fs::write(path, md).with_context(|| format!("cannot write {}", path.display()))?
        }
        None => print!("{md}"),
    }
    Ok(())
}
