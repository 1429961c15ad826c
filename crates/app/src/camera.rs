//! The 2D camera: which world point is at the centre of the window and how many pixels a metre
//! covers. Screen coordinates are physical pixels with the origin at the top-left corner and y
//! pointing down; world coordinates are metres with y pointing up.

use glam::Vec2;
use tumble_physics::{Aabb, BodyKind, World};

/// Closest and farthest zoom, in pixels per metre.
pub const ZOOM_RANGE: (f32, f32) = (0.05, 20_000.0);

/// A 2D orthographic camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The world point drawn at the centre of the viewport.
    pub center: Vec2,
    /// Zoom: pixels per metre.
    pub pixels_per_metre: f32,
    /// The viewport's size in physical pixels.
    pub viewport: Vec2,
}

impl Camera {
    /// A camera looking at `center` at `pixels_per_metre` over a viewport of that size.
    pub fn new(center: Vec2, pixels_per_metre: f32, viewport: Vec2) -> Self {
        Self {
            center,
            pixels_per_metre,
            viewport: viewport.max(Vec2::ONE),
        }
    }

    /// Where a world point lands on the screen (pixels, y down).
    pub fn world_to_screen(&self, p: Vec2) -> Vec2 {
        let d = (p - self.center) * self.pixels_per_metre;
        Vec2::new(self.viewport.x * 0.5 + d.x, self.viewport.y * 0.5 - d.y)
    }

    /// The world point under a screen point (pixels, y down).
    pub fn screen_to_world(&self, s: Vec2) -> Vec2 {
        let d = Vec2::new(s.x - self.viewport.x * 0.5, self.viewport.y * 0.5 - s.y);
        self.center + d / self.pixels_per_metre
    }

    /// Clip-space units per metre on each axis: `clip = (world - center) * clip_scale`.
    pub fn clip_scale(&self) -> Vec2 {
        Vec2::new(
            2.0 * self.pixels_per_metre / self.viewport.x,
            2.0 * self.pixels_per_metre / self.viewport.y,
        )
    }

    /// The world rectangle the viewport shows.
    pub fn visible(&self) -> Aabb {
        let half = self.viewport * 0.5 / self.pixels_per_metre;
        Aabb {
            min: self.center - half,
            max: self.center + half,
        }
    }

    /// Moves the view with the pointer: `delta` is the pointer's motion in pixels.
    pub fn pan_pixels(&mut self, delta: Vec2) {
        self.center -= Vec2::new(delta.x, -delta.y) / self.pixels_per_metre;
    }

    /// Zooms by `factor` (> 1 zooms in) keeping the world point under `screen` in place.
    pub fn zoom_at(&mut self, screen: Vec2, factor: f32) {
        if !(factor.is_finite() && factor > 0.0) {
            return;
        }
        let anchor = self.screen_to_world(screen);
        self.pixels_per_metre = (self.pixels_per_metre * factor).clamp(ZOOM_RANGE.0, ZOOM_RANGE.1);
        // Put the anchor back under the pointer.
        let moved = self.screen_to_world(screen);
        self.center += anchor - moved;
    }

    /// Frames `bounds` inside the screen rectangle `area` (pixels: min, max) with a margin.
    pub fn fit(&mut self, bounds: Aabb, area: (Vec2, Vec2)) {
        let size = (bounds.max - bounds.min).max(Vec2::splat(0.5));
        let area_size = (area.1 - area.0).max(Vec2::splat(16.0));
        let ppm = (area_size.x / size.x).min(area_size.y / size.y) * 0.9;
        self.pixels_per_metre = ppm.clamp(ZOOM_RANGE.0, ZOOM_RANGE.1);
        // The area's centre on screen must show the bounds' centre.
        let area_center = (area.0 + area.1) * 0.5;
        let offset = area_center - self.viewport * 0.5;
        self.center = bounds.center() - Vec2::new(offset.x, -offset.y) / self.pixels_per_metre;
    }
}

/// What "fit scene" frames: the moving bodies (dynamic and kinematic) with a margin, so a
/// pyramid on a long ground fills the view; the whole world when nothing moves. A box around
/// the origin for an empty world.
pub fn world_bounds(world: &World) -> Aabb {
    let union = |statics: bool| {
        let mut bounds: Option<Aabb> = None;
        // Every shape of every live body.
        for shape in world.shapes() {
            let b = shape.fat_aabb;
            if !statics
                && world
                    .body(shape.body)
                    .is_ok_and(|b| b.kind == BodyKind::Static)
            {
                continue;
            }
            if b.min.is_finite() && b.max.is_finite() {
                bounds = Some(bounds.map_or(b, |a| a.union(&b)));
            }
        }
        bounds
    };
    if let Some(moving) = union(false) {
        // A margin of a quarter of the size, and at least a metre, so the ground shows.
        let margin = ((moving.max - moving.min) * 0.25).max(Vec2::ONE);
        return Aabb {
            min: moving.min - margin,
            max: moving.max + margin,
        };
    }
    union(true).unwrap_or(Aabb {
        min: Vec2::splat(-1.0),
        max: Vec2::splat(1.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screen_and_world_round_trip() {
        let cam = Camera::new(Vec2::new(3.0, -2.0), 40.0, Vec2::new(800.0, 600.0));
        assert_eq!(cam.world_to_screen(cam.center), Vec2::new(400.0, 300.0));
        // One metre up is 40 pixels up (smaller y on screen).
        assert_eq!(
            cam.world_to_screen(cam.center + Vec2::Y),
            Vec2::new(400.0, 260.0)
        );
        let p = Vec2::new(7.5, 1.25);
        assert!((cam.screen_to_world(cam.world_to_screen(p)) - p).length() < 1e-4);
    }

    #[test]
    fn zoom_keeps_the_point_under_the_pointer() {
        let mut cam = Camera::new(Vec2::ZERO, 20.0, Vec2::new(640.0, 480.0));
        let pointer = Vec2::new(100.0, 50.0);
        let before = cam.screen_to_world(pointer);
        cam.zoom_at(pointer, 1.5);
        assert!((cam.pixels_per_metre - 30.0).abs() < 1e-4);
        assert!((cam.screen_to_world(pointer) - before).length() < 1e-4);
    }

    #[test]
    fn fit_frames_the_bounds_inside_the_area() {
        let mut cam = Camera::new(Vec2::ZERO, 1.0, Vec2::new(1000.0, 500.0));
        let bounds = Aabb {
            min: Vec2::new(-10.0, 0.0),
            max: Vec2::new(10.0, 5.0),
        };
        // Leave 200 px on the left for a panel.
        let area = (Vec2::new(200.0, 0.0), Vec2::new(1000.0, 500.0));
        cam.fit(bounds, area);
        let a = cam.world_to_screen(bounds.min);
        let b = cam.world_to_screen(bounds.max);
        for s in [a, b] {
            assert!(
                s.x >= 200.0 && s.x <= 1000.0 && s.y >= 0.0 && s.y <= 500.0,
                "{s}"
            );
        }
        let mid = cam.world_to_screen(bounds.center());
        assert!((mid - Vec2::new(600.0, 250.0)).length() < 1e-3, "{mid}");
    }
}
