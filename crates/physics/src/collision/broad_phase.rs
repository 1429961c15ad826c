//! Broad phase: a bounding-volume hierarchy over every body's fat AABB, rebuilt when a fat
//! box changes, and queried only with the boxes that moved.
//!
//! Why a rebuilt tree and not Box2D's incremental tree: a median-split build over the fat
//! boxes is O(n log n), has no insertion-order history (so the same boxes always give the
//! same tree, on any thread count), and a resting scene rebuilds nothing because no fat box
//! changes. Pair finding queries the tree only with moved proxies, and a few moved proxies
//! refit only the nodes above them, so its cost follows what moved, not the body count (a
//! sleeping pile beside one moving body costs the tree nothing).

use glam::Vec2;

use crate::shape::Aabb;
use crate::threads::parallel::{Spread, for_parts};

/// Most proxies in a leaf: below this a linear scan beats descending further.
const LEAF_SIZE: usize = 4;

/// A piece of the tree's walk against itself: one subtree's pairs, or the pairs between two.
#[derive(Clone, Copy, Debug)]
enum Walk {
    Within(usize),
    Between(usize, usize),
}

/// A tree node: an internal node's children, or a leaf's range of `items`.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    /// Bounds of everything below.
    pub aabb: Aabb,
    /// Internal: index of the left child (the right is `child + 1`). Leaf: first item.
    child_or_first: u32,
    /// 0 for an internal node, otherwise the leaf's item count.
    count: u32,
}

impl Node {
    /// Whether this node holds proxies directly.
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The hierarchy. Proxy ids are body indices.
#[derive(Default, Debug, Clone)]
pub struct BroadPhase {
    nodes: Vec<Node>,
    items: Vec<u32>,
    /// Each node's parent (`NO_NODE` for the root), for refits that walk up from a leaf.
    parent: Vec<u32>,
    /// Each proxy's leaf (`NO_NODE` for a proxy not in the tree).
    leaf_of: Vec<u32>,
    /// Scratch for the build: centres of the boxes being split.
    centers: Vec<[f32; 2]>,
    /// [`cost`](Self::cost) right after the last rebuild.
    built_cost: f32,
    /// [`cost`](Self::cost) now, kept up to date by the refits.
    current_cost: f32,
}

/// "No node" in `parent` and `leaf_of`.
const NO_NODE: u32 = u32::MAX;

impl BroadPhase {
    /// The nodes, root first (empty when there are no proxies); for debug drawing.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Rebuilds the tree over the proxies of `aabbs` (proxy id = index) that `live` keeps.
    pub(crate) fn rebuild(&mut self, aabbs: &[Aabb], live: impl Fn(u32) -> bool) {
        self.nodes.clear();
        self.parent.clear();
        self.items.clear();
        self.items
            .extend((0..aabbs.len() as u32).filter(|&i| live(i)));
        self.leaf_of.clear();
        self.leaf_of.resize(aabbs.len(), NO_NODE);
        self.centers.clear();
        self.centers.extend(aabbs.iter().map(|b| {
            let c = b.center();
            [c.x, c.y]
        }));
        if self.items.is_empty() {
            self.built_cost = 0.0;
            self.current_cost = 0.0;
            return;
        }
        self.nodes.push(Node {
            aabb: aabbs[self.items[0] as usize],
            child_or_first: 0,
            count: 0,
        });
        self.parent.push(NO_NODE);
        let n = self.items.len();
        self.build(0, 0, n, aabbs);
        self.built_cost = self.cost();
        self.current_cost = self.built_cost;
    }

    /// Rebuilds the tree over every proxy of `aabbs`.
    #[cfg(test)]
    pub(crate) fn rebuild_all(&mut self, aabbs: &[Aabb]) {
        self.rebuild(aabbs, |_| true);
    }

    /// The summed perimeter of the inner nodes: what a query pays to descend, in the surface
    /// area heuristic's terms. A refitted tree whose bodies rearranged grows costlier.
    pub fn cost(&self) -> f32 {
        self.nodes
            .iter()
            .filter(|n| !n.is_leaf())
            .map(|n| n.aabb.perimeter())
            .sum()
    }

    /// How much costlier the tree is than right after its last rebuild (1 = as good).
    pub(crate) fn looseness(&self) -> f32 {
        if self.built_cost > 0.0 {
            self.current_cost / self.built_cost
        } else {
            1.0
        }
    }

