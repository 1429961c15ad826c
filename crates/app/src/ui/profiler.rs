//! The profile panel: each stage's milliseconds over the last seconds (egui_plot), and the
//! thread sweep, which runs a copy of the current scene at 1..N threads on a background thread
//! and plots milliseconds per step against threads.

use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};

use egui_plot::{Legend, Line, Plot, Points};
use tumble_physics::{SceneDef, StepSettings};

use crate::sim::{Sim, build_world};

/// Steps each thread count runs before timing starts (caches, pools, contacts settle).
pub const SWEEP_WARMUP_STEPS: u32 = 20;
/// Steps timed per thread count.
pub const SWEEP_TIMED_STEPS: u32 = 60;

/// One thread count's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepPoint {
    /// Worker threads.
    pub threads: usize,
    /// Mean wall time of one step (ms).
    pub step_ms: f64,
}

enum Message {
    Progress(f32),
    Point(SweepPoint),
    Done,
}

/// A thread sweep: idle, running (with progress), or finished (with points).
#[derive(Default)]
pub struct Sweep {
    rx: Option<Receiver<Message>>,
    /// Results so far, by thread count.
    pub points: Vec<SweepPoint>,
    /// 0..1 while running.
    pub progress: f32,
    /// The scene the points belong to.
    pub scene: String,
}

impl Sweep {
    /// Starts sweeping `sim`'s scene (from its start, with its current settings and
    /// substeps, its script and its sample's controller) at 1..=`max_threads` threads on a
    /// background thread.
    pub fn start(&mut self, sim: &Sim, max_threads: usize) {
        let (tx, rx) = channel();
        let scene = Arc::clone(&sim.scene);
        let settings = *sim.world.settings();
        let substeps = sim.substeps;
        let max_threads = max_threads.max(1);
        self.points.clear();
        self.progress = 0.0;
        self.scene = scene.name.clone();
        self.rx = Some(rx);
        crate::spawn_thread("thread-sweep", move || {
            run_sweep(&scene, settings, substeps, max_threads, &tx);
        })
        .map_err(|e| eprintln!("warning: cannot start the thread sweep: {e}"))
        .ok();
    }

    /// Whether a sweep is under way.
    pub fn is_running(&self) -> bool {
        self.rx.is_some()
    }

    /// Takes in what the sweep thread has sent.
    pub fn poll(&mut self) {
        let Some(rx) = &self.rx else {
            return;
        };
        let mut finished = false;
        loop {
            match rx.try_recv() {
                Ok(Message::Progress(p)) => self.progress = p,
                Ok(Message::Point(p)) => self.points.push(p),
                Ok(Message::Done) => {
                    self.progress = 1.0;
                    finished = true;
                }
                Err(std::sync::mpsc::TryRecvError::Empty) => break,
                Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                    finished = true;
                    break;
                }
            }
        }
        if finished {
            self.rx = None;
        }
    }
}

fn run_sweep(
    scene: &SceneDef,
    settings: StepSettings,
    substeps: u32,
    max_threads: usize,
    tx: &Sender<Message>,
) {
    let per = SWEEP_WARMUP_STEPS + SWEEP_TIMED_STEPS;
    let total = (per as usize * max_threads) as f32;
    for threads in 1..=max_threads {
        let Ok(mut world) = build_world(scene) else {
            break;
        };
        *world.settings_mut() = settings;
        world.set_thread_count(threads);
        // What runs between steps runs here too (junkyard's pusher, a sample's controller
        // with no key held: the platformer's elevator), so the sweep times the scene's step.
        let script = tumble_scene::builtin::script_for(scene);
        let mut controller = tumble_scene::sample::Controller::for_scene(scene);
        if let Some(c) = &controller {
            c.install(&mut world);
        }
        let mut ms = 0.0;
        for i in 0..per {
            let step = u64::from(i);
            if let Some(script) = script {
                script(step, &mut world);
            }
            if let Some(c) = &mut controller {
                c.before_step(step, tumble_scene::sample::Keys::NONE, &mut world);
            }
            world.step(scene.dt, substeps.max(1));
            if let Some(c) = &mut controller {
                c.after_step(step, &mut world);
            }
            if i >= SWEEP_WARMUP_STEPS {
                ms += world.profile().step_ms;
            }
            if i % 5 == 0 {
                let done = ((threads - 1) * per as usize + i as usize) as f32;
                if tx.send(Message::Progress(done / total)).is_err() {
                    return; // the viewer left
                }
            }
        }
        let point = SweepPoint {
            threads,
            step_ms: ms / f64::from(SWEEP_TIMED_STEPS),
        };
        if tx.send(Message::Point(point)).is_err() {
            return;
        }
    }
    let _ = tx.send(Message::Done);
}

