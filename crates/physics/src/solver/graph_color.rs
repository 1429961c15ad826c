//! Constraint graph colouring: no two constraints of one colour share a dynamic body, so
//! each colour can be solved in parallel without locks (Box2D v3 `constraint_graph.c`).
//!
//! We colour from scratch every step, greedily, in contact order. The contact order is
//! deterministic, so the colouring is too, and it never depends on history.

/// Colours available; the last acts as Box2D's overflow index and is never assigned.
pub const COLOR_COUNT: usize = 24;
/// Colours used by dynamic–dynamic constraints. The rest, near the end, take constraints
/// against static or kinematic bodies, so those are solved last in each pass and resist
/// push-through into the ground most (Box2D's `B2_DYNAMIC_COLOR_COUNT`).
pub const DYNAMIC_COLOR_COUNT: usize = COLOR_COUNT - 4;
/// The overflow colour's index in colour tables: constraints that fit nowhere.
pub const OVERFLOW: usize = COLOR_COUNT - 1;

/// Per-colour bitsets over body ids, reused between steps.
#[derive(Default, Debug, Clone)]
pub struct GraphColoring {
    bits: Vec<Vec<u64>>,
}

impl GraphColoring {
    /// Clears the bitsets for `body_count` bodies.
    pub fn reset(&mut self, body_count: usize) {
        let words = body_count.div_ceil(64);
        self.bits.resize_with(COLOR_COUNT, Vec::new);
        for b in &mut self.bits {
            b.clear();
            b.resize(words, 0);
        }
    }

    #[inline]
    fn test(&self, color: usize, body: usize) -> bool {
        self.bits[color][body >> 6] & (1u64 << (body & 63)) != 0
    }

    #[inline]
    fn set(&mut self, color: usize, body: usize) {
        self.bits[color][body >> 6] |= 1u64 << (body & 63);
    }

    /// Assigns a colour to a constraint between two bodies; `None` for a body means it is
    /// not dynamic (static or kinematic bodies are only read, so they never conflict).
    /// Returns [`OVERFLOW`] when no colour fits.
    pub fn assign(&mut self, a: Option<usize>, b: Option<usize>) -> usize {
        match (a, b) {
            (Some(a), Some(b)) => {
                for c in 0..DYNAMIC_COLOR_COUNT {
                    if !self.test(c, a) && !self.test(c, b) {
                        self.set(c, a);
                        self.set(c, b);
                        return c;
                    }
                }
                OVERFLOW
            }
            (Some(d), None) | (None, Some(d)) => {
                // Top down, never colour 0, as Box2D does.
                for c in (1..OVERFLOW).rev() {
                    if !self.test(c, d) {
                        self.set(c, d);
                        return c;
                    }
                }
                OVERFLOW
            }
            (None, None) => OVERFLOW,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_colour_shares_a_dynamic_body() {
        let mut g = GraphColoring::default();
        g.reset(100);
        // A chain 0-1-2-...-99 plus every body against the static ground.
        let mut by_color: Vec<Vec<(Option<usize>, Option<usize>)>> = vec![Vec::new(); COLOR_COUNT];
        for i in 0..99 {
            let c = g.assign(Some(i), Some(i + 1));
            by_color[c].push((Some(i), Some(i + 1)));
        }
        for i in 0..100 {
            let c = g.assign(Some(i), None);
            by_color[c].push((Some(i), None));
        }
        assert!(by_color[OVERFLOW].is_empty());
        for (c, list) in by_color.iter().enumerate() {
            let mut seen = std::collections::HashSet::new();
            for (a, b) in list {
                for d in [a, b].into_iter().flatten() {
                    assert!(seen.insert(*d), "colour {c} repeats body {d}");
                }
            }
        }
        // A chain needs 2 colours; static contacts go to the top colours.
        assert!(!by_color[0].is_empty() && !by_color[1].is_empty());
        assert!(
            by_color[2..DYNAMIC_COLOR_COUNT]
                .iter()
                .all(|l| l.is_empty())
        );
        assert_eq!(by_color[OVERFLOW - 1].len(), 100);
    }

    #[test]
    fn a_hub_overflows_after_the_dynamic_colours() {
        let mut g = GraphColoring::default();
        g.reset(64);
        let colors: Vec<usize> = (1..30).map(|i| g.assign(Some(0), Some(i))).collect();
        assert_eq!(
            &colors[..DYNAMIC_COLOR_COUNT],
            &(0..DYNAMIC_COLOR_COUNT).collect::<Vec<_>>()[..]
        );
        assert!(colors[DYNAMIC_COLOR_COUNT..].iter().all(|&c| c == OVERFLOW));
    }
}
