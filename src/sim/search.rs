//! Contact search by box-mapped link lists (Lian §5.5, physics-lian1994 §5), modern form.
//!
//! The work-space is divided into a uniform grid of boxes. Each particle is entered (head/next
//! link arrays) into every box touched by its cube of side 2(R + TOL/2), as in TRUBAL, so a
//! polydisperse assembly stays linear: big particles have many entries, small boxes stay
//! small. Two particles are candidates when their gap is below TOL; a pair found in several
//! boxes is reported only by the box holding the lower corner of the intersection of their
//! cubes. The candidate list is rebuilt only when some particle has moved more than XRES
//! (< TOL/(2√3)) in any component since the last rebuild, so no pair can come into contact
//! unseen between rebuilds.

use rayon::prelude::*;

use super::contacts::{PairKey, WallKey};
use super::scene::{Scene, Vec3};
use super::walls::wall_gap;

/// The grid of the last rebuild (for `PRint Entries`/`Map`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridInfo {
    pub n: [usize; 3],
    pub cell: [f64; 3],
    pub entries: usize,
    pub max_entries_per_box: usize,
    pub empty_boxes: usize,
}

/// Chooses the box size: twice the median radius plus TOL (boxes need not exceed the largest
/// diameter: large particles simply get more entries), limited so the grid has at most about
/// 4 boxes per particle.
fn grid_dims(scene: &Scene, tol: f64) -> ([usize; 3], [f64; 3]) {
    let p = &scene.particles;
    let mut r: Vec<f64> = p.radius.clone();
    let median = if r.is_empty() {
        1.0
    } else {
        let k = r.len() / 2;
        r.select_nth_unstable_by(k, f64::total_cmp);
        r[k]
    };
    let mut h = 2.0 * median + tol;
    let max_cells = (4 * p.len()).max(27) as f64;
    let vol = scene.size[0] * scene.size[1] * scene.size[2];
    if vol / (h * h * h) > max_cells {
        h = (vol / max_cells).cbrt();
    }
    let mut n = [1usize; 3];
    let mut cell = [0.0; 3];
    for k in 0..3 {
        n[k] = ((scene.size[k] / h).floor() as usize).clamp(1, 1 << 20);
        cell[k] = scene.size[k] / n[k] as f64;
    }
    (n, cell)
}

#[inline]
fn cell_index(x: f64, k: usize, n: &[usize; 3], cell: &[f64; 3], periodic: bool) -> i64 {
    let c = (x / cell[k]).floor() as i64;
    if periodic {
        c
    } else {
        c.clamp(0, n[k] as i64 - 1)
    }
}

#[inline]
fn wrap(c: i64, n: usize) -> usize {
    c.rem_euclid(n as i64) as usize
}