    fn build(&mut self, node: usize, first: usize, end: usize, aabbs: &[Aabb]) {
        let items = &mut self.items[first..end];
        let mut bounds = aabbs[items[0] as usize];
        let mut cmin = self.centers[items[0] as usize];
        let mut cmax = cmin;
        for &i in items.iter() {
            bounds = bounds.union(&aabbs[i as usize]);
            let c = self.centers[i as usize];
            cmin = [cmin[0].min(c[0]), cmin[1].min(c[1])];
            cmax = [cmax[0].max(c[0]), cmax[1].max(c[1])];
        }
        self.nodes[node].aabb = bounds;
        let count = end - first;
        if count <= LEAF_SIZE {
            self.nodes[node].child_or_first = first as u32;
            self.nodes[node].count = count as u32;
            for &i in &self.items[first..end] {
                self.leaf_of[i as usize] = node as u32;
            }
            return;
        }
        // Median split on the longer axis of the centres; ties broken by id so the tree is
        // a pure function of the boxes.
        let axis = if cmax[0] - cmin[0] >= cmax[1] - cmin[1] {
            0
        } else {
            1
        };
        let mid = count / 2;
        let centers = &self.centers;
        items.select_nth_unstable_by(mid, |&a, &b| {
            centers[a as usize][axis]
                .total_cmp(&centers[b as usize][axis])
                .then(a.cmp(&b))
        });
        let left = self.nodes.len();
        let placeholder = Node {
            aabb: bounds,
            child_or_first: 0,
            count: 0,
        };
        self.nodes.push(placeholder);
        self.nodes.push(placeholder);
        self.parent.extend([node as u32; 2]);
        self.nodes[node].child_or_first = left as u32;
        self.nodes[node].count = 0;
        self.build(left, first, first + mid, aabbs);
        self.build(left + 1, first + mid, end, aabbs);
    }

    /// Proxies the tree was built over.
    pub fn proxy_count(&self) -> usize {
        self.items.len()
    }

    /// Recomputes every node's box from `aabbs` without changing the tree's shape: O(n), far
    /// cheaper than a rebuild, at the price of looser nodes as bodies wander. Nodes are stored
    /// parent before child, so a reverse walk sees children first.
    pub(crate) fn refit(&mut self, aabbs: &[Aabb]) {
        for k in (0..self.nodes.len()).rev() {
            self.nodes[k].aabb = self.fitted(k, aabbs);
        }
        self.current_cost = self.cost();
    }

    /// A refit when only the proxies in `moved` changed their boxes since the tree was last
    /// built or refitted: only the nodes above them are recomputed, each walk up stopping
    /// where a node's box comes out as it was. The boxes are exactly those of [`Self::refit`];
    /// the cost follows what moved (a tree's depth per proxy), not the proxy count.
    pub(crate) fn refit_moved(&mut self, aabbs: &[Aabb], moved: &[u32]) {
        // A walk up reads a node per level, scattered; a full refit streams through every
        // node. Past about one moved proxy in sixteen nodes the full refit is cheaper.
        let missing = moved
            .iter()
            .any(|&p| self.leaf_of.get(p as usize).is_none_or(|&l| l == NO_NODE));
        if missing || moved.len() * 16 > self.nodes.len() {
            self.refit(aabbs);
            return;
        }
        for &p in moved {
            let mut k = self.leaf_of[p as usize] as usize;
            loop {
                let aabb = self.fitted(k, aabbs);
                let old = self.nodes[k].aabb;
                if aabb == old {
                    break;
                }
                if !self.nodes[k].is_leaf() {
                    self.current_cost += aabb.perimeter() - old.perimeter();
                }
                self.nodes[k].aabb = aabb;
                match self.parent[k] {
                    NO_NODE => break,
                    up => k = up as usize,
                }
            }
        }
    }

    /// Node `k`'s box from its proxies' boxes (a leaf) or its children's (an inner node).
    fn fitted(&self, k: usize, aabbs: &[Aabb]) -> Aabb {
        let node = &self.nodes[k];
        let first = node.child_or_first as usize;
        if node.is_leaf() {
            let items = &self.items[first..first + node.count as usize];
            items[1..].iter().fold(aabbs[items[0] as usize], |b, &i| {
                b.union(&aabbs[i as usize])
            })
        } else {
            self.nodes[first].aabb.union(&self.nodes[first + 1].aabb)
        }
    }

