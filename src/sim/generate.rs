//! Assembly generation: `CReate`, `RGEnerate` (random) and `AGEnerate` (lattice), with the
//! overlap check and the agglomerate regions of `AGGlomerate` (Lian §5.3).
//!
//! A generated particle is *inside* a region when the whole particle is inside: its centre
//! lies within R_A − R of the region centre (doc/spec/DECISIONS.md). Without a region, the particle
//! must lie in the work-space: its centre in [0, L) on periodic axes, in [R, L − R] on open
//! axes. Overlap: centre distance below (R_i + R_j)(1 − 1e-9), so touching lattice spheres are
//! accepted despite round-off (`SET GENoverlap` changes the tolerance, e.g. to build agglomerates
//! at the JKR zero-load spacing).

use std::collections::HashMap;

pub use super::scene::{CreateIndex, OverlapIndex};
use super::scene::{Region, Scene, Vec3};

impl OverlapIndex {
    /// Indexes the scene's particles; `r_new` is the largest radius that will be checked.
    pub fn new(scene: &Scene, r_new: f64) -> Self {
        let rmax = scene.max_radius().max(r_new);
        let mut idx = OverlapIndex {
            h: 2.0 * rmax,
            cells: HashMap::default(),
            rmax,
            pos: Vec::new(),
            radius: Vec::new(),
            lo: Vec3::repeat(f64::INFINITY),
            hi: Vec3::repeat(f64::NEG_INFINITY),
        };
        for i in 0..scene.particles.len() {
            idx.insert(&scene.particles.pos[i], scene.particles.radius[i]);
        }
        idx
    }

    fn key(&self, x: &Vec3) -> (i64, i64, i64) {
        (
            (x.x / self.h).floor() as i64,
            (x.y / self.h).floor() as i64,
            (x.z / self.h).floor() as i64,
        )
    }

    /// Whether [`Self::overlaps`] answers as the minimum-image scan [`first_overlap`]
    /// does: every indexed centre lies in [0, L] along the periodic axes (the index looks
    /// at the images one period away only).
    pub fn decides(&self, scene: &Scene) -> bool {
        (0..3).all(|k| {
            // (Empty: lo = +∞, hi = −∞, which passes.)
            !scene.settings.periodic[k] || (self.lo[k] >= 0.0 && self.hi[k] <= scene.size[k])
        })
    }

    /// Adds a sphere; returns its entry number (a sphere larger than those indexed so far
    /// widens the search, which stays correct with the cells it has).
    pub fn insert(&mut self, x: &Vec3, r: f64) -> usize {
        self.rmax = self.rmax.max(r);
        let k = self.key(x);
        let i = self.pos.len();
        self.pos.push(*x);
        self.radius.push(r);
        self.lo = self.lo.inf(x);
        self.hi = self.hi.sup(x);
        self.cells.entry(k).or_default().push(i);
        i
    }

    /// The first indexed sphere that a sphere (x, r) overlaps (minimum image on periodic
    /// axes), by entry number.
    pub fn overlaps(&self, scene: &Scene, x: &Vec3, r: f64) -> Option<usize> {
        let reach = ((r + self.rmax) / self.h).ceil() as i64;
        // An image farther than this from the indexed centres' box (along one axis) overlaps
        // none of them (the test below is d < (r + r_j)(1 − GENoverlap); a little slack for
        // the round-off of the image's coordinate). Only the images within it are searched:
        // with three periodic axes a point far from every side has one, not 27.
        let margin = (r + self.rmax) * (1.0 - scene.settings.gen_overlap).max(1.0) * (1.0 + 1e-9);
        let mut images = vec![*x];
        for k in 0..3 {
            if scene.settings.periodic[k] {
                let l = scene.size[k];
                let mut more = Vec::new();
                for im in &images {
                    for s in [-1.0, 1.0] {
                        let mut y = *im;
                        y[k] += s * l;
                        if !(y[k] - self.hi[k] > margin || self.lo[k] - y[k] > margin) {
                            more.push(y);
                        }
                    }
                }
                images.extend(more);
            }
        }
        for y in &images {
            let (cx, cy, cz) = self.key(y);
            for dz in -reach..=reach {
                for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        if let Some(v) = self.cells.get(&(cx + dx, cy + dy, cz + dz)) {
                            for &j in v {
                                let d = (self.pos[j] - y).norm();
                                if d < (r + self.radius[j]) * (1.0 - scene.settings.gen_overlap) {
                                    return Some(j);
                                }
                            }
                        }
                    }
                }
            }
        }
        None
    }
}

