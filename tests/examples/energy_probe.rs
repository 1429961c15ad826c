//! Where the elastic box's energy goes: `energy_probe [STEPS]` runs `elastic_box` under
//! several settings (env knobs below) and prints the energy drift, and for the default run the
//! steps that lost the most energy with the contacts that were active in them.
use tumble_physics::*;

fn run(label: &str, steps: u32, tweak: impl Fn(&mut StepSettings), substeps: u32, verbose: bool) {
    let scene = tumble_scene::builtin::build("elastic_box").unwrap();
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.set_thread_count(1);
    tweak(w.settings_mut());
    let e0 = w.kinetic_energy();
    let mut losses = Vec::new();
    let mut prev = e0;
    for s in 0..steps {
        w.step(scene.dt, substeps);
        let e = w.kinetic_energy();
        if verbose {
            let touching: Vec<(usize, usize, f32, f32)> = w
                .contacts()
                .filter(|c| {
                    c.manifold.count > 0 && c.manifold.points()[0].total_normal_impulse > 0.0
                })
                .map(|c| {
                    let p = c.manifold.points()[0];
                    (
                        c.body_a.index as usize,
                        c.body_b.index as usize,
                        p.separation,
                        p.normal_velocity,
                    )
                })
                .collect();
            losses.push((prev - e, s, touching));
        }
        prev = e;
    }
    println!(
        "{label}: energy {:.2} -> {:.2} J, change {:+.1}%",
        e0,
        prev,
        100.0 * (prev / e0 - 1.0)
    );
    if verbose {
        losses.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (loss, s, touching) in losses.iter().take(8) {
            println!(
                "  step {s}: lost {loss:.4} J; pushing contacts (a, b, separation, approach) {touching:?}"
            );
        }
        let gained: f64 = losses.iter().filter(|l| l.0 < 0.0).map(|l| -l.0).sum();
        let lost: f64 = losses.iter().filter(|l| l.0 > 0.0).map(|l| l.0).sum();
        println!("  total lost {lost:.2} J, total gained {gained:.2} J");
    }
}

fn main() {
    let steps: u32 = std::env::args().nth(1).map_or(3600, |s| s.parse().unwrap());
    run("defaults", steps, |_| {}, 4, false);
    run(
        "threshold 0",
        steps,
        |s| s.restitution_threshold = 0.0,
        4,
        true,
    );
    for passes in [2, 4, 8, 16] {
        run(
            &format!("threshold 0, {passes} restitution passes"),
            steps,
            |s| {
                s.restitution_threshold = 0.0;
                s.restitution_iterations = passes;
            },
            4,
            false,
        );
    }
    run(
        "impacts bounce",
        steps,
        |s| s.impacts_bounce = true,
        4,
        false,
    );
    for passes in [4, 8] {
        run(
            &format!("defaults, {passes} restitution passes"),
            steps,
            |s| s.restitution_iterations = passes,
            4,
            false,
        );
    }
}