/// The profile panel's contents.
pub fn profile_ui(ui: &mut egui::Ui, sim: &Sim, sweep: &mut Sweep) {
    let cores = tumble_physics::default_thread_count();
    ui.columns(2, |cols| {
        let ui = &mut cols[0];
        ui.label(format!(
            "Stage times, last {:.0} s of simulated time (ms per step)",
            crate::sim::HISTORY_SECONDS
        ));
        let now = sim.history.back().map_or(0.0, |s| s.time);
        let height = (ui.available_height() - 8.0).max(80.0);
        Plot::new("stages")
            .height(height)
            .legend(Legend::default())
            .include_y(0.0)
            .x_axis_label("s")
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .show(ui, |plot| {
                let stages = sim.history.front().map(|s| s.stages.map(|(name, _)| name));
                if let Some(names) = stages {
                    for (k, name) in names.iter().enumerate() {
                        let points: Vec<[f64; 2]> = sim
                            .history
                            .iter()
                            .map(|s| [s.time - now, s.stages[k].1])
                            .collect();
                        plot.line(Line::new(*name, points));
                    }
                }
                let total: Vec<[f64; 2]> = sim
                    .history
                    .iter()
                    .map(|s| [s.time - now, s.step_ms])
                    .collect();
                plot.line(Line::new("step", total).width(2.0));
            });

        let ui = &mut cols[1];
        ui.horizontal(|ui| {
            let label = format!("Thread sweep 1..{cores}");
            if ui
                .add_enabled(!sweep.is_running(), egui::Button::new(label))
                .on_hover_text(
                    "Runs a copy of this scene from its start at each thread count \
                     (the live world waits meanwhile) and plots ms per step.",
                )
                .clicked()
            {
                sweep.start(sim, cores);
            }
            if sweep.is_running() {
                ui.add(
                    egui::ProgressBar::new(sweep.progress)
                        .show_percentage()
                        .animate(true),
                );
            } else if let (Some(first), Some(best)) = (
                sweep.points.first(),
                sweep
                    .points
                    .iter()
                    .min_by(|a, b| a.step_ms.total_cmp(&b.step_ms)),
            ) {
                ui.label(format!(
                    "{}: {:.2}x at {} threads",
                    sweep.scene,
                    first.step_ms / best.step_ms.max(1e-9),
                    best.threads
                ));
            }
        });
        let height = (ui.available_height() - 8.0).max(80.0);
        Plot::new("sweep")
            .height(height)
            .include_y(0.0)
            .include_x(1.0)
            .include_x(cores as f64)
            .x_axis_label("threads")
            .y_axis_label("ms / step")
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .show(ui, |plot| {
                let pts: Vec<[f64; 2]> = sweep
                    .points
                    .iter()
                    .map(|p| [p.threads as f64, p.step_ms])
                    .collect();
                plot.line(Line::new("ms / step", pts.clone()));
                plot.points(Points::new("ms / step", pts).radius(4.0));
            });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sweep_runs_every_thread_count_on_its_own_thread() {
        let sim = Sim::load("vertical_stack", 1).unwrap();
        let mut sweep = Sweep::default();
        sweep.start(&sim, 2);
        assert!(sweep.is_running());
        let started = std::time::Instant::now();
        while sweep.is_running() {
            assert!(started.elapsed().as_secs() < 60, "sweep never finished");
            std::thread::sleep(std::time::Duration::from_millis(5));
            sweep.poll();
        }
        assert_eq!(sweep.progress, 1.0);
        let threads: Vec<usize> = sweep.points.iter().map(|p| p.threads).collect();
        assert_eq!(threads, vec![1, 2]);
        assert!(sweep.points.iter().all(|p| p.step_ms > 0.0));
    }
}
