//! Timing tumble's step, and the small statistics the reports use.

use std::time::Instant;

use anyhow::{Context, Result};
use tumble_physics::{SceneDef, World};

use crate::scenes;

/// One timed run of tumble: a fresh world, `warmup` untimed steps, then `steps` timed ones.
#[derive(Clone, Debug)]
pub struct TumbleRun {
    /// Mean wall time of one `World::step` call over the timed steps (ms).
    pub step_ms: f64,
    /// Mean of each stage of `World::profile()` over the timed steps, in pipeline order.
    pub stages: Vec<(&'static str, f64)>,
    /// Mean contacts per timed step.
    pub contacts: f64,
}

/// Builds the scene's world with `threads` workers and times it (see [`TumbleRun`]).
pub fn time_tumble(scene: &SceneDef, threads: usize, warmup: u32, steps: u32) -> Result<TumbleRun> {
    let mut world = World::from_scene(scene, &scenes::limits())
        .with_context(|| format!("{}: cannot build the world", scene.name))?;
    world.set_thread_count(threads);
    // A built-in that moves things between steps (junkyard's pusher) does so here too, inside
    // the clock as in `compare` (the peers run theirs, `peers::script`, there).
    let script = tumble_scene::builtin::script(&scene.name);
    let step = |world: &mut World| {
        if let Some(script) = script {
            script(world.step_count(), world);
        }
        world.step(scene.dt, scene.substeps);
    };
    for _ in 0..warmup {
        step(&mut world);
    }
    let mut wall = 0.0f64;
    let mut contacts = 0.0f64;
    let mut stages: Vec<(&'static str, f64)> = world
        .profile()
        .stages()
        .iter()
        .map(|&(name, _)| (name, 0.0))
        .collect();
    for _ in 0..steps {
        let t = Instant::now();
        step(&mut world);
        wall += t.elapsed().as_secs_f64() * 1e3;
        let profile = world.profile();
        contacts += profile.contacts as f64;
        for (sum, (_, ms)) in stages.iter_mut().zip(profile.stages().iter()) {
            sum.1 += ms;
        }
    }
    let n = f64::from(steps.max(1));
    Ok(TumbleRun {
        step_ms: wall / n,
        stages: stages
            .into_iter()
            .map(|(name, ms)| (name, ms / n))
            .collect(),
        contacts: contacts / n,
    })
}

/// The median (mean of the middle two for an even count); NaN when empty.
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The smallest value; NaN when empty.
pub fn min(values: &[f64]) -> f64 {
    values.iter().copied().reduce(f64::min).unwrap_or(f64::NAN)
}

/// Parses a comma-separated list of positive integers ("1,2,4").
pub fn parse_list(text: &str) -> Result<Vec<usize>, String> {
    let mut out = Vec::new();
    for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let n: usize = part
            .parse()
            .map_err(|_| format!("{part:?} is not a positive integer"))?;
        if n == 0 {
            return Err("0 is not allowed; give positive integers".into());
        }
        out.push(n);
    }
    if out.is_empty() {
        return Err("give at least one number, e.g. 1,2".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
        assert_eq!(min(&[3.0, 1.0, 2.0]), 1.0);
    }

    #[test]
    fn lists() {
        assert_eq!(parse_list("1, 2,4").unwrap(), vec![1, 2, 4]);
        assert!(parse_list("1,0").is_err());
        assert!(parse_list("x").is_err());
        assert!(parse_list("").is_err());
    }
}