    /// Calls `f(p, q)` once for every pair of distinct proxies whose fat boxes overlap, by
    /// walking the tree against itself (each subtree's pairs, then the pairs between sibling
    /// subtrees, pruned where their bounds part). When most proxies moved this is cheaper
    /// than one query per proxy, which visits the same upper nodes again for every proxy.
    #[cfg(test)]
    pub(crate) fn overlapping_pairs(&self, aabbs: &[Aabb], mut f: impl FnMut(u32, u32)) {
        if !self.nodes.is_empty() {
            self.pairs_within(0, aabbs, &mut f);
        }
    }

    /// [`overlapping_pairs`](Self::overlapping_pairs) over `spread`: the top six levels of
    /// the walk are cut into pieces (up to a few hundred), which the workers share, each
    /// keeping what `keep` returns for its pairs, sorted; the pieces' lists are joined in
    /// order, so the result is sorted runs, one a part (callers sort it).
    pub(crate) fn overlapping_pairs_parallel<T: Send + Ord>(
        &self,
        aabbs: &[Aabb],
        spread: Spread<'_>,
        keep: &(impl Fn(u32, u32) -> Option<T> + Sync),
    ) -> Vec<T> {
        if self.nodes.is_empty() {
            return Vec::new();
        }
        let mut walks = Vec::new();
        let depth = if spread.workers() > 1 { 6 } else { 0 };
        self.walks_within(0, depth, &mut walks);
        for_parts(
            spread,
            &walks[..],
            1,
            &|_, part: &[Walk]| {
                let mut out = Vec::new();
                for walk in part {
                    let mut found = |p, q| out.extend(keep(p, q));
                    match *walk {
                        Walk::Within(n) => self.pairs_within(n, aabbs, &mut found),
                        Walk::Between(a, b) => self.pairs_between(a, b, aabbs, &mut found),
                    }
                }
                out.sort_unstable();
                out
            },
            &|mut a, b| {
                a.extend(b);
                a
            },
        )
    }

    /// The pieces of the walk within subtree `n`, cut `depth` levels down.
    fn walks_within(&self, n: usize, depth: u32, out: &mut Vec<Walk>) {
        let node = self.nodes[n];
        if depth == 0 || node.is_leaf() {
            out.push(Walk::Within(n));
            return;
        }
        let left = node.child_or_first as usize;
        self.walks_within(left, depth - 1, out);
        self.walks_within(left + 1, depth - 1, out);
        self.walks_between(left, left + 1, depth - 1, out);
    }

    /// The pieces of the walk of subtree `a` against subtree `b`, cut `depth` levels down.
    fn walks_between(&self, a: usize, b: usize, depth: u32, out: &mut Vec<Walk>) {
        let (na, nb) = (self.nodes[a], self.nodes[b]);
        if depth == 0 || na.is_leaf() || nb.is_leaf() || !na.aabb.overlaps(&nb.aabb) {
            out.push(Walk::Between(a, b));
            return;
        }
        let [(a1, b1), (a2, b2)] = self.split_pair(a, b);
        self.walks_between(a1, b1, depth - 1, out);
        self.walks_between(a2, b2, depth - 1, out);
    }

    /// The two node pairs a walk of nodes `a` against `b` (not both leaves) descends to: it
    /// splits the inner one, or of two inner nodes the one with the larger box, so the pair
    /// of boxes shrinks fastest.
    fn split_pair(&self, a: usize, b: usize) -> [(usize, usize); 2] {
        let (na, nb) = (&self.nodes[a], &self.nodes[b]);
        if !na.is_leaf() && (nb.is_leaf() || na.aabb.perimeter() >= nb.aabb.perimeter()) {
            let c = na.child_or_first as usize;
            [(c, b), (c + 1, b)]
        } else {
            let c = nb.child_or_first as usize;
            [(a, c), (a, c + 1)]
        }
    }

    fn leaf_items(&self, node: &Node) -> &[u32] {
        let first = node.child_or_first as usize;
        &self.items[first..first + node.count as usize]
    }

    fn pairs_within(&self, n: usize, aabbs: &[Aabb], f: &mut impl FnMut(u32, u32)) {
        let node = self.nodes[n];
        if node.is_leaf() {
            let items = self.leaf_items(&node);
            for (k, &p) in items.iter().enumerate() {
                for &q in &items[k + 1..] {
                    if aabbs[p as usize].overlaps(&aabbs[q as usize]) {
                        f(p, q);
                    }
                }
            }
            return;
        }
        let left = node.child_or_first as usize;
        self.pairs_within(left, aabbs, f);
        self.pairs_within(left + 1, aabbs, f);
        self.pairs_between(left, left + 1, aabbs, f);
    }

