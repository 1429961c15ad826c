//! Samples: the built-in scenes grouped as Box2D's samples app groups them, and the ones a
//! person plays, whose [`Controller`] reads the keys held and drives the world between
//! steps.
//!
//! A controller keeps what the world does not (a character's velocity, a score); it is plain
//! data, so the viewer's replay and snapshots keep it beside the world and a run replays bit
//! for bit. It sees the keys as a [`Keys`] set per step, never the wall clock, so the same
//! keys at the same steps give the same states natively, in the browser and in tests.

use serde::{Deserialize, Serialize};
use tumble_physics::{BodyId, PreSolve, SceneDef, ShapeId, World};

use crate::builtin::features::Feature;
use crate::builtin::platformer::Platformer;

/// Where a sample sits in the sample browser (Box2D's samples app's categories, and the
/// scene files).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Category {
    /// Box2D's benchmark scenes, under their names.
    Benchmark,
    /// Piles, pyramids and stacks.
    Stacking,
    /// Joints, chains and ragdolls.
    Joints,
    /// Shapes and materials.
    Shapes,
    /// Events, sensors and hooks.
    Events,
    /// Fast bodies, bullets and restitution.
    Continuous,
    /// Characters a person steers.
    Character,
    /// Hard cases: overlap, mass ratios, precision.
    Robustness,
    /// The scene files of `assets/scenes`.
    Files,
}

impl Category {
    /// Every category, in the browser's order.
    pub const ALL: [Category; 9] = [
        Category::Character,
        Category::Benchmark,
        Category::Stacking,
        Category::Joints,
        Category::Shapes,
        Category::Events,
        Category::Continuous,
        Category::Robustness,
        Category::Files,
    ];

    /// The heading the browser shows.
    pub fn name(self) -> &'static str {
        match self {
            Category::Benchmark => "Benchmark",
            Category::Stacking => "Stacking",
            Category::Joints => "Joints",
            Category::Shapes => "Shapes",
            Category::Events => "Events",
            Category::Continuous => "Continuous",
            Category::Character => "Character",
            Category::Robustness => "Robustness",
            Category::Files => "Scene files",
        }
    }
}

/// The keys a sample reads, held or not, as a set: one byte a step in a recording.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Keys(pub u8);

impl Keys {
    /// Walk left (Left, A).
    pub const LEFT: Keys = Keys(1);
    /// Walk right (Right, D).
    pub const RIGHT: Keys = Keys(1 << 1);
    /// Jump (Space, Up, W).
    pub const JUMP: Keys = Keys(1 << 2);
    /// Down (Down, S).
    pub const DOWN: Keys = Keys(1 << 3);
    /// The names [`Keys::parse`] takes, with their keys.
    pub const NAMES: [(&'static str, Keys); 4] = [
        ("left", Keys::LEFT),
        ("right", Keys::RIGHT),
        ("jump", Keys::JUMP),
        ("down", Keys::DOWN),
    ];

    /// No key held.
    pub const NONE: Keys = Keys(0);

    /// Whether every key of `other` is held.
    pub fn contains(self, other: Keys) -> bool {
        self.0 & other.0 == other.0
    }

    /// Holds or releases `key`.
    pub fn set(&mut self, key: Keys, held: bool) {
        if held {
            self.0 |= key.0;
        } else {
            self.0 &= !key.0;
        }
    }

    /// The key named `name` (`left`, `right`, `jump`, `down`).
    pub fn parse(name: &str) -> Option<Keys> {
        Keys::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, k)| k)
    }
}

/// A scripted key: at step `step` (counted from the scene's start, before that step is
/// taken), `key` goes down (`pressed`) or up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyEvent {
    /// The step it comes before.
    pub step: u64,
    /// The key.
    pub key: Keys,
    /// Down or up.
    pub pressed: bool,
}

/// A script of keys, as the viewer's `--keys` and the page's `keys=` take it: events
/// separated by commas or spaces, each `STEP:KEY+` (down) or `STEP:KEY-` (up), e.g.
/// `0:right+,95:jump+,99:jump-,400:right-`; or `demo`, the sample's own run
/// ([`KeyScript::for_scene`]). Sorted by step; events of one step apply in the
/// order given.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct KeyScript {
    /// The events, by step.
    pub events: Vec<KeyEvent>,
}

