//! Broad phase: a bounding-volume hierarchy over every body's fat AABB, rebuilt when a fat
//! box changes, and queried only with the boxes that moved.
//!
//! Why a rebuilt tree and not Box2D's incremental tree: a median-split build over the fat
//! boxes is O(n log n), has no insertion-order history (so the same boxes always give the
//! same tree, on any thread count), and a resting scene rebuilds nothing because no fat box
//! changes. Pair finding queries the tree only with moved proxies (or, where many moved,
//! walks the tree against itself once, leaving out the subtrees where nothing moved), and a
//! few moved proxies refit only the nodes above them, so its cost follows what moved, not the
//! body count (a sleeping pile beside one moving body costs the tree nothing). A refitted
//! tree is rebuilt when its walks grow twice as slow per pair found as its best since the
//! last rebuild, which a few large turning boxes can hide from its cost.

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

/// The work of a walk of the tree against itself: its leaves' box tests and the
/// overlapping pairs found (both the same on any thread count).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct WalkEffort {
    pub tests: u64,
    pub found: u64,
}

impl std::ops::Add for WalkEffort {
    type Output = WalkEffort;
    fn add(self, o: WalkEffort) -> WalkEffort {
        WalkEffort {
            tests: self.tests + o.tests,
            found: self.found + o.found,
        }
    }
}

/// A leaf's boxes as four lanes of each coordinate (a leaf of fewer filled with boxes
/// that overlap nothing), so that one box is tested against all of them at once.
struct LeafLanes {
    min_x: [f32; LEAF_SIZE],
    min_y: [f32; LEAF_SIZE],
    max_x: [f32; LEAF_SIZE],
    max_y: [f32; LEAF_SIZE],
}

impl LeafLanes {
    #[inline]
    fn of(boxes: &[Aabb]) -> LeafLanes {
        let mut lanes = LeafLanes {
            min_x: [f32::INFINITY; LEAF_SIZE],
            min_y: [f32::INFINITY; LEAF_SIZE],
            max_x: [f32::NEG_INFINITY; LEAF_SIZE],
            max_y: [f32::NEG_INFINITY; LEAF_SIZE],
        };
        for (k, b) in boxes.iter().enumerate().take(LEAF_SIZE) {
            lanes.min_x[k] = b.min.x;
            lanes.min_y[k] = b.min.y;
            lanes.max_x[k] = b.max.x;
            lanes.max_y[k] = b.max.y;
        }
        lanes
    }

    /// Bit k set where lane k overlaps `b` ([`Aabb::overlaps`], lane by lane without
    /// branches, which the compiler turns into one vector compare per coordinate).
    #[inline]
    fn overlapping(&self, b: &Aabb) -> u32 {
        let mut mask = 0;
        for k in 0..LEAF_SIZE {
            let apart = (self.min_x[k] > b.max.x)
                | (self.min_y[k] > b.max.y)
                | (b.min.x > self.max_x[k])
                | (b.min.y > self.max_y[k]);
            mask |= u32::from(!apart) << k;
        }
        mask
    }
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
    /// Each item's box, in `items`' order (a leaf's boxes side by side, a cache line for a
    /// leaf of four): the walk of the tree against itself reads these, not the proxies'
    /// boxes scattered by id. Kept equal to the proxies' boxes by every build and refit.
    item_boxes: Vec<Aabb>,
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
    /// Per node, whether a proxy below it moved (see [`Self::prepare_walk`]); empty: every
    /// node counts as moved. Emptied by every build and refit.
    node_moved: Vec<bool>,
    /// The pieces of the next walk of the tree against itself, and the worker count they
    /// were cut for (`None`: not prepared since the last build or refit).
    walk_pieces: Vec<Walk>,
    pieces_for: Option<usize>,
    /// Box tests per overlapping pair in the walks of the tree against itself since its
    /// last rebuild: the fewest (`None` before the first), and the latest walk's.
    best_walk_effort: Option<f32>,
    walk_effort: f32,
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
            self.item_boxes.clear();
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
        self.item_boxes.clear();
        self.item_boxes
            .extend(self.items.iter().map(|&i| aabbs[i as usize]));
        self.built_cost = self.cost();
        self.current_cost = self.built_cost;
        self.best_walk_effort = None;
        self.forget_walk();
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

    /// The walk's marks and pieces no longer hold (the boxes or the tree changed).
    fn forget_walk(&mut self) {
        self.node_moved.clear();
        self.pieces_for = None;
    }