    fn pairs_between(&self, a: usize, b: usize, aabbs: &[Aabb], f: &mut impl FnMut(u32, u32)) {
        let (na, nb) = (self.nodes[a], self.nodes[b]);
        if !na.aabb.overlaps(&nb.aabb) {
            return;
        }
        if na.is_leaf() && nb.is_leaf() {
            for &p in self.leaf_items(&na) {
                let bp = &aabbs[p as usize];
                for &q in self.leaf_items(&nb) {
                    if bp.overlaps(&aabbs[q as usize]) {
                        f(p, q);
                    }
                }
            }
            return;
        }
        for (a, b) in self.split_pair(a, b) {
            self.pairs_between(a, b, aabbs, f);
        }
    }

    /// Calls `f` with every proxy whose fat box overlaps `aabb`, in tree order.
    pub(crate) fn query(&self, aabb: &Aabb, aabbs: &[Aabb], mut f: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !node.aabb.overlaps(aabb) {
                continue;
            }
            if node.is_leaf() {
                let first = node.child_or_first as usize;
                for &item in &self.items[first..first + node.count as usize] {
                    if aabbs[item as usize].overlaps(aabb) {
                        f(item);
                    }
                }
            } else {
                // A median split halves the count at each level, so depth ≤ log2(n) + 1 < 64.
                stack[top] = node.child_or_first;
                stack[top + 1] = node.child_or_first + 1;
                top += 2;
            }
        }
    }
}