impl KeyScript {
    /// Reads a script, saying which event is wrong and how to write it.
    pub fn parse(text: &str) -> Result<KeyScript, String> {
        let mut events = Vec::new();
        for item in text.split([',', ' ']).filter(|s| !s.is_empty()) {
            let bad = |why: &str| {
                format!(
                    "key event `{item}`: {why}; write STEP:KEY+ or STEP:KEY- with KEY one of left, right, jump, down (e.g. 0:right+,120:right-)"
                )
            };
            let (step, rest) = item.split_once(':').ok_or_else(|| bad("no `:`"))?;
            let step: u64 = step
                .trim()
                .parse()
                .map_err(|_| bad("the step is not a whole number"))?;
            let (name, pressed) = match rest.trim() {
                r if r.ends_with('+') => (&r[..r.len() - 1], true),
                r if r.ends_with('-') => (&r[..r.len() - 1], false),
                _ => return Err(bad("it must end in + (down) or - (up)")),
            };
            let key = Keys::parse(name).ok_or_else(|| bad("unknown key"))?;
            events.push(KeyEvent { step, key, pressed });
        }
        // Stable: events of one step keep their order.
        events.sort_by_key(|e| e.step);
        Ok(KeyScript { events })
    }

    /// Reads a script for `scene`: `demo` is the sample's own run through its level (the
    /// platformer's [`SCRIPT`](crate::builtin::platformer::SCRIPT)), anything else as
    /// [`KeyScript::parse`] reads it.
    pub fn for_scene(text: &str, scene: &SceneDef) -> Result<KeyScript, String> {
        if text.trim() == "demo" {
            return match Controller::for_scene(scene).filter(|c| !c.demo_keys().is_empty()) {
                Some(c) => KeyScript::parse(c.demo_keys()),
                None => Err(format!(
                    "keys `demo`: {} has no demo run (a sample a person plays has: platformer)",
                    scene.name
                )),
            };
        }
        KeyScript::parse(text)
    }

    /// The keys held during step `step`, given those held during the step before.
    pub fn keys_at(&self, step: u64, before: Keys) -> Keys {
        let mut keys = before;
        for e in self.events.iter().filter(|e| e.step == step) {
            keys.set(e.key, e.pressed);
        }
        keys
    }

    /// Whether it has no events.
    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }
}

/// A sample that a person plays: what it keeps between steps, and what it does around them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Controller {
    /// The platformer's character and score.
    Platformer(Box<Platformer>),
    /// A feature sample's counts and drawing.
    Feature(Box<Feature>),
}

impl Controller {
    /// The controller of `scene` if it is a built-in that has one, as the built-in builds it
    /// (a scene under its name with other bodies gets none).
    pub fn for_scene(scene: &SceneDef) -> Option<Controller> {
        let builtin = crate::builtin::controller(&scene.name)?;
        (crate::builtin::build(&scene.name)? == *scene).then(builtin)
    }

    /// Sets the world's hooks the sample needs: after the world is built and after it is
    /// restored from a snapshot (hooks are code, not state).
    pub fn install(&self, world: &mut World) {
        match self {
            Controller::Platformer(_) => Platformer::install(world),
            Controller::Feature(f) => f.install(world),
        }
    }

    /// Before step `step` (counted from the scene's start) with `keys` held.
    pub fn before_step(&mut self, step: u64, keys: Keys, world: &mut World) {
        match self {
            Controller::Platformer(p) => p.before_step(step, keys, world),
            Controller::Feature(f) => f.before_step(step, keys, world),
        }
    }

    /// After step `step` was taken (its events are the world's).
    pub fn after_step(&mut self, step: u64, world: &mut World) {
        match self {
            Controller::Platformer(p) => p.after_step(step, world),
            Controller::Feature(f) => f.after_step(step, world),
        }
    }

    /// Lines for the viewer's panel.
    pub fn status(&self) -> Vec<String> {
        match self {
            Controller::Platformer(p) => p.status(),
            Controller::Feature(f) => f.lines.clone(),
        }
    }

    /// Draws what the world does not show (a character's ray, its planes).
    pub fn draw(&self, draw: &mut impl tumble_physics::draw::DebugDraw) {
        match self {
            Controller::Platformer(p) => p.draw(draw),
            Controller::Feature(f) => f.draw(draw),
        }
    }