/// The first particle of the scene that a sphere (x, r) would overlap: a plain scan, which
/// `CReate` uses to confirm and name an overlap its index found (and where the index cannot
/// decide, [`OverlapIndex::decides`]).
pub fn first_overlap(scene: &Scene, x: &Vec3, r: f64) -> Option<usize> {
    let p = &scene.particles;
    (0..p.len()).find(|&j| {
        let d = scene.branch(&p.pos[j], x).norm();
        d < (r + p.radius[j]) * (1.0 - scene.settings.gen_overlap)
    })
}

/// Whether a particle (x, r) is acceptable with respect to the region / work-space.
pub fn inside(scene: &Scene, region: Option<&Region>, x: &Vec3, r: f64) -> bool {
    if let Some(g) = region {
        let d = (x - Vec3::from(g.centre)).norm();
        if d > g.radius - r {
            return false;
        }
    }
    for k in 0..3 {
        let l = scene.size[k];
        let ok = if scene.settings.periodic[k] {
            (0.0..l).contains(&x[k])
        } else {
            x[k] >= r && x[k] <= l - r
        };
        if !ok {
            return false;
        }
    }
    true
}

/// Mass of a sphere.
pub fn sphere_mass(rho: f64, r: f64) -> f64 {
    rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// Most lattice sites `AGEnerate` examines: 10 million, and 100 more per particle the scene
/// can hold (a step far below the particle size would otherwise make it loop for hours).
pub fn max_lattice_sites(nball: usize) -> u128 {
    10_000_000 + 100 * nball as u128
}

/// The index ranges (i, j, k, inclusive) of the sites of an orthorhombic lattice with the
/// given origin and step (positive) that can fall in the box `lo..hi` (the work-space, or
/// a region's bounding box: one site more on each side, for round-off; the caller keeps
/// only the sites inside), and their number.
pub fn lattice_ranges(
    origin: [f64; 3],
    step: [f64; 3],
    lo: [f64; 3],
    hi: [f64; 3],
) -> ([(i64, i64); 3], u128) {
    let mut range = [(0i64, 0i64); 3];
    let mut count: u128 = 1;
    for k in 0..3 {
        let (qa, qb) = (
            ((lo[k] - origin[k]) / step[k] - 1e-9).ceil(),
            ((hi[k] - origin[k]) / step[k] - 1e-9).ceil(),
        );
        // (`as i64` saturates: both ends of a huge range can saturate to one value, so the
        // number of sites is also taken from the unrounded ends; NaN counts as too many.)
        let (a, b) = (qa as i64, qb as i64);
        range[k] = (a.saturating_sub(1), b);
        let n = (range[k].1 as i128 - range[k].0 as i128 + 1).max(0) as u128;
        let span = qb - qa + 2.0;
        let n = if span.is_nan() || span >= 1e30 {
            u128::MAX
        } else {
            n.max(span.max(0.0) as u128)
        };
        count = count.saturating_mul(n);
    }
    (range, count)
}

/// The sites of `ranges` ([`lattice_ranges`]) in the work-space, in x-fastest order
/// (`AGEnerate`), each given to `f`; `f` returns false to stop.
pub fn lattice_sites(
    scene: &Scene,
    origin: [f64; 3],
    step: [f64; 3],
    range: [(i64, i64); 3],
    mut f: impl FnMut(Vec3) -> bool,
) {
    // (An axis without sites: none at all, whatever the width of the others.)
    if range.iter().any(|r| r.0 > r.1) {
        return;
    }
    for k in range[2].0..=range[2].1 {
        for j in range[1].0..=range[1].1 {
            for i in range[0].0..=range[0].1 {
                let x = Vec3::new(
                    origin[0] + i as f64 * step[0],
                    origin[1] + j as f64 * step[1],
                    origin[2] + k as f64 * step[2],
                );
                if x.iter()
                    .enumerate()
                    .all(|(a, &c)| c >= 0.0 && c < scene.size[a])
                    && !f(x)
                {
                    return;
                }
            }
        }
    }
}

/// How far a long generation command has got, for the session's progress line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advance {
    /// The command's name as the user reads it (`RGEnerate`, `AGEnerate`, `RGEnerate Seed`).
    pub command: &'static str,
    /// What `done` and `total` count: "particles placed", "sites examined", "numbers drawn".
    pub what: &'static str,
    pub done: u64,
    pub total: u64,
    /// `RGEnerate`: the tries so far (0 otherwise) and the fraction of the recent tries that
    /// placed a particle.
    pub tries: u64,
    pub rate: f64,
}