impl BroadPhase {
    /// Walks the proxies whose fat boxes the ray `origin + t · translation`, t in
    /// [0, `max_fraction`], may cross, calling `f(proxy, max_fraction)`, which returns the
    /// new largest fraction to look at: less to clip the ray (the nearest hit so far), the
    /// same to go on, 0 to stop (Box2D's `b2DynamicTree_RayCast`). A node is skipped when the
    /// ray's box misses it or the ray's line passes beside it (the separating axis along
    /// the ray's normal: van den Bergen, "Collision Detection in Interactive 3D
    /// Environments", 2003, p. 80).
    pub(crate) fn ray_cast(
        &self,
        aabbs: &[Aabb],
        origin: Vec2,
        translation: Vec2,
        mut max_fraction: f32,
        mut f: impl FnMut(u32, f32) -> f32,
    ) {
        if self.nodes.is_empty() || max_fraction <= 0.0 {
            return;
        }
        let normal = Vec2::new(-translation.y, translation.x);
        let abs_normal = normal.abs();
        let ray_box = |max_fraction: f32| {
            let end = origin + translation * max_fraction;
            Aabb {
                min: origin.min(end),
                max: origin.max(end),
            }
        };
        let misses = |b: &Aabb, ray: &Aabb| {
            let (c, h) = (b.center(), (b.max - b.min) * 0.5);
            !b.overlaps(ray) || (normal.dot(origin - c)).abs() > abs_normal.dot(h)
        };
        let mut ray = ray_box(max_fraction);
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if misses(&node.aabb, &ray) {
                continue;
            }
            if node.is_leaf() {
                let first = node.child_or_first as usize;
                for &item in &self.items[first..first + node.count as usize] {
                    if misses(&aabbs[item as usize], &ray) {
                        continue;
                    }
                    let value = f(item, max_fraction);
                    if value <= 0.0 {
                        return;
                    }
                    if value < max_fraction {
                        max_fraction = value;
                        ray = ray_box(max_fraction);
                    }
                }
            } else {
                // Nearer child on top, so that a hit found there clips the ray before the
                // farther one is tried (front to back along the ray).
                let (a, b) = (node.child_or_first, node.child_or_first + 1);
                let along = |n: u32| translation.dot(self.nodes[n as usize].aabb.center());
                let (near, far) = if along(a) <= along(b) { (a, b) } else { (b, a) };
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
    }
}

/// Whether the ray `origin + t · translation`, t in [0, `max_fraction`], may cross `b` (the
/// test [`BroadPhase::ray_cast`] makes of each node), for proxies outside the tree.
pub(crate) fn ray_may_cross(b: &Aabb, origin: Vec2, translation: Vec2, max_fraction: f32) -> bool {
    let end = origin + translation * max_fraction;
    let ray = Aabb {
        min: origin.min(end),
        max: origin.max(end),
    };
    let normal = Vec2::new(-translation.y, translation.x);
    let (c, h) = (b.center(), (b.max - b.min) * 0.5);
    b.overlaps(&ray) && (normal.dot(origin - c)).abs() <= normal.abs().dot(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes(n: usize) -> Vec<Aabb> {
        // A deterministic scatter of boxes of varied size.
        let mut seed = 12345u32;
        let mut next = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        (0..n)
            .map(|_| {
                let c = Vec2::new(next() * 50.0, next() * 50.0);
                let h = Vec2::new(0.1 + next(), 0.1 + next());
                Aabb {
                    min: c - h,
                    max: c + h,
                }
            })
            .collect()
    }

    #[test]
    fn query_finds_exactly_the_brute_force_pairs() {
        let aabbs = boxes(700);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        for (i, q) in aabbs.iter().enumerate() {
            let mut found = Vec::new();
            bp.query(q, &aabbs, |j| found.push(j as usize));
            found.sort();
            let brute: Vec<usize> = (0..aabbs.len()).filter(|&j| aabbs[j].overlaps(q)).collect();
            assert_eq!(found, brute, "proxy {i}");
        }
    }

    /// Where the ray enters box `b` (the slab method), if it does within [0, `max`].
    fn slab(b: &Aabb, o: Vec2, d: Vec2, max: f32) -> Option<f32> {
        let (mut lo, mut hi) = (0.0f32, max);
        for k in 0..2 {
            if d[k] == 0.0 {
                if o[k] < b.min[k] || o[k] > b.max[k] {
                    return None;
                }
            } else {
                let (t1, t2) = ((b.min[k] - o[k]) / d[k], (b.max[k] - o[k]) / d[k]);
                lo = lo.max(t1.min(t2));
                hi = hi.min(t1.max(t2));
            }
        }
        (lo <= hi).then_some(lo)
    }

    #[test]
    fn a_ray_visits_every_box_it_crosses_and_clipping_finds_the_nearest() {
        let aabbs = boxes(700);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        for k in 0..50 {
            let a = k as f32 * 0.37;
            let o = Vec2::new(-5.0 + k as f32, 25.0);
            let d = Vec2::new(a.cos(), a.sin()) * 80.0;
            let mut seen = Vec::new();
            bp.ray_cast(&aabbs, o, d, 1.0, |i, max| {
                seen.push(i as usize);
                max
            });
            seen.sort();
            // A box the ray truly crosses is always visited (the node tests are
            // conservative: a few more may be).
            for (j, b) in aabbs.iter().enumerate() {
                if slab(b, o, d, 1.0).is_some() {
                    assert!(seen.binary_search(&j).is_ok(), "ray {k} missed box {j}");
                }
            }
            // Clipping each time to the entry of the box met: the nearest entry is found.
            let mut nearest = 1.0f32;
            bp.ray_cast(&aabbs, o, d, 1.0, |i, max| {
                match slab(&aabbs[i as usize], o, d, max) {
                    Some(t) => {
                        nearest = nearest.min(t);
                        t.max(1e-9)
                    }
                    None => max,
                }
            });
            let brute = aabbs
                .iter()
                .filter_map(|b| slab(b, o, d, 1.0))
                .fold(1.0f32, f32::min);
            assert_eq!(nearest, brute, "ray {k}");
        }
    }

    #[test]
    fn overlapping_pairs_are_exactly_the_brute_force_pairs_each_once() {
        let aabbs = boxes(700);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        let mut found = Vec::new();
        bp.overlapping_pairs(&aabbs, |p, q| found.push((p.min(q), p.max(q))));
        let count = found.len();
        found.sort();
        found.dedup();
        assert_eq!(found.len(), count, "a pair reported twice");
        let mut brute = Vec::new();
        for p in 0..aabbs.len() {
            for q in p + 1..aabbs.len() {
                if aabbs[p].overlaps(&aabbs[q]) {
                    brute.push((p as u32, q as u32));
                }
            }
        }
        assert!(brute.len() > 100, "the scatter overlaps enough to test");
        assert_eq!(found, brute);
        let crew = crate::threads::crew::Crew::start(crate::threads::crew::tests::pool(1));
        for spread in [Spread::INLINE, Spread::over(&crew)] {
            let pair = |p: u32, q: u32| Some((p.min(q), p.max(q)));
            let mut parallel = bp.overlapping_pairs_parallel(&aabbs, spread, &pair);
            parallel.sort();
            assert_eq!(parallel, brute, "{spread:?}");
        }
    }

    #[test]
    fn refit_keeps_queries_exact() {
        let mut aabbs = boxes(500);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        // Move every third box far away, then refit instead of rebuilding.
        for (i, b) in aabbs.iter_mut().enumerate().filter(|(i, _)| i % 3 == 0) {
            let d = Vec2::new((i % 7) as f32 * 3.0 - 9.0, (i % 5) as f32 * 4.0 - 8.0);
            *b = Aabb {
                min: b.min + d,
                max: b.max + d,
            };
        }
        bp.refit(&aabbs);
        for q in &aabbs {
            let mut found = Vec::new();
            bp.query(q, &aabbs, |j| found.push(j as usize));
            found.sort();
            let brute: Vec<usize> = (0..aabbs.len()).filter(|&j| aabbs[j].overlaps(q)).collect();
            assert_eq!(found, brute);
        }
    }

    #[test]
    fn a_refit_of_the_moved_proxies_gives_a_full_refits_boxes() {
        let mut aabbs = boxes(600);
        let mut partial = BroadPhase::default();
        partial.rebuild_all(&aabbs);
        let mut full = partial.clone();
        // Rounds of a few moved boxes (the partial walk), then one of many (the full sweep);
        // the node boxes must equal a full refit's bit for bit every time, and the kept cost
        // the summed perimeters to f32 rounding (1e-4 relative over a few hundred updates).
        for (round, count) in [(0usize, 3usize), (1, 1), (2, 10), (3, 200)] {
            let moved: Vec<u32> = (0..count)
                .map(|k| ((k * 37 + round * 11) % aabbs.len()) as u32)
                .collect();
            for &i in &moved {
                let d = Vec2::new(round as f32 - 1.5, 2.0 - round as f32);
                let b = &mut aabbs[i as usize];
                *b = Aabb {
                    min: b.min + d,
                    max: b.max + d * 1.5,
                };
            }
            partial.refit_moved(&aabbs, &moved);
            full.refit(&aabbs);
            let boxes_of = |t: &BroadPhase| t.nodes.iter().map(|n| n.aabb).collect::<Vec<_>>();
            assert_eq!(boxes_of(&partial), boxes_of(&full), "round {round}");
            let kept = partial.current_cost;
            assert!((kept / partial.cost() - 1.0).abs() < 1e-4, "round {round}");
        }
        for q in &aabbs {
            let mut found = Vec::new();
            partial.query(q, &aabbs, |j| found.push(j as usize));
            found.sort();
            let brute: Vec<usize> = (0..aabbs.len()).filter(|&j| aabbs[j].overlaps(q)).collect();
            assert_eq!(found, brute);
        }
    }

    #[test]
    fn a_refit_after_the_boxes_rearranged_is_looser_and_a_rebuild_restores_it() {
        let mut aabbs = boxes(400);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        assert_eq!(bp.looseness(), 1.0);
        // Moving every box by the same offset keeps the tree as good as new...
        let shift = Vec2::new(3.0, -2.0);
        let shifted: Vec<Aabb> = aabbs
            .iter()
            .map(|b| Aabb {
                min: b.min + shift,
                max: b.max + shift,
            })
            .collect();
        bp.refit(&shifted);
        assert!((bp.looseness() - 1.0).abs() < 1e-3, "{}", bp.looseness());
        // ...while scrambling which box is where makes every node span the whole field.
        aabbs.reverse();
        bp.refit(&aabbs);
        assert!(bp.looseness() > 2.0, "{}", bp.looseness());
        bp.rebuild_all(&aabbs);
        assert_eq!(bp.looseness(), 1.0);
    }

    #[test]
    fn rebuild_is_a_pure_function_of_the_boxes() {
        let aabbs = boxes(300);
        let mut a = BroadPhase::default();
        let mut b = BroadPhase::default();
        a.rebuild_all(&aabbs);
        b.rebuild_all(&boxes(10));
        b.rebuild_all(&aabbs);
        assert_eq!(a.items, b.items);
        assert_eq!(a.nodes.len(), b.nodes.len());
    }
}