    /// Prepares the next walk of the tree against itself for `workers`: marks the nodes
    /// above the proxies in `moved` (all of them in the tree), so that the walk leaves out
    /// every pair of subtrees neither of which holds one: it finds exactly the pairs with a
    /// moved member, at a cost that follows what moved and shares the upper levels that one
    /// query per moved proxy would walk again each time. Then cuts the walk into pieces, in
    /// a buffer kept from walk to walk (a steady step allocates nothing).
    pub(crate) fn prepare_walk(&mut self, moved: &[u32], workers: usize) {
        self.mark_moved(moved);
        let mut pieces = std::mem::take(&mut self.walk_pieces);
        pieces.clear();
        if !self.nodes.is_empty() {
            self.walks_within(0, Self::piece_depth(workers), &mut pieces);
        }
        self.walk_pieces = pieces;
        self.pieces_for = Some(workers);
    }

    /// How many levels down the walk is cut into pieces for `workers`.
    fn piece_depth(workers: usize) -> u32 {
        if workers > 1 { 6 } else { 0 }
    }

    fn mark_moved(&mut self, moved: &[u32]) {
        self.node_moved.clear();
        let leaf = |p: u32| self.leaf_of.get(p as usize).copied().unwrap_or(NO_NODE);
        if moved.iter().any(|&p| leaf(p) == NO_NODE) {
            // Not all in the tree (it was not brought up to date): every node counts.
            return;
        }
        self.node_moved.resize(self.nodes.len(), false);
        for &p in moved {
            let mut k = self.leaf_of[p as usize];
            while k != NO_NODE && !self.node_moved[k as usize] {
                self.node_moved[k as usize] = true;
                k = self.parent[k as usize];
            }
        }
    }

    /// Whether a proxy below node `n` moved (every node, until [`Self::prepare_walk`]).
    #[inline]
    fn moved_below(&self, n: usize) -> bool {
        self.node_moved.get(n).copied().unwrap_or(true)
    }

    /// Whether the latest walk of the tree against itself tested more than twice as many
    /// boxes per overlapping pair as the best walk since the last rebuild: a refitted tree
    /// whose bodies rearranged, where [`looseness`](Self::looseness) misses it because a few
    /// large turning boxes make most of the cost (tumbler's walls: from 6.5 to 26 tests a
    /// pair over its 750 steps while the looseness stayed under 1.25). The best walk, not
    /// the first: a scene's first walks find few pairs (bodies placed apart).
    pub(crate) fn walks_slowly(&self) -> bool {
        self.best_walk_effort
            .is_some_and(|best| self.walk_effort > 2.0 * best)
    }

    /// Notes the effort of a walk of the tree against itself (see [`Self::walks_slowly`]).
    pub(crate) fn note_walk(&mut self, effort: WalkEffort) {
        let per_pair = effort.tests as f32 / effort.found.max(1) as f32;
        self.walk_effort = per_pair;
        self.best_walk_effort = Some(self.best_walk_effort.map_or(per_pair, |b| b.min(per_pair)));
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
        self.forget_walk();
        for (b, &i) in self.item_boxes.iter_mut().zip(&self.items) {
            *b = aabbs[i as usize];
        }
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
        self.forget_walk();
        // A walk up reads a node per level, scattered; a full refit streams through every
        // node. Past about one moved proxy in sixteen nodes the full refit is cheaper.
        let missing = moved
            .iter()
            .any(|&p| self.leaf_of.get(p as usize).is_none_or(|&l| l == NO_NODE));
        if missing || moved.len() * 16 > self.nodes.len() {
            self.refit(aabbs);
            return;
        }
        // Every moved item's box first, so that each leaf is fitted from current boxes.
        for &p in moved {
            let leaf = &self.nodes[self.leaf_of[p as usize] as usize];
            let first = leaf.child_or_first as usize;
            // A leaf holds at most `LEAF_SIZE` items: a scan finds the proxy's place.
            let items = &self.items[first..first + leaf.count as usize];
            if let Some(at) = items.iter().position(|&i| i == p) {
                self.item_boxes[first + at] = aabbs[p as usize];
            }
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
            debug_assert!(
                self.leaf_items(node)
                    .iter()
                    .zip(self.leaf_boxes(node))
                    .all(|(&i, b)| aabbs[i as usize] == *b)
            );
            let boxes = self.leaf_boxes(node);
            boxes[1..].iter().fold(boxes[0], |b, c| b.union(c))
        } else {
            self.nodes[first].aabb.union(&self.nodes[first + 1].aabb)
        }
    }

    /// Calls `f(p, q)` once for every pair of distinct proxies whose fat boxes overlap, by
    /// walking the tree against itself (each subtree's pairs, then the pairs between sibling
    /// subtrees, pruned where their bounds part). When most proxies moved this is cheaper
    /// than one query per proxy, which visits the same upper nodes again for every proxy.
    #[cfg(test)]
    pub(crate) fn overlapping_pairs(&self, mut f: impl FnMut(u32, u32)) {
        if !self.nodes.is_empty() {
            self.pairs_within(0, &mut f, &mut 0);
        }
    }

