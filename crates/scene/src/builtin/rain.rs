//! Box2D's `rain` benchmark (`shared/benchmarks.c`, `CreateRain` and `StepRain`): five rows of
//! ground, each of 501 half-metre boxes on one static body, and 40 columns of groups of five
//! ragdolls (Box2D's human, [`super::human`]) falling 40 m onto each row. Every 8 steps one
//! column gets a group in each row; once all 40 have theirs, every 8 steps the oldest
//! column's groups are destroyed and made again at the top, so the scene is always making and
//! destroying bodies and joints while 11,000 bodies and 10,000 joints fall, pile and sleep.
//!
//! The script keeps no state of its own: which column comes next follows from the step count
//! ([`wave`]), and a group's bodies are found in the world by their tag ([`tag`], kept as each
//! body's user data), so a restored snapshot or a replay carries on exactly where it was.

use tumble_physics::{BodyDef, BodyId, BodyKind, PartDef, SceneDef, World, WorldError};

use super::{human, rect};

/// Rows of ground, each with a group per column above it.
pub const ROWS: usize = 5;
/// Columns of groups across the ground.
pub const COLUMNS: usize = 40;
/// Humans in a group, side by side.
pub const GROUP_SIZE: usize = 5;
/// Side of a ground box (m), and its boxes in a row, less one.
const GRID_SIZE: f32 = 0.5;
const GRID_COUNT: usize = 500;
/// Steps between two waves of groups.
pub const DELAY: u64 = 8;
/// The rows' spacing (m), and a group's height above its row's ground.
const ROW_SPACING: f32 = 45.0;
const DROP_HEIGHT: f32 = 40.0;
/// High bits that mark a body's user data as a rain group's: "rain" in ASCII.
const TAG: u64 = 0x7261_696e << 32;

/// The scene at step 0: the ground only; the script makes the groups. 1000 steps, sleeping
/// on, every dynamic body's sleep threshold 0.1 m/s (Box2D's human sets it per body; here all
/// dynamic bodies are humans, so the scene's threshold is the same thing).
pub fn scene() -> SceneDef {
    let mut scene = SceneDef::new("rain");
    scene.steps = 1000;
    scene.solver.sleep_threshold = Some(0.1);
    let mut parts = Vec::with_capacity(ROWS * (GRID_COUNT + 1));
    let mut y = 0.0f32;
    for _ in 0..ROWS {
        let mut x = -0.5 * GRID_COUNT as f32 * GRID_SIZE;
        for _ in 0..=GRID_COUNT {
            parts.push(PartDef::new(rect(0.5 * GRID_SIZE, 0.5 * GRID_SIZE)).at(x, y, 0.0));
            x += GRID_SIZE;
        }
        y += ROW_SPACING;
    }
    scene.push(BodyDef::compound(parts).kind(BodyKind::Static));
    scene
}

/// What happens before step `steps`: `None` between waves, else the column whose groups (one
/// per row) are made, and whether that column's old groups are destroyed first.
pub fn wave(steps: u64) -> Option<(usize, bool)> {
    if !steps.is_multiple_of(DELAY) {
        return None;
    }
    let wave = usize::try_from(steps / DELAY).ok()?;
    Some(if wave < COLUMNS {
        (wave, false)
    } else {
        ((wave - COLUMNS) % COLUMNS, true)
    })
}

/// The user data that marks the bodies of the group at `row`, `column`.
pub fn tag(row: usize, column: usize) -> u64 {
    TAG | (row * COLUMNS + column) as u64
}

/// The group at `row`, `column` as a scene of its own (bodies and joints numbered from 0):
/// Box2D's `CreateGroup`, five humans 0.5 m apart with joint friction 0.05 N·m, springs of
/// 5 Hz and damping ratio 0.5, the i-th human of every group in filter group −(i + 1).
pub fn group(row: usize, column: usize) -> SceneDef {
    let span = GRID_COUNT as f32 * GRID_SIZE;
    let spacing = span / COLUMNS as f32;
    let mut x = -0.5 * span + spacing * (column as f32 + 0.5);
    let y = DROP_HEIGHT + ROW_SPACING * row as f32;
    let mut group = SceneDef::new("rain group");
    for i in 0..GROUP_SIZE {
        human(&mut group, [x, y], 0.05, 5.0, 0.5, i as i64 + 1);
        x += 0.5;
    }
    group
}

