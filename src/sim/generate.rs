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