    /// [`overlapping_pairs`](Self::overlapping_pairs) over `spread`: the top six levels of
    /// the walk are cut into pieces (up to a few hundred), which the workers share, each
    /// keeping what `keep` returns for its pairs, sorted; the pieces' lists are joined in
    /// order, so the result is sorted runs, one a part (callers sort it). With it, the walk's
    /// effort, for [`Self::note_walk`]. The tree must be fitted to the proxies' boxes (its
    /// leaves read their own copies).
    pub(crate) fn overlapping_pairs_parallel<T: Send + Ord>(
        &self,
        spread: Spread<'_>,
        keep: &(impl Fn(u32, u32) -> Option<T> + Sync),
    ) -> (Vec<T>, WalkEffort) {
        if self.nodes.is_empty() {
            return (Vec::new(), WalkEffort::default());
        }
        // The pieces prepared for this walk, or (in tests) cut now.
        let cut_now;
        let walks = if self.pieces_for == Some(spread.workers()) {
            &self.walk_pieces
        } else {
            let mut pieces = Vec::new();
            self.walks_within(0, Self::piece_depth(spread.workers()), &mut pieces);
            cut_now = pieces;
            &cut_now
        };
        for_parts(
            spread,
            &walks[..],
            1,
            &|_, part: &[Walk]| {
                let mut out = Vec::new();
                let (mut tests, mut found) = (0, 0);
                for walk in part {
                    let mut f = |p, q| {
                        found += 1;
                        out.extend(keep(p, q));
                    };
                    match *walk {
                        Walk::Within(n) => self.pairs_within(n, &mut f, &mut tests),
                        Walk::Between(a, b) => self.pairs_between(a, b, &mut f, &mut tests),
                    }
                }
                out.sort_unstable();
                (out, WalkEffort { tests, found })
            },
            &|(mut a, ea), (b, eb)| {
                a.extend(b);
                (a, ea + eb)
            },
        )
    }