/// Makes `group`'s bodies in the world, each tagged `tag`, then its joints between them.
pub fn spawn(world: &mut World, tag: u64, group: &SceneDef) -> Result<(), WorldError> {
    let mut ids = Vec::with_capacity(group.bodies.len());
    for body in &group.bodies {
        let id = world.create_body(body)?;
        world.set_user_data(id, tag)?;
        ids.push(id);
    }
    for joint in &group.joints {
        let mut joint = joint.clone();
        // The group's joints name its bodies by their index in the group.
        for body in joint.bodies_mut() {
            *body = ids[body.index as usize];
        }
        world.create_joint(&joint)?;
    }
    Ok(())
}

/// The script: Box2D's `StepRain`. A wave that replaces a column destroys its old groups
/// (all rows at once: one [`World::destroy_bodies`], where Box2D destroys row by row; the
/// world after is the same), then makes them again row by row.
pub fn step(steps: u64, world: &mut World) {
    let Some((column, replace)) = wave(steps) else {
        return;
    };
    if replace {
        // One pass over the bodies finds all the column's groups.
        let old: Vec<BodyId> = world
            .body_ids()
            .filter(|&id| {
                let data = world.user_data(id).unwrap_or(0);
                let index = (data & 0xffff_ffff) as usize;
                data & !0xffff_ffff == TAG && index % COLUMNS == column && index / COLUMNS < ROWS
            })
            .collect();
        // Found alive just now, each once: the call cannot be refused.
        let _ = world.destroy_bodies(&old);
    }
    for row in 0..ROWS {
        // The group is fixed data that builds; a world too full for it stays as it is.
        let _ = spawn(world, tag(row, column), &group(row, column));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::Limits;

    #[test]
    fn waves_fill_the_columns_then_replace_them_oldest_first() {
        assert_eq!(wave(0), Some((0, false)));
        assert_eq!(wave(1), None);
        assert_eq!(wave(7), None);
        assert_eq!(wave(8), Some((1, false)));
        assert_eq!(wave(8 * 39), Some((39, false)));
        assert_eq!(wave(8 * 40), Some((0, true)));
        assert_eq!(wave(8 * 41), Some((1, true)));
        assert_eq!(wave(8 * 80), Some((0, true)));
    }

    #[test]
    fn groups_are_made_tagged_and_remade_in_place() {
        let scene = scene();
        let mut world = World::from_scene(&scene, &Limits::default()).unwrap();
        let bones = super::super::BONES.len();
        let per_group = GROUP_SIZE * bones;
        let joints = GROUP_SIZE * (bones - 1);
        let of = |world: &World, t: u64| -> Vec<BodyId> {
            world
                .body_ids()
                .filter(|&id| world.user_data(id).unwrap() == t)
                .collect()
        };
        step(0, &mut world);
        step(3, &mut world);
        step(DELAY, &mut world);
        // Two waves: columns 0 and 1, a group in each row.
        assert_eq!(world.body_count(), 1 + 2 * ROWS * per_group);
        assert_eq!(world.joint_count(), 2 * ROWS * joints);
        for row in 0..ROWS {
            assert_eq!(of(&world, tag(row, 0)).len(), per_group);
            assert_eq!(of(&world, tag(row, 1)).len(), per_group);
        }
        // Column 0's bottom group has fallen 30 m; the wave that replaces column 0 (the
        // script keeps no state: any step that is that wave's) puts a fresh group back at the
        // top, and leaves column 1 alone.
        for id in of(&world, tag(0, 0)) {
            let body = world.body(id).unwrap();
            world
                .set_transform(id, body.origin - tumble_physics::Vec2::Y * 30.0, body.angle)
                .unwrap();
        }
        let column_1 = of(&world, tag(2, 1));
        step(DELAY * COLUMNS as u64, &mut world);
        assert_eq!(world.body_count(), 1 + 2 * ROWS * per_group);
        assert_eq!(world.joint_count(), 2 * ROWS * joints);
        assert_eq!(of(&world, tag(2, 1)), column_1);
        let mut heights: Vec<f32> = of(&world, tag(0, 0))
            .into_iter()
            .map(|id| world.body(id).unwrap().origin.y)
            .collect();
        let mut expected: Vec<f32> = group(0, 0).bodies.iter().map(|b| b.position[1]).collect();
        heights.sort_by(f32::total_cmp);
        expected.sort_by(f32::total_cmp);
        assert_eq!(heights, expected);
        assert!(expected.iter().all(|&y| y > DROP_HEIGHT));
    }
}