    /// The sample's own run through its level, as a key script (`--keys demo`); empty for
    /// a sample that has none.
    pub fn demo_keys(&self) -> &'static str {
        match self {
            Controller::Platformer(_) => crate::builtin::platformer::SCRIPT,
            Controller::Feature(_) => "",
        }
    }

    /// What the camera follows (the character), if anything.
    pub fn focus(&self) -> Option<tumble_physics::Vec2> {
        match self {
            Controller::Platformer(p) => Some(p.position),
            Controller::Feature(_) => None,
        }
    }

    /// Whether the level was finished (the platformer's flag reached).
    pub fn finished(&self) -> bool {
        match self {
            Controller::Platformer(p) => p.reached_flag.is_some(),
            Controller::Feature(_) => false,
        }
    }
}

/// The first shape of the scene's body number `index` (a sample names its bodies by their
/// place in its scene).
pub fn scene_shape(world: &World, index: usize) -> Option<ShapeId> {
    world
        .body_shapes(BodyId::scene(index))
        .ok()?
        .next()
        .map(|s| s.id)
}

/// A pre-solve hook that makes `decks` one-way platforms: a contact with one pushes only
/// when its normal pushes the other shape up (more than 60 degrees from the horizontal);
/// every other contact pushes as usual.
pub fn one_way_platforms(decks: Vec<ShapeId>) -> PreSolve {
    Box::new(move |a, b, normal| {
        let up = if decks.contains(&a) {
            normal
        } else if decks.contains(&b) {
            -normal
        } else {
            return true;
        };
        up.y > 0.5
    })
}

/// Plays `scene` for `steps` steps with the keys of `script`, as the viewer does (its
/// controller before and after each step), on `threads` threads: the world and the
/// controller at the end. The scene must be valid.
pub fn play(
    scene: &SceneDef,
    script: &KeyScript,
    steps: u64,
    threads: usize,
    mut each: impl FnMut(u64, &World, Option<&Controller>),
) -> Result<(World, Option<Controller>), tumble_physics::SceneError> {
    let mut world = World::from_scene(scene, &tumble_physics::Limits::default())?;
    world.set_thread_count(threads);
    let mut controller = Controller::for_scene(scene);
    if let Some(c) = &controller {
        c.install(&mut world);
    }
    let script_fn = crate::builtin::script_for(scene);
    let mut keys = Keys::NONE;
    for step in 0..steps {
        keys = script.keys_at(step, keys);
        if let Some(f) = script_fn {
            f(step, &mut world);
        }
        if let Some(c) = &mut controller {
            c.before_step(step, keys, &mut world);
        }
        world.step(scene.dt, scene.substeps);
        if let Some(c) = &mut controller {
            c.after_step(step, &mut world);
        }
        each(step, &world, controller.as_ref());
    }
    Ok((world, controller))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_script_reads_and_applies_in_step_order() {
        let script = KeyScript::parse("10:jump+, 0:right+ 12:jump- 10:left+,10:left-").unwrap();
        assert_eq!(script.events.len(), 5);
        assert_eq!(script.events[0].step, 0);
        let k0 = script.keys_at(0, Keys::NONE);
        assert_eq!(k0, Keys::RIGHT);
        assert_eq!(script.keys_at(5, k0), Keys::RIGHT);
        // left went down and up within step 10, in the order given.
        let k10 = script.keys_at(10, k0);
        assert!(k10.contains(Keys::JUMP) && k10.contains(Keys::RIGHT) && !k10.contains(Keys::LEFT));
        assert_eq!(script.keys_at(12, k10), Keys::RIGHT);
    }

    #[test]
    fn demo_is_the_samples_own_run_and_other_scenes_have_none() {
        let platformer = crate::builtin::build("platformer").unwrap();
        let demo = KeyScript::for_scene("demo", &platformer).unwrap();
        assert_eq!(
            demo,
            KeyScript::parse(crate::builtin::platformer::SCRIPT).unwrap()
        );
        let pyramid = crate::builtin::build("pyramid").unwrap();
        assert!(
            KeyScript::for_scene("demo", &pyramid)
                .unwrap_err()
                .contains("no demo")
        );
        assert_eq!(
            KeyScript::for_scene("3:left+", &pyramid)
                .unwrap()
                .events
                .len(),
            1
        );
    }

    #[test]
    fn a_bad_key_script_says_which_event_and_how_to_write_it() {
        for (text, why) in [
            ("5right+", "no `:`"),
            ("x:right+", "not a whole number"),
            ("5:right", "must end in +"),
            ("5:fly+", "unknown key"),
        ] {
            let e = KeyScript::parse(text).unwrap_err();
            assert!(e.contains(why) && e.contains("STEP:KEY+"), "{text}: {e}");
        }
    }
}