    /// The pieces of the walk within subtree `n`, cut `depth` levels down.
    fn walks_within(&self, n: usize, depth: u32, out: &mut Vec<Walk>) {
        let node = self.nodes[n];
        if !self.moved_below(n) {
            return;
        }
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
        if !(self.moved_below(a) || self.moved_below(b)) {
            return;
        }
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

    fn leaf_boxes(&self, node: &Node) -> &[Aabb] {
        let first = node.child_or_first as usize;
        &self.item_boxes[first..first + node.count as usize]
    }

    /// The pairs within subtree `n`, counting the leaves' box tests into `tests`.
    fn pairs_within(&self, n: usize, f: &mut impl FnMut(u32, u32), tests: &mut u64) {
        let node = self.nodes[n];
        if !self.moved_below(n) {
            return;
        }
        if node.is_leaf() {
            let (items, boxes) = (self.leaf_items(&node), self.leaf_boxes(&node));
            *tests += (items.len() * (items.len() - 1) / 2) as u64;
            for (k, (&p, bp)) in items.iter().zip(boxes).enumerate() {
                for (&q, bq) in items[k + 1..].iter().zip(&boxes[k + 1..]) {
                    if bp.overlaps(bq) {
                        f(p, q);
                    }
                }
            }
            return;
        }
        let left = node.child_or_first as usize;
        self.pairs_within(left, f, tests);
        self.pairs_within(left + 1, f, tests);
        self.pairs_between(left, left + 1, f, tests);
    }

    /// The pairs between subtrees `a` and `b`: a walk down the pairs of nodes whose boxes
    /// overlap, each tested before it is pushed, on a stack rather than by recursion.
    /// `tests` counts the leaves' box tests only: the same however the walk was cut into
    /// pieces (a pair of leaves is reached exactly when every pair above it overlaps).
    fn pairs_between(&self, a: usize, b: usize, f: &mut impl FnMut(u32, u32), tests: &mut u64) {
        let nodes = &self.nodes;
        let wanted = |a: usize, b: usize| {
            (self.moved_below(a) || self.moved_below(b)) && nodes[a].aabb.overlaps(&nodes[b].aabb)
        };
        if !wanted(a, b) {
            return;
        }
        // Each pop pushes at most two pairs, each a level deeper on one side: the stack
        // holds at most the two subtrees' depths (each under 64, see `query`) plus one.
        let mut stack = [(0u32, 0u32); 129];
        stack[0] = (a as u32, b as u32);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (a, b) = (stack[top].0 as usize, stack[top].1 as usize);
            let (na, nb) = (&nodes[a], &nodes[b]);
            if na.is_leaf() && nb.is_leaf() {
                let (ia, ba) = (self.leaf_items(na), self.leaf_boxes(na));
                let ib = self.leaf_items(nb);
                *tests += (ia.len() * ib.len()) as u64;
                let lanes = LeafLanes::of(self.leaf_boxes(nb));
                for (&p, bp) in ia.iter().zip(ba) {
                    let mut hits = lanes.overlapping(bp);
                    while hits != 0 {
                        f(p, ib[hits.trailing_zeros() as usize]);
                        hits &= hits - 1;
                    }
                }
                continue;
            }
            for (a, b) in self.split_pair(a, b) {
                if wanted(a, b) {
                    stack[top] = (a as u32, b as u32);
                    top += 1;
                }
            }
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
        bp.overlapping_pairs(|p, q| found.push((p.min(q), p.max(q))));
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
        let mut efforts = Vec::new();
        for spread in [Spread::INLINE, Spread::over(&crew)] {
            let pair = |p: u32, q: u32| Some((p.min(q), p.max(q)));
            let (mut parallel, effort) = bp.overlapping_pairs_parallel(spread, &pair);
            parallel.sort();
            assert_eq!(parallel, brute, "{spread:?}");
            efforts.push(effort);
        }
        // The rebuild that the effort may call for happens on any thread count alike.
        assert_eq!(efforts[0], efforts[1]);
        assert_eq!(efforts[0].found, brute.len() as u64);
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
    fn a_walk_that_tests_twice_the_boxes_a_pair_of_the_best_since_the_rebuild_is_slow() {
        let walk = |bp: &mut BroadPhase| {
            let (pairs, effort) =
                bp.overlapping_pairs_parallel(Spread::INLINE, &|p, q| Some((p.min(q), p.max(q))));
            bp.note_walk(effort);
            (pairs.len(), effort)
        };
        let mut aabbs = boxes(400);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        let (found, effort) = walk(&mut bp);
        // The effort counts every box test: at least one per pair found.
        assert_eq!(effort.found, found as u64);
        assert!(effort.tests >= effort.found);
        assert!(!bp.walks_slowly());
        // The same boxes shifted together: the same tree walk, as fast.
        let shift = Vec2::new(3.0, -2.0);
        for b in &mut aabbs {
            *b = Aabb {
                min: b.min + shift,
                max: b.max + shift,
            };
        }
        bp.refit(&aabbs);
        assert_eq!(walk(&mut bp).1, effort);
        assert!(!bp.walks_slowly());
        // Scrambled: the same pairs, found by testing many more boxes each.
        aabbs.reverse();
        bp.refit(&aabbs);
        let (found_scrambled, slow) = walk(&mut bp);
        assert_eq!(found_scrambled, found);
        assert!(slow.tests > 2 * effort.tests, "{slow:?} vs {effort:?}");
        assert!(bp.walks_slowly());
        bp.rebuild_all(&aabbs);
        let (_, rebuilt) = walk(&mut bp);
        assert_eq!(rebuilt, effort);
        assert!(!bp.walks_slowly());
    }

    #[test]
    fn a_walk_after_marking_the_moved_finds_every_pair_with_a_moved_member_and_no_more_work() {
        let aabbs = boxes(600);
        let mut bp = BroadPhase::default();
        bp.rebuild_all(&aabbs);
        let moved: Vec<u32> = (0..aabbs.len() as u32).filter(|p| p % 7 == 3).collect();
        let is_moved = |p: u32| p % 7 == 3;
        let mut brute = Vec::new();
        for p in 0..aabbs.len() {
            for q in p + 1..aabbs.len() {
                let (pu, qu) = (p as u32, q as u32);
                if aabbs[p].overlaps(&aabbs[q]) && (is_moved(pu) || is_moved(qu)) {
                    brute.push((pu, qu));
                }
            }
        }
        assert!(brute.len() > 50, "the scatter overlaps enough to test");
        let keep = |p: u32, q: u32| (is_moved(p) || is_moved(q)).then_some((p.min(q), p.max(q)));
        let (_, everything) = bp.overlapping_pairs_parallel(Spread::INLINE, &keep);
        bp.prepare_walk(&moved, 1);
        let crew = crate::threads::crew::Crew::start(crate::threads::crew::tests::pool(1));
        for spread in [Spread::INLINE, Spread::over(&crew)] {
            let (mut found, effort) = bp.overlapping_pairs_parallel(spread, &keep);
            found.sort();
            assert_eq!(found, brute, "{spread:?}");
            // Subtrees where nothing moved are left out: fewer boxes tested.
            assert!(
                effort.tests < everything.tests,
                "{effort:?} vs {everything:?}"
            );
        }
        // A rebuild forgets the marks: every pair again.
        bp.rebuild_all(&aabbs);
        assert_eq!(
            bp.overlapping_pairs_parallel(Spread::INLINE, &keep).1,
            everything
        );
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