/// The session's watch over a long generation command, called every [`WATCH_EVERY`] steps:
/// given how far it has got, it answers whether to go on. `false` (Ctrl-C) stops the
/// command, which then changes nothing. The simulation core does no I/O: the progress line
/// and the signal are the session's.
pub type Watch<'a> = &'a mut dyn FnMut(&Advance) -> bool;

/// Tries, sites or numbers between two calls of a [`Watch`] (a few ms of work).
pub const WATCH_EVERY: u64 = 4096;

/// `RGEnerate`'s look-out for a target that random placement cannot reach.
///
/// Random sequential addition slows down as the free room fills: near the jamming limit
/// (a volume fraction of 0.38 for equal spheres, 0.55 for discs) the fraction approaches its
/// limit as t^(-1/d) in the number of tries t (Feder's law), so the rate of placement falls
/// as p ∝ t^(-α) with α → 1 + 1/d, and all that is still to come after try t is
/// ∫_t^∞ p = p t/(α − 1). The look-out measures α over two windows of tries, [t/4, t/2] and
/// [t/2, t], and gives up when even twice that (with α no larger than 1 + 1/d, the rate
/// taken at the upper end of its statistical error) falls short of the target, or when the
/// rate, which can only fall, cannot reach it within the try limit. Early on, while the
/// rate has not yet started to fall as a power (α ≤ 1), it never gives up; a scene filled
/// before the command began makes the measured α smaller, so the estimate larger (never
/// the other way round).
#[derive(Clone, Debug)]
pub struct RateWatch {
    /// (tries, placed) at tries = 1024 · 2^(k/4).
    marks: Vec<(u64, u64)>,
    next: f64,
    /// The space's dimension (2 in a `TWOd` scene).
    dim: f64,
}

/// The rate as an upper bound: `k` events in `w` tries (about two standard errors above).
fn rate_upper(k: u64, w: u64) -> f64 {
    let k = k as f64;
    (k + 2.0 * k.sqrt() + 2.0) / w.max(1) as f64
}

impl RateWatch {
    pub fn new(two_d: bool) -> Self {
        RateWatch {
            marks: Vec::new(),
            next: 1024.0,
            dim: if two_d { 2.0 } else { 3.0 },
        }
    }

    /// After try `tries`, with `placed` of `target` particles placed and at most `limit`
    /// tries: `Some` when the target cannot be reached.
    pub fn hopeless(
        &mut self,
        tries: u64,
        placed: u64,
        target: u64,
        limit: u64,
    ) -> Option<Hopeless> {
        if (tries as f64) < self.next {
            return None;
        }
        self.next *= 2f64.powf(0.25);
        self.marks.push((tries, placed));
        let k = self.marks.len();
        if k < 9 {
            return None;
        }
        let (t, m) = self.marks[k - 1];
        let (t2, m2) = self.marks[k - 5];
        let (t4, m4) = self.marks[k - 9];
        let (k2, w2) = (m - m2, t - t2);
        let (k1, w1) = (m2 - m4, t2 - t4);
        let r2 = rate_upper(k2, w2);
        // The rate can only fall: within the tries left it places at most r2 a try.
        let mut most = placed as f64 + r2 * limit.saturating_sub(tries) as f64;
        // The power-law tail, once the windows have counts to measure it by (or the rate
        // has fallen to nothing).
        if k1 + k2 >= 20 || (k2 == 0 && k1 > 0) {
            let mid = |a: u64, b: u64| 0.5 * (a + b) as f64;
            let alpha = if k2 == 0 {
                f64::INFINITY
            } else {
                ((k1 as f64 / w1 as f64) / (k2 as f64 / w2 as f64)).ln()
                    / (mid(t2, t) / mid(t4, t2)).ln()
            };
            let alpha = alpha.min(1.0 + 1.0 / self.dim);
            if alpha > 1.05 {
                most = most.min(placed as f64 + 2.0 * r2 * t as f64 / (alpha - 1.0));
            }
        }
        (most < target as f64).then_some(Hopeless {
            most: most.floor() as u64,
            recent: (k2, w2),
        })
    }
}