/// Finds all candidate pairs (gap < tol) and particle–wall candidates.
pub fn candidates(scene: &Scene, tol: f64) -> (Vec<PairKey>, Vec<WallKey>, GridInfo) {
    let p = &scene.particles;
    let np = p.len();
    let (n, cell) = grid_dims(scene, tol);
    let ncell = n[0] * n[1] * n[2];
    let periodic = scene.settings.periodic;
    let half = 0.5 * tol;

    // Link lists: head[box] -> entry, next[entry] -> entry, owner[entry] = particle.
    let mut head = vec![u32::MAX; ncell];
    let mut next: Vec<u32> = Vec::with_capacity(np * 2);
    let mut owner: Vec<u32> = Vec::with_capacity(np * 2);
    let mut lo_cell = vec![[0i64; 3]; np];
    let mut hi_cell = vec![[0i64; 3]; np];
    for i in 0..np {
        let ext = p.radius[i] + half;
        let mut lo = [0i64; 3];
        let mut hi = [0i64; 3];
        for k in 0..3 {
            lo[k] = cell_index(p.pos[i][k] - ext, k, &n, &cell, periodic[k]);
            hi[k] = cell_index(p.pos[i][k] + ext, k, &n, &cell, periodic[k]);
            if periodic[k] && hi[k] - lo[k] >= n[k] as i64 {
                // The cube spans the whole period: enter each box once.
                lo[k] = 0;
                hi[k] = n[k] as i64 - 1;
            }
        }
        lo_cell[i] = lo;
        hi_cell[i] = hi;
        for cz in lo[2]..=hi[2] {
            for cy in lo[1]..=hi[1] {
                for cx in lo[0]..=hi[0] {
                    let b = wrap(cx, n[0]) + n[0] * (wrap(cy, n[1]) + n[1] * wrap(cz, n[2]));
                    owner.push(i as u32);
                    next.push(head[b]);
                    head[b] = (owner.len() - 1) as u32;
                }
            }
        }
    }

    // A pair found in several boxes is reported only by the box of the lower corner of the
    // intersection of the two cubes (computed in i's frame, then wrapped).
    let reports = |i: usize, j: usize, d: &Vec3, bxyz: [usize; 3]| -> bool {
        (0..3).all(|k| {
            let lo_i = p.pos[i][k] - p.radius[i] - half;
            let lo_j = p.pos[i][k] + d[k] - p.radius[j] - half;
            let c = cell_index(lo_i.max(lo_j), k, &n, &cell, periodic[k]);
            let c = if periodic[k] {
                wrap(c, n[k])
            } else {
                c as usize
            };
            // A cube spanning the whole period was entered from box 0 upward.
            let spans =
                |q: usize| periodic[k] && lo_cell[q][k] == 0 && hi_cell[q][k] == n[k] as i64 - 1;
            let c = if spans(i) && spans(j) { 0 } else { c };
            c == bxyz[k]
        })
    };
    // Pairs per block of boxes, in parallel; blocks are concatenated in box order (and the
    // merge sorts the keys anyway), so the result does not depend on the number of threads.
    const BLOCK: usize = 256;
    let per_block: Vec<(Vec<PairKey>, usize, usize)> = head
        .par_chunks(BLOCK)
        .with_max_len(1)
        .enumerate()
        .map(|(blk, heads)| {
            let mut pairs = Vec::new();
            let mut members: Vec<u32> = Vec::new();
            let (mut max_entries, mut empty) = (0usize, 0usize);
            for (off, &h0) in heads.iter().enumerate() {
                let b = blk * BLOCK + off;
                members.clear();
                let mut e = h0;
                while e != u32::MAX {
                    members.push(owner[e as usize]);
                    e = next[e as usize];
                }
                max_entries = max_entries.max(members.len());
                if members.is_empty() {
                    empty += 1;
                    continue;
                }
                let bz = b / (n[0] * n[1]);
                let by = (b / n[0]) % n[1];
                let bx = b % n[0];
                for x in 0..members.len() {
                    let i = members[x] as usize;
                    for &jj in &members[x + 1..] {
                        let j = jj as usize;
                        let d = scene.branch(&p.pos[i], &p.pos[j]);
                        let reach = p.radius[i] + p.radius[j] + tol;
                        if d.norm_squared() >= reach * reach {
                            continue;
                        }
                        if !reports(i, j, &d, [bx, by, bz]) {
                            continue;
                        }
                        let (ida, idb) = (p.id[i], p.id[j]);
                        let (i, j, ida, idb) = if ida < idb {
                            (i, j, ida, idb)
                        } else {
                            (j, i, idb, ida)
                        };
                        pairs.push(PairKey {
                            i: i as u32,
                            j: j as u32,
                            ida,
                            idb,
                        });
                    }
                }
            }
            (pairs, max_entries, empty)
        })
        .collect();
    let mut info = GridInfo {
        n,
        cell,
        entries: owner.len(),
        ..Default::default()
    };
    let mut pairs = Vec::with_capacity(per_block.iter().map(|b| b.0.len()).sum());
    for (v, max_entries, empty) in per_block {
        pairs.extend(v);
        info.max_entries_per_box = info.max_entries_per_box.max(max_entries);
        info.empty_boxes += empty;
    }

    // Particle–wall candidates in parallel over fixed blocks of particles, in particle order.
    let walls: Vec<WallKey> = if scene.walls.is_empty() {
        Vec::new()
    } else {
        (0..np)
            .into_par_iter()
            .with_min_len(1024)
            .flat_map_iter(|i| {
                scene
                    .walls
                    .iter()
                    .enumerate()
                    .filter(move |(_, wall)| wall_gap(&wall.geom, &p.pos[i], p.radius[i]).0 < tol)
                    .map(move |(w, _)| WallKey {
                        i: i as u32,
                        id: p.id[i],
                        wall: w as u32,
                    })
            })
            .collect()
    };
    (pairs, walls, info)
}

/// Brute-force O(N²) reference used by the tests.
pub fn brute_force_pairs(scene: &Scene, tol: f64) -> Vec<(u32, u32)> {
    let p = &scene.particles;
    let mut v = Vec::new();
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let d: Vec3 = scene.branch(&p.pos[i], &p.pos[j]);
            if d.norm() < p.radius[i] + p.radius[j] + tol {
                let (a, b) = (p.id[i].min(p.id[j]), p.id[i].max(p.id[j]));
                v.push((a, b));
            }
        }
    }
    v.sort_unstable();
    v
}
