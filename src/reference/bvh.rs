//! A bounding volume hierarchy over triangles in f64: binned surface-area heuristic
//! (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies"), nodes in
//! depth-first order, traversed nearest child first.

use glam::DVec3;

/// A triangle as intersection needs it: one vertex and the two edges from it.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    pub p0: DVec3,
    pub e1: DVec3,
    pub e2: DVec3,
}

impl Triangle {
    pub fn new(p0: DVec3, p1: DVec3, p2: DVec3) -> Self {
        Self {
            p0,
            e1: p1 - p0,
            e2: p2 - p0,
        }
    }

    fn bounds(&self) -> Aabb {
        let mut b = Aabb::point(self.p0);
        b.grow(self.p0 + self.e1);
        b.grow(self.p0 + self.e2);
        b
    }

    /// Möller & Trumbore 1997: (t, b1, b2) of the hit with t in (t_min, t_max), the point
    /// p0 + b1 e1 + b2 e2. In f64 the edge cases (a ray through an edge or a vertex) are
    /// 2⁻⁵² wide, far below a pixel's footprint.
    pub fn intersect(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64, f64)> {
        let p = dir.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let s = origin - self.p0;
        let b1 = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&b1) {
            return None;
        }
        let q = s.cross(self.e1);
        let b2 = dir.dot(q) * inv;
        if b2 < 0.0 || b1 + b2 > 1.0 {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        (t > t_min && t < t_max).then_some((t, b1, b2))
    }
}

#[derive(Clone, Copy, Debug)]
struct Aabb {
    min: DVec3,
    max: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    fn point(p: DVec3) -> Self {
        Self { min: p, max: p }
    }

    fn grow(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    fn union(&mut self, other: &Aabb) {
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }

    fn half_area(&self) -> f64 {
        let d = (self.max - self.min).max(DVec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// The slab test: the entry distance, if the ray meets the box within (t_min, t_max).
    fn hit(&self, origin: DVec3, inv_dir: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        // A NaN (an origin on a slab of a direction with a zero component) loses to the
        // other values: f64::max and min return the non-NaN operand.
        let near = t0.min(t1).max_element().max(t_min);
        let far = t0.max(t1).min_element().min(t_max);
        (near <= far).then_some(near)
    }
}

/// Interior nodes hold their second child's index in `first` (the first child follows
/// them); leaves hold `count` > 0 triangles from `order[first..]`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
    axis: u8,
}

/// The closest hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    /// Index into the triangles the BVH was built from.
    pub triangle: usize,
    pub b1: f64,
    pub b2: f64,
}

pub struct Bvh {
    /// The triangles in leaf order, so that a leaf's are contiguous in memory.
    triangles: Vec<Triangle>,
    nodes: Vec<Node>,
    /// The index each of `triangles` had in the list the BVH was built from.
    order: Vec<u32>,
}

const BINS: usize = 16;
/// Deepest node; a subtree reaching it becomes one leaf whatever its size.
const MAX_DEPTH: usize = 60;
const MAX_LEAF: usize = 4;
/// Cost of a node visit relative to a triangle test, in the SAH.
const TRAVERSAL_COST: f64 = 1.0;

impl Bvh {
    pub fn new(triangles: Vec<Triangle>) -> Self {
        let mut bvh = Self {
            order: (0..triangles.len() as u32).collect(),
            nodes: Vec::with_capacity(2 * triangles.len().max(1)),
            triangles,
        };
        if !bvh.triangles.is_empty() {
            let bounds: Vec<Aabb> = bvh.triangles.iter().map(Triangle::bounds).collect();
            let centroids: Vec<DVec3> = bounds.iter().map(|b| (b.min + b.max) * 0.5).collect();
            bvh.build(&bounds, &centroids, 0, bvh.triangles.len(), 0);
            bvh.triangles = bvh.order.iter().map(|&i| bvh.triangles[i as usize]).collect();
        }
        bvh
    }

