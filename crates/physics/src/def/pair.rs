//! `[x, y]` pairs read from either a list or a tuple, so RON files may write `(x, y)` (how
//! serde names a fixed array) or `[x, y]` (how the contract writes it); JSON has lists only.

use serde::de::{Deserializer, Error, SeqAccess, Visitor};
use std::fmt;

struct PairVisitor;

impl<'de> Visitor<'de> for PairVisitor {
    type Value = [f32; 2];

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a pair of numbers, written [x, y] (or (x, y) in RON)")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f32; 2], A::Error> {
        let x = seq
            .next_element::<f32>()?
            .ok_or_else(|| A::Error::invalid_length(0, &self))?;
        let y = seq
            .next_element::<f32>()?
            .ok_or_else(|| A::Error::invalid_length(1, &self))?;
        if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
            return Err(A::Error::invalid_length(3, &self));
        }
        Ok([x, y])
    }
}

/// One pair.
pub fn one<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 2], D::Error> {
    d.deserialize_any(PairVisitor)
}

struct Pair([f32; 2]);

impl<'de> serde::Deserialize<'de> for Pair {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Pair, D::Error> {
        one(d).map(Pair)
    }
}

/// Most points one list may hold.
const MAX_LIST: usize = 100_000;

struct ListVisitor;

impl<'de> Visitor<'de> for ListVisitor {
    type Value = Vec<[f32; 2]>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a list of [x, y] pairs")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut out = Vec::new();
        while let Some(Pair(p)) = seq.next_element::<Pair>()? {
            // Polygons have at most 8 vertices and chains rarely thousands of points;
            // stop early on absurd input.
            if out.len() >= MAX_LIST {
                return Err(A::Error::custom(format!(
                    "more than {MAX_LIST} points (split the chain)"
                )));
            }
            out.push(p);
        }
        Ok(out)
    }
}

/// A list of pairs.
pub fn list<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f32; 2]>, D::Error> {
    d.deserialize_seq(ListVisitor)
}