/// What [`RateWatch::hopeless`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hopeless {
    /// The most particles the placement could reach within the try limit by the estimate
    /// (those placed included).
    pub most: u64,
    /// Particles placed in the last half of the tries, and those tries.
    pub recent: (u64, u64),
}

/// Spreads the low 21 bits of `v` to every third bit (Morton interleaving).
fn spread3(v: u64) -> u64 {
    let mut x = v & 0x1f_ffff;
    x = (x | (x << 32)) & 0x1f00000000ffff;
    x = (x | (x << 16)) & 0x1f0000ff0000ff;
    x = (x | (x << 8)) & 0x100f00f00f00f00f;
    x = (x | (x << 4)) & 0x10c30c30c30c30c3;
    (x | (x << 2)) & 0x1249249249249249
}

/// The order of `pos` along a Morton (Z-order) curve through the box `lo..hi` (cubic cells:
/// 2^21 steps along the longest side), ties in the given order: particles close in space come
/// close in the order, so that the contact loop reads neighbouring particles from
/// neighbouring memory.
pub fn morton_order(pos: &[Vec3], lo: Vec3, hi: Vec3) -> Vec<usize> {
    let top = ((1u64 << 21) - 1) as f64;
    let extent = (hi - lo).max();
    let scale = if extent > 0.0 { top / extent } else { 0.0 };
    let key = |x: &Vec3| {
        let q = |k: usize| ((x[k] - lo[k]) * scale).clamp(0.0, top) as u64;
        spread3(q(0)) | (spread3(q(1)) << 1) | (spread3(q(2)) << 2)
    };
    let mut order: Vec<usize> = (0..pos.len()).collect();
    order.sort_by_key(|&k| key(&pos[k]));
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::rng::Rng;

    /// The index's answer (only the periodic images that can reach the indexed centres are
    /// searched) is the brute-force minimum-image test's, for points all over the box and
    /// near its sides, with one, two and three periodic axes and GENoverlap 0 … 0.05 (SET
    /// allows 0 ≤ f < 0.1).
    #[test]
    fn the_overlap_index_finds_what_a_brute_force_scan_finds() {
        for (periodic, g) in [
            ([true; 3], 1e-9),
            ([true, false, true], 1e-9),
            ([false, false, true], 0.05),
            ([true; 3], 0.0),
        ] {
            let mut sc = Scene::new([0.01, 0.012, 0.008], 10, 1000, 0);
            sc.settings.periodic = periodic;
            sc.settings.gen_overlap = g;
            let mut rng = Rng::new(7);
            let mut idx = OverlapIndex::new(&sc, 6e-4);
            let mut centres: Vec<(Vec3, f64)> = Vec::new();
            let point = |rng: &mut Rng| {
                // Half of the points within 1 mm of a side.
                let mut x = Vec3::zeros();
                for k in 0..3 {
                    let l = sc.size[k];
                    let u = rng.uniform();
                    x[k] = if rng.uniform() < 0.5 {
                        u * l
                    } else if u < 0.5 {
                        2.0 * u * 1e-3
                    } else {
                        l - 2.0 * (u - 0.5) * 1e-3
                    };
                }
                x
            };
            for _ in 0..150 {
                let x = point(&mut rng);
                let r = 2e-4 + 4e-4 * rng.uniform();
                idx.insert(&x, r);
                centres.push((x, r));
            }
            let (mut hits, mut misses) = (0, 0);
            for _ in 0..4000 {
                let x = point(&mut rng);
                let r = 1e-4 + 5e-4 * rng.uniform();
                let brute = centres
                    .iter()
                    .any(|(c, rc)| sc.branch(c, &x).norm() < (r + rc) * (1.0 - g));
                assert_eq!(
                    idx.overlaps(&sc, &x, r).is_some(),
                    brute,
                    "{x} {r} {periodic:?}"
                );
                if brute { hits += 1 } else { misses += 1 }
            }
            assert!(hits > 200 && misses > 200, "{hits} {misses}");
        }
    }

    /// The tries at which random sequential addition placed each sphere: periodic box of
    /// side 1, radii from `radius` (a new one after each placement, as `RGEnerate`), `pre`
    /// spheres placed before the watched run begins, `tries` tries in all.
    fn rsa(two_d: bool, radius: &dyn Fn(&mut Rng) -> f64, pre: usize, tries: u64) -> Vec<u64> {
        let mut sc = Scene::new([1.0, 1.0, 1.0], 10, 100_000, 0);
        sc.settings.periodic = [true; 3];
        let mut rng = Rng::new(11);
        let mut idx = OverlapIndex::new(&sc, 0.2);
        let mut r = radius(&mut rng);
        let mut placed = Vec::new();
        let mut t = 0;
        while t < tries {
            let mut x = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            if two_d {
                x.z = 0.5;
            }
            if placed.len() >= pre {
                t += 1;
            }
            if idx.overlaps(&sc, &x, r).is_none() {
                idx.insert(&x, r);
                if placed.len() >= pre {
                    placed.push(t);
                } else {
                    placed.push(0);
                }
                r = radius(&mut rng);
            }
        }
        placed.split_off(pre)
    }

    /// [`RateWatch`] replayed over a run whose placements came at the tries `at`, for
    /// target `n` and `RGEnerate`'s try limit: the try it gave up at, if it did.
    fn gives_up_at(at: &[u64], n: u64, two_d: bool) -> Option<u64> {
        let limit = 1000 * n + 10_000;
        let end = at
            .get(n as usize - 1)
            .copied()
            .unwrap_or(u64::MAX)
            .min(limit);
        let mut w = RateWatch::new(two_d);
        loop {
            let t = w.next.ceil() as u64;
            if t > end {
                return None;
            }
            let placed = at.partition_point(|&x| x <= t) as u64;
            if w.hopeless(t, placed, n, limit).is_some() {
                return Some(t);
            }
        }
    }

    /// The look-out never refuses a target that the try limit lets random placement reach
    /// (every target up to the last reached, in runs of equal spheres, discs, a spread of
    /// radii and a box already half filled), and gives up on one beyond reach long before the
    /// limit.
    #[test]
    fn rgenerate_gives_up_only_on_targets_beyond_reach() {
        let fixed = |r: f64| move |_: &mut Rng| r;
        let runs: [(&str, bool, &dyn Fn(&mut Rng) -> f64, usize); 4] = [
            ("spheres", false, &fixed(0.08), 0),
            ("discs", true, &fixed(0.03), 0),
            ("spread", false, &|g: &mut Rng| 0.05 + 0.05 * g.uniform(), 0),
            ("half full", false, &fixed(0.08), 80),
        ];
        for (name, two_d, radius, pre) in runs {
            let tries = 600_000;
            let at = rsa(two_d, radius, pre, tries);
            let most = at.len() as u64;
            for n in 1..=most {
                let reached = at[n as usize - 1] <= 1000 * n + 10_000;
                let gave_up = gives_up_at(&at, n, two_d);
                if reached {
                    assert_eq!(gave_up, None, "{name}: target {n} refused (of {most})");
                }
            }
            // Far beyond reach: given up within a few per cent of the limit.
            for (n, part) in [(most + most / 5, 2), (3 * most, 20), (100 * most, 100)] {
                let t = gives_up_at(&at, n, two_d).expect("gave up");
                assert!(
                    t < (1000 * n + 10_000) / part && t < tries,
                    "{name}: {n} given up at {t}"
                );
            }
        }
    }

    #[test]
    fn morton_order_visits_octants_in_turn() {
        // The 8 corners of a cube, listed backwards: the curve takes x first, then y, then z.
        let mut pos = Vec::new();
        for z in [0.0, 1.0] {
            for y in [0.0, 1.0] {
                for x in [0.0, 1.0] {
                    pos.push(Vec3::new(x, y, z));
                }
            }
        }
        pos.reverse();
        let order = morton_order(&pos, Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0));
        assert_eq!(order, vec![7, 6, 5, 4, 3, 2, 1, 0]);
        // Points of one small octant come before any of the next.
        let pos = vec![
            Vec3::new(0.6, 0.1, 0.1),
            Vec3::new(0.1, 0.1, 0.1),
            Vec3::new(0.4, 0.4, 0.4),
            Vec3::new(0.9, 0.9, 0.9),
        ];
        assert_eq!(
            morton_order(&pos, Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0)),
            vec![1, 2, 0, 3]
        );
        // Equal keys keep their order; a flat box does not divide by zero.
        let same = vec![Vec3::new(0.5, 0.5, 0.0); 3];
        assert_eq!(
            morton_order(&same, Vec3::zeros(), Vec3::new(1.0, 1.0, 0.0)),
            vec![0, 1, 2]
        );
    }
}
