//! Constraint graph colouring: no two constraints of one colour share a dynamic body, so
//! each colour can be solved in parallel without locks (Box2D v3 `constraint_graph.c`).
//!
//! We colour greedily, in contact order, from the sequence of touching pairs alone: the
//! contact order is deterministic, so the colouring is too, and it never depends on history
//! (the solver keeps last step's colouring only when that sequence repeats exactly).

/// Colours available; the last acts as Box2D's overflow index and is never assigned.
pub const COLOR_COUNT: usize = 24;
/// Colours used by dynamic–dynamic constraints. The rest, near the end, take constraints
/// against static or kinematic bodies, so those are solved last in each pass and resist
/// push-through into the ground most (Box2D's `B2_DYNAMIC_COLOR_COUNT`).
pub const DYNAMIC_COLOR_COUNT: usize = COLOR_COUNT - 4;
/// The overflow colour's index in colour tables: constraints that fit nowhere.
pub const OVERFLOW: usize = COLOR_COUNT - 1;

/// For each body, the colours that already hold one of its constraints (bit c = colour c),
/// reused between steps. A body-major mask makes each assignment one bit scan instead of a
/// walk over per-colour bitsets (same colours chosen, so the same results).
#[derive(Default, Debug, Clone)]
pub struct GraphColoring {
    used: Vec<u32>,
}

const _: () = assert!(COLOR_COUNT <= 32);

/// Bits of the colours dynamic–dynamic constraints may take.
const DYNAMIC_COLORS: u32 = (1 << DYNAMIC_COLOR_COUNT) - 1;
/// Bits of the colours a constraint with one dynamic body may take: 1 to `OVERFLOW - 1`.
const STATIC_COLORS: u32 = ((1 << OVERFLOW) - 1) & !1;

impl GraphColoring {
    /// Clears the masks for `body_count` bodies.
    pub fn reset(&mut self, body_count: usize) {
        self.used.clear();
        self.used.resize(body_count, 0);
    }

    /// Assigns a colour to a constraint between two bodies; `None` for a body means it is
    /// not dynamic (static or kinematic bodies are only read, so they never conflict).
    /// Returns [`OVERFLOW`] when no colour fits.
    pub fn assign(&mut self, a: Option<usize>, b: Option<usize>) -> usize {
        match (a, b) {
            (Some(a), Some(b)) => {
                // The lowest colour free for both.
                let free = !(self.used[a] | self.used[b]) & DYNAMIC_COLORS;
                if free == 0 {
                    return OVERFLOW;
                }
                let c = free.trailing_zeros() as usize;
                self.used[a] |= 1 << c;
                self.used[b] |= 1 << c;
                c
            }
            (Some(d), None) | (None, Some(d)) => {
                // Top down, never colour 0, as Box2D does: the highest free colour.
                let free = !self.used[d] & STATIC_COLORS;
                if free == 0 {
                    return OVERFLOW;
                }
                let c = 31 - free.leading_zeros() as usize;
                self.used[d] |= 1 << c;
                c
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