    /// Builds the subtree over `order[start..end]`; returns its node index.
    fn build(&mut self, bounds: &[Aabb], centroids: &[DVec3], start: usize, end: usize, depth: usize) -> usize {
        let mut node_bounds = Aabb::EMPTY;
        let mut centre_bounds = Aabb::EMPTY;
        for &i in &self.order[start..end] {
            node_bounds.union(&bounds[i as usize]);
            centre_bounds.grow(centroids[i as usize]);
        }
        let index = self.nodes.len();
        self.nodes.push(Node {
            bounds: node_bounds,
            first: start as u32,
            count: (end - start) as u32,
            axis: 0,
        });
        let count = end - start;
        if count <= MAX_LEAF || depth == MAX_DEPTH {
            return index;
        }
        let Some((axis, split)) = self.best_split(bounds, centroids, start, end, &node_bounds, &centre_bounds) else {
            return index;
        };
        // Partition by bin; the SAH found both sides non-empty.
        let (lo, extent) = (
            centre_bounds.min[axis],
            centre_bounds.max[axis] - centre_bounds.min[axis],
        );
        let bin_of = |c: DVec3| (((c[axis] - lo) / extent * BINS as f64) as usize).min(BINS - 1);
        let mut mid = start;
        for i in start..end {
            if bin_of(centroids[self.order[i] as usize]) < split {
                self.order.swap(i, mid);
                mid += 1;
            }
        }
        self.build(bounds, centroids, start, mid, depth + 1);
        let second = self.build(bounds, centroids, mid, end, depth + 1);
        self.nodes[index].first = second as u32;
        self.nodes[index].count = 0;
        self.nodes[index].axis = axis as u8;
        index
    }

