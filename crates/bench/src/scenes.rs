//! Scenes the benchmarks run: the loader's (files and built-ins) plus a generated family,
//! `pile_N`, whose body count is its parameter.

use anyhow::{Context, Result, bail};
use tumble_physics::{BodyDef, BodyKind, Limits, SceneDef, ShapeDef};
use tumble_scene::LoadLimits;

/// Prefix of the generated scene family: `pile_1000` is [`pile`] with 1000 dynamic bodies.
pub const PILE_PREFIX: &str = "pile_";

/// Seed of every generated pile, so that each count is the same scene on every run.
pub const PILE_SEED: u64 = 0x7475_6d62_6c65; // "tumble"

/// Most bodies a benchmark scene may hold (far above any default).
pub const MAX_BODIES: usize = 1_000_000;

/// Limits for benchmark scenes: the default limits with room for huge generated piles.
pub fn limits() -> Limits {
    Limits {
        max_bodies: MAX_BODIES,
        ..Limits::default()
    }
}

/// A scene by name: `pile_N`, a built-in scene's name, or a `.ron`/`.json` file.
pub fn resolve(name: &str) -> Result<SceneDef> {
    if let Some(count) = name.strip_prefix(PILE_PREFIX) {
        let n: usize = count
            .parse()
            .with_context(|| format!("{name}: expected {PILE_PREFIX}N with N a body count"))?;
        if n == 0 || n > MAX_BODIES {
            bail!("{name}: the body count must be from 1 to {MAX_BODIES}");
        }
        return Ok(pile(n, PILE_SEED));
    }
    let limits = LoadLimits {
        scene: limits(),
        ..LoadLimits::default()
    };
    Ok(tumble_scene::load(name, &limits)?)
}

/// SplitMix64: a small, fast, seedable generator; the same numbers on every platform.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let unit = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * unit
    }
}

/// Spacing of the spawn grid (m). A box of the largest half extent, turned any way, reaches
/// 0.45·√2 ≈ 0.64 m from its centre, so neighbours start apart with a random jitter too.
const SPACING: f32 = 1.5;
/// Largest random offset from a grid point (m); 2 × 0.64 + 2 × 0.1 < 1.5.
const JITTER: f32 = 0.1;
/// Half thickness of the container's walls and floor (m).
const WALL: f32 = 1.0;

/// `n` dynamic bodies, about half boxes (half extents 0.2 to 0.45 m) and half circles (radius
/// 0.2 to 0.45 m), random angles and densities 0.5 to 2, on a jittered grid inside a static
/// box container (floor and two walls) whose width grows as √n, so they fall a little and pile
/// up. The first three bodies are the container; the seed fixes everything else.
pub fn pile(n: usize, seed: u64) -> SceneDef {
    let mut rng = SplitMix64(seed);
    let mut scene = SceneDef::new(format!("{PILE_PREFIX}{n}"));
    scene.steps = 300;
    // Twice as wide as tall, so the pile is a heap rather than a column.
    let columns = ((2.0 * n as f64).sqrt().ceil() as usize).max(1);
    let rows = n.div_ceil(columns);
    let inner_half_width = 0.5 * columns as f32 * SPACING;
    let height = rows as f32 * SPACING + 2.0;
    let wall = |hx: f32, hy: f32, x: f32, y: f32| {
        BodyDef::new(ShapeDef::Box {
            half_extents: [hx, hy],
            radius: 0.0,
        })
        .kind(BodyKind::Static)
        .at(x, y)
    };
    scene.push(wall(inner_half_width + 2.0 * WALL, WALL, 0.0, -WALL));
    let wall_x = inner_half_width + WALL;
    scene.push(wall(WALL, 0.5 * height, -wall_x, 0.5 * height));
    scene.push(wall(WALL, 0.5 * height, wall_x, 0.5 * height));
    for k in 0..n {
        let (row, column) = (k / columns, k % columns);
        let x = -inner_half_width + (column as f32 + 0.5) * SPACING + rng.range(-JITTER, JITTER);
        let y = 1.0 + row as f32 * SPACING + rng.range(-JITTER, JITTER);
        let size = rng.range(0.2, 0.45);
        let shape = if rng.next_u64() & 1 == 0 {
            ShapeDef::Box {
                half_extents: [size, rng.range(0.2, 0.45)],
                radius: 0.0,
            }
        } else {
            ShapeDef::Circle { radius: size }
        };
        let angle = rng.range(-std::f32::consts::PI, std::f32::consts::PI);
        let density = rng.range(0.5, 2.0);
        scene.push(
            BodyDef::new(shape)
                .at(x, y)
                .angle(angle)
                .density(density)
                .velocity(rng.range(-1.0, 1.0), 0.0),
        );
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piles_are_valid_seeded_and_sized() {
        for n in [1, 7, 100, 2_000] {
            let scene = pile(n, PILE_SEED);
            scene.validate(&limits()).expect("a pile is a valid scene");
            assert_eq!(scene.bodies.len(), n + 3);
            let dynamic = scene
                .bodies
                .iter()
                .filter(|b| b.kind == BodyKind::Dynamic)
                .count();
            assert_eq!(dynamic, n);
            assert_eq!(
                scene,
                pile(n, PILE_SEED),
                "the same seed gives the same pile"
            );
        }
        assert_ne!(pile(50, 1), pile(50, 2));
    }

    #[test]
    fn pile_names_resolve() {
        assert_eq!(resolve("pile_10").unwrap().bodies.len(), 13);
        assert!(resolve("pile_x").is_err());
        assert!(resolve("pile_0").is_err());
        assert_eq!(resolve("pyramid").unwrap().name, "pyramid");
    }
}
