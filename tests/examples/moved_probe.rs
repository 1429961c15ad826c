use tumble_physics::{Limits, World};
fn main() {
    let scene = tumble_scene::builtin::build("large_pyramid").unwrap();
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    w.set_thread_count(1);
    let (mut moved, mut contacts, mut recycled, mut touching) = (0usize, 0usize, 0usize, 0usize);
    for s in 0..300 {
        w.step(scene.dt, scene.substeps);
        if s >= 10 {
            let p = *w.profile();
            moved += p.moved;
            contacts += p.contacts;
            recycled += p.recycled;
            touching += p.touching;
        }
    }
    println!(
        "per step: moved {} contacts {} recycled {} touching {}",
        moved / 290,
        contacts / 290,
        recycled / 290,
        touching / 290
    );
}
