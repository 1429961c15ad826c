//! How many proxies move in the broad phase a step, and how many contacts are kept, recycled
//! and touching, on `large_pyramid` (sleeping off), averaged over steps 10 to 300 at one
//! thread: the figures docs/bench/sleep.md quotes for the fat boxes grown together (157
//! moved a step). `cargo run --release -p tumble-tests --example moved_probe`. A count, not
//! a timing: the same on any machine.
use tumble_physics::{Limits, World};

fn main() {
    let scene = tumble_scene::builtin::build("large_pyramid").unwrap();
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.set_thread_count(1);
    let (mut moved, mut contacts, mut recycled, mut touching) = (0, 0, 0, 0);
    let (warmup, steps) = (10, 300);
    for s in 0..steps {
        w.step(scene.dt, scene.substeps);
        if s >= warmup {
            let p = w.profile();
            moved += p.moved;
            contacts += p.contacts;
            recycled += p.recycled;
            touching += p.touching;
        }
    }
    let n = steps - warmup;
    println!(
        "large_pyramid, a step on average: moved {} contacts {} recycled {} touching {}",
        moved / n,
        contacts / n,
        recycled / n,
        touching / n
    );
}