    /// The axis and first bin of the right side of the cheapest binned SAH split, or None
    /// when a leaf is cheaper (or the centroids coincide).
    fn best_split(
        &self,
        bounds: &[Aabb],
        centroids: &[DVec3],
        start: usize,
        end: usize,
        node_bounds: &Aabb,
        centre_bounds: &Aabb,
    ) -> Option<(usize, usize)> {
        let mut best: Option<(f64, usize, usize)> = None;
        for axis in [0, 1, 2] {
            let lo = centre_bounds.min[axis];
            let extent = centre_bounds.max[axis] - lo;
            if extent <= 0.0 {
                continue;
            }
            let mut bins = [(Aabb::EMPTY, 0usize); BINS];
            for &i in &self.order[start..end] {
                let b = (((centroids[i as usize][axis] - lo) / extent * BINS as f64) as usize).min(BINS - 1);
                bins[b].0.union(&bounds[i as usize]);
                bins[b].1 += 1;
            }
            // Sweep from the right for the right sides' areas and counts.
            let mut right = [(0.0, 0usize); BINS];
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for b in (1..BINS).rev() {
                acc.union(&bins[b].0);
                n += bins[b].1;
                right[b] = (acc.half_area(), n);
            }
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for split in 1..BINS {
                acc.union(&bins[split - 1].0);
                n += bins[split - 1].1;
                let (right_area, right_n) = right[split];
                if n == 0 || right_n == 0 {
                    continue;
                }
                let cost = acc.half_area() * n as f64 + right_area * right_n as f64;
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, split));
                }
            }
        }
        let (cost, axis, split) = best?;
        let leaf_cost = (end - start) as f64;
        let split_cost = TRAVERSAL_COST + cost / node_bounds.half_area().max(f64::MIN_POSITIVE);
        (split_cost < leaf_cost || end - start > 16 * MAX_LEAF).then_some((axis, split))
    }

    /// The closest hit with t in (t_min, t_max), skipping triangles for which `skip` is true.
    pub fn intersect(
        &self,
        origin: DVec3,
        dir: DVec3,
        t_min: f64,
        t_max: f64,
        skip: impl Fn(usize) -> bool,
    ) -> Option<Hit> {
        let mut closest = None;
        self.traverse(origin, dir, t_min, t_max, false, |triangle, t, b1, b2| {
            let taken = !skip(triangle);
            if taken {
                closest = Some(Hit { t, triangle, b1, b2 });
            }
            taken
        });
        closest
    }

    /// Whether anything not skipped lies on the ray within (t_min, t_max).
    pub fn occluded(&self, origin: DVec3, dir: DVec3, t_min: f64, t_max: f64, skip: impl Fn(usize) -> bool) -> bool {
        let mut found = false;
        self.traverse(origin, dir, t_min, t_max, true, |triangle, _, _, _| {
            found = !skip(triangle);
            found
        });
        found
    }

    /// Visits the triangles the ray may meet, nearest child first. `accept` is called for
    /// each hit closer than the closest taken so far and says whether it takes it; with
    /// `first_ends`, the first taken hit ends the walk (an occlusion query).
    fn traverse(
        &self,
        origin: DVec3,
        dir: DVec3,
        t_min: f64,
        mut t_max: f64,
        first_ends: bool,
        mut accept: impl FnMut(usize, f64, f64, f64) -> bool,
    ) {
        let inv_dir = dir.recip();
        let hit = |index: u32, t_max: f64| self.nodes[index as usize].bounds.hit(origin, inv_dir, t_min, t_max);
        if self.nodes.is_empty() || hit(0, t_max).is_none() {
            return;
        }
        // The build keeps the depth below MAX_DEPTH, so the far children fit.
        let mut stack = [(0u32, 0.0f64); MAX_DEPTH + 1];
        let mut top = 0;
        let mut current = 0u32;
        loop {
            let node = &self.nodes[current as usize];
            if node.count == 0 {
                let (a, b) = (current + 1, node.first);
                match (hit(a, t_max), hit(b, t_max)) {
                    (Some(ta), Some(tb)) => {
                        let (near, far, t_far) = if ta <= tb { (a, b, tb) } else { (b, a, ta) };
                        stack[top] = (far, t_far);
                        top += 1;
                        current = near;
                        continue;
                    }
                    (Some(_), None) => {
                        current = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        current = b;
                        continue;
                    }
                    (None, None) => {}
                }
            } else {
                let first = node.first as usize;
                for k in first..first + node.count as usize {
                    if let Some((t, b1, b2)) = self.triangles[k].intersect(origin, dir, t_min, t_max) {
                        if accept(self.order[k] as usize, t, b1, b2) {
                            if first_ends {
                                return;
                            }
                            t_max = t;
                        }
                    }
                }
            }
            // The next far child that the closest hit so far does not hide.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let (index, t_entry) = stack[top];
                if t_entry <= t_max {
                    current = index;
                    break;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn random_point(rng: &mut Rng, scale: f64) -> DVec3 {
        DVec3::new(
            rng.range(-scale, scale),
            rng.range(-scale, scale),
            rng.range(-scale, scale),
        )
    }

    fn brute_force(triangles: &[Triangle], origin: DVec3, dir: DVec3, skip: impl Fn(usize) -> bool) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, t) in triangles.iter().enumerate() {
            if skip(i) {
                continue;
            }
            let t_max = best.map_or(f64::INFINITY, |b| b.t);
            if let Some((t, b1, b2)) = t.intersect(origin, dir, 0.0, t_max) {
                best = Some(Hit { t, triangle: i, b1, b2 });
            }
        }
        best
    }

    /// A soup of small and large triangles, some sharing planes (a grid) and some
    /// degenerate: every ray's closest hit and occlusion agree with testing them all.
    #[test]
    fn hits_match_brute_force() {
        let mut rng = Rng::new(3);
        let mut triangles = Vec::new();
        for _ in 0..2000 {
            let p = random_point(&mut rng, 4.0);
            let size = rng.log_uniform(1e-3, 1.0);
            triangles.push(Triangle::new(
                p,
                p + random_point(&mut rng, size),
                p + random_point(&mut rng, size),
            ));
        }
        for i in 0..20 {
            for j in 0..20 {
                let p = DVec3::new(f64::from(i) * 0.2 - 2.0, -1.0, f64::from(j) * 0.2 - 2.0);
                triangles.push(Triangle::new(p, p + DVec3::X * 0.2, p + DVec3::Z * 0.2));
            }
        }
        let p = DVec3::ONE;
        triangles.push(Triangle::new(p, p, p + DVec3::X));
        let bvh = Bvh::new(triangles.clone());
        let skip = |i: usize| i % 7 == 3;
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..4000 {
            let origin = random_point(&mut rng, 6.0);
            let dir = (random_point(&mut rng, 5.0) - origin).normalize() * rng.range(0.5, 2.0);
            let expected = brute_force(&triangles, origin, dir, skip);
            let got = bvh.intersect(origin, dir, 0.0, f64::INFINITY, skip);
            assert_eq!(got, expected, "ray {origin} {dir}");
            let limit = rng.range(0.0, 10.0);
            let occluded = expected.is_some_and(|h| h.t < limit);
            assert_eq!(bvh.occluded(origin, dir, 0.0, limit, skip), occluded);
            if expected.is_some() {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(hits > 500 && misses > 500, "{hits} hits, {misses} misses");
    }

    #[test]
    fn an_empty_bvh_hits_nothing() {
        let bvh = Bvh::new(Vec::new());
        assert!(bvh
            .intersect(DVec3::ZERO, DVec3::X, 0.0, f64::INFINITY, |_| false)
            .is_none());
        assert!(!bvh.occluded(DVec3::ZERO, DVec3::X, 0.0, f64::INFINITY, |_| false));
    }

    /// Thousands of triangles in one point keep the depth bounded.
    #[test]
    fn coincident_triangles_build_a_bounded_tree() {
        let p = DVec3::new(0.5, 0.5, 0.5);
        let triangles = vec![Triangle::new(p, p + DVec3::X, p + DVec3::Y); 5000];
        let bvh = Bvh::new(triangles);
        let hit = bvh.intersect(DVec3::new(0.75, 0.75, -1.0), DVec3::Z, 0.0, f64::INFINITY, |_| false);
        assert!((hit.unwrap().t - 1.5).abs() < 1e-12);
    }
}
