//! Contact search by box-mapped link lists (Lian §5.5, doc/spec/physics-lian1994.md §5), modern form.
//!
//! Two ways to fill the boxes, both giving exactly the pairs with gap < TOL (the merge sorts
//! them, so the choice never changes a result):
//! - near-monodisperse scenes (R_max ≤ 1.5 × median): one box per particle, boxes at least
//!   2 R_max + TOL wide, each box compared with itself and its 13 forward neighbours
//!   (without periodic axes these are five runs of consecutive boxes, so each particle is
//!   tested against five contiguous runs of slot-ordered x, y, z, R arrays, without a branch
//!   per test);
//! - otherwise TRUBAL's: each particle is entered into every box touched by its cube of side
//!   2(R + TOL/2), so a polydisperse assembly stays linear (big particles have many entries,
//!   small boxes stay small); a pair found in several boxes is reported only by the box
//!   holding the lower corner of the intersection of their cubes.
//!
//! The candidate list is rebuilt only when some particle has moved more than XRES
//! (< TOL/(2√3)) in any component since the last rebuild, so no pair can come into contact
//! unseen between rebuilds.

use rayon::prelude::*;

mod sheared;
use sheared::sheared_pairs;

use super::contacts::{KeyParts, PairKey, WallKey};
use super::scene::{Scene, Vec3};
use super::walls::WallShape;

/// The grid of the last rebuild (for `PRint Entries`/`Map`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridInfo {
    pub n: [usize; 3],
    pub cell: [f64; 3],
    pub entries: usize,
    pub max_entries_per_box: usize,
    pub empty_boxes: usize,
}

impl GridInfo {
    /// The grid of a one-cell-per-particle search, from its cells' slot starts.
    fn of_cells(n: [usize; 3], cell: [f64; 3], start: &[u32]) -> GridInfo {
        let counts = start.windows(2).map(|w| w[1] - w[0]);
        GridInfo {
            n,
            cell,
            entries: start.last().copied().unwrap_or(0) as usize,
            max_entries_per_box: counts.clone().max().unwrap_or(0) as usize,
            empty_boxes: counts.filter(|&m| m == 0).count(),
        }
    }
}

/// Chooses the box size: twice the median radius plus TOL (boxes need not exceed the largest
/// diameter: large particles simply get more entries), limited so the grid has at most about
/// 4 boxes per particle.
fn grid_dims(scene: &Scene, tol: f64) -> ([usize; 3], [f64; 3]) {
    let median = median_radius(scene).unwrap_or(1.0);
    grid_of(scene, 2.0 * median + tol, 4)
}

/// The median particle radius, of every radius up to 1024 particles and of an evenly spaced
/// sample of about 1024 beyond (None without particles). It chooses only the grid of the
/// search, never which pairs it finds.
fn median_radius(scene: &Scene) -> Option<f64> {
    let all = &scene.particles.radius;
    let mut r: Vec<f64> = all
        .iter()
        .step_by(all.len().div_ceil(1024).max(1))
        .copied()
        .collect();
    if r.is_empty() {
        return None;
    }
    let k = r.len() / 2;
    r.select_nth_unstable_by(k, f64::total_cmp);
    Some(r[k])
}

/// Boxes of side at least `h` filling the work-space, enlarged so that there are at most about
/// `per_particle` boxes per particle (a dilute gas gets bigger boxes).
fn grid_of(scene: &Scene, mut h: f64, per_particle: usize) -> ([usize; 3], [f64; 3]) {
    let max_cells = (per_particle * scene.particles.len()).max(27) as f64;
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

/// `q.floor() as i64`, without the call to the C library's `floor` that the baseline
/// x86-64 build makes (no rounding instruction before SSE4.1): the truncation, one less
/// for a negative non-integer; the same value for every input, NaN and ±∞ included.
#[inline]
fn floor_i64(q: f64) -> i64 {
    let t = q as i64;
    t.saturating_sub(i64::from((t as f64) > q))
}

#[inline]
fn cell_index(x: f64, k: usize, n: &[usize; 3], cell: &[f64; 3], periodic: bool) -> i64 {
    let c = floor_i64(x / cell[k]);
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

/// The key of the pair of particles `i` and `j`, the lower id first.
#[inline]
fn key_of(p: &super::scene::Particles, i: usize, j: usize) -> PairKey {
    let (ida, idb) = (p.id[i], p.id[j]);
    let (i, j, ida, idb) = if ida < idb {
        (i, j, ida, idb)
    } else {
        (j, i, idb, ida)
    };
    PairKey {
        i: i as u32,
        j: j as u32,
        ida,
        idb,
    }
}

/// Finds all candidate pairs (gap < tol) and particle–wall candidates.
pub fn candidates(scene: &Scene, tol: f64) -> (Vec<PairKey>, Vec<WallKey>, GridInfo) {
    let (pairs, walls, info) = candidates_in_parts(scene, tol, 1);
    let pairs = pairs.into_flat();
    (pairs, walls, info)
}

/// [`candidates`], the pairs parted by their lower id into `parts` ranges (one per thread,
/// to be sorted in parallel: [`KeyParts`]).
pub fn candidates_in_parts(
    scene: &Scene,
    tol: f64,
    parts: usize,
) -> (KeyParts, Vec<WallKey>, GridInfo) {
    // The wall candidates beside the particle pairs (nothing shared).
    let ((pairs, info), walls) = rayon::join(
        || match single_cell_grid(scene, tol) {
            _ if scene.cell.shift != 0.0 => {
                let (pairs, info) = sheared_pairs(scene, tol);
                (KeyParts::split(pairs, parts), info)
            }
            Some((n, cell)) => {
                let max_id = scene.particles.id.iter().copied().max().unwrap_or(0);
                single_cell_pairs(scene, tol, n, cell, &KeyParts::bounds(max_id, parts))
            }
            None => {
                let (pairs, info) = multi_entry_pairs(scene, tol);
                (KeyParts::split(pairs, parts), info)
            }
        },
        || wall_candidates(scene, tol),
    );
    (pairs, walls, info)
}

/// Grid of the single-cell search, if it suits the scene: near-monodisperse (largest radius
/// at most 1.5 × the median), cells no smaller than the largest reach 2 R_max + TOL, and at
/// least 3 cells along every periodic axis (so that the 27 neighbours of a cell are distinct).
fn single_cell_grid(scene: &Scene, tol: f64) -> Option<([usize; 3], [f64; 3])> {
    let median = median_radius(scene)?;
    let rmax = scene.max_radius();
    // (Written so that a NaN radius or TOL chooses the general search.)
    let suits = rmax <= 1.5 * median && tol >= 0.0;
    if !suits {
        return None;
    }
    let (n, cell) = grid_of(scene, 2.0 * rmax + tol, 2);
    if (0..3).any(|k| scene.settings.periodic[k] && n[k] < 3) {
        return None;
    }
    Some((n, cell))
}

/// Single-cell search: each particle is entered in the one cell of its centre (a counting
/// sort), and each cell is compared with itself and its 13 forward neighbours (half stencil),
/// so every pair is examined once. Cells are at least 2 R_max + TOL wide, so every pair with
/// gap < TOL is in the same or adjacent cells (positions outside an open side are clamped to
/// the edge cells, which only brings particles closer in cell index).
fn single_cell_pairs(
    scene: &Scene,
    tol: f64,
    n: [usize; 3],
    cell: [f64; 3],
    bounds: &[u32],
) -> (KeyParts, GridInfo) {
    let p = &scene.particles;
    let np = p.len();
    let periodic = scene.settings.periodic;
    let ncell = n[0] * n[1] * n[2];
    let coord = |i: usize| -> [usize; 3] {
        let mut c = [0usize; 3];
        for k in 0..3 {
            let x = cell_index(p.pos[i][k], k, &n, &cell, periodic[k]);
            c[k] = if periodic[k] {
                wrap(x, n[k])
            } else {
                x as usize
            };
        }
        c
    };
    let flat = |c: [usize; 3]| c[0] + n[0] * (c[1] + n[1] * c[2]);
    // Counting sort of the particles by cell (particles of a cell in index order).
    let cell_of: Vec<u32> = (0..np)
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| flat(coord(i)) as u32)
        .collect();
    let (start, members) = by_cell(&cell_of, ncell, bounds.len() - 1);
    let (stencil, offsets) = forward_stencil(n);
    // Without periodic axes, the 13 forward neighbours of a cell are five runs of consecutive
    // slots (the cell after it in its row; three cells of the next row; three rows of three
    // in the next layer), so each particle is tested against five contiguous runs of the
    // slot-ordered coordinates below, without a branch per test.
    let runs_ok = !periodic.iter().any(|&q| q);
    let slot_xyzr: Option<[Vec<f64>; 4]> = runs_ok.then(|| {
        let of = |k: usize| -> Vec<f64> {
            members
                .par_iter()
                .with_min_len(4096)
                .map(|&i| {
                    if k < 3 {
                        p.pos[i as usize][k]
                    } else {
                        p.radius[i as usize]
                    }
                })
                .collect()
        };
        [of(0), of(1), of(2), of(3)]
    });
    let cells = Cells {
        scene,
        tol,
        n,
        start: &start,
        members: &members,
        stencil,
        offsets,
    };
    const BLOCK: usize = 256;
    let nparts = bounds.len() - 1;
    // Each block's keys go to the part of their lower id.
    let per_block: Vec<Vec<Vec<PairKey>>> = (0..ncell.div_ceil(BLOCK))
        .into_par_iter()
        .with_max_len(1)
        .map(|blk| {
            let mut parted = vec![Vec::new(); nparts];
            let mut pairs = Parted(&mut parted, bounds);
            let mut hits: Vec<u32> = Vec::new();
            for c in blk * BLOCK..((blk + 1) * BLOCK).min(ncell) {
                if cells.slots_of(c).is_empty() {
                    continue;
                }
                match &slot_xyzr {
                    Some(xyzr) => cells.by_runs(c, xyzr, &mut hits, &mut pairs),
                    None => cells.by_stencil(c, &mut pairs),
                }
            }
            parted
        })
        .collect();
    // Each part's keys: its lists of all blocks, in block order (moved, not copied).
    let mut parts: Vec<Vec<Vec<PairKey>>> = vec![Vec::new(); nparts];
    for block in per_block {
        for (t, keys) in block.into_iter().enumerate() {
            if !keys.is_empty() {
                parts[t].push(keys);
            }
        }
    }
    let pairs = KeyParts {
        bounds: bounds.to_vec(),
        parts,
    };
    (pairs, GridInfo::of_cells(n, cell, &start))
}

/// The 13 forward neighbours of a cell, and the same as offsets of the flat cell index (for
/// cells whose 13 neighbours all exist without wrapping).
fn forward_stencil(n: [usize; 3]) -> (Vec<[i64; 3]>, Vec<isize>) {
    let mut stencil = Vec::with_capacity(13);
    for dz in -1i64..=1 {
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if (dz, dy, dx) > (0, 0, 0) {
                    stencil.push([dx, dy, dz]);
                }
            }
        }
    }
    let offsets: Vec<isize> = stencil
        .iter()
        .map(|d| (d[0] + n[0] as i64 * (d[1] + n[1] as i64 * d[2])) as isize)
        .collect();
    (stencil, offsets)
}

/// The sorted cells of the single-cell search.
struct Cells<'a> {
    scene: &'a Scene,
    tol: f64,
    n: [usize; 3],
    /// `start[c]..start[c + 1]`: cell c's slots in `members` (particle indices).
    start: &'a [u32],
    members: &'a [u32],
    stencil: Vec<[i64; 3]>,
    offsets: Vec<isize>,
}

impl Cells<'_> {
    #[inline]
    fn slots_of(&self, c: usize) -> std::ops::Range<usize> {
        self.start[c] as usize..self.start[c + 1] as usize
    }

    #[inline]
    fn key(&self, sa: usize, sb: usize) -> PairKey {
        key_of(
            &self.scene.particles,
            self.members[sa] as usize,
            self.members[sb] as usize,
        )
    }

    /// Whether the particles in cell slots sa and sb are candidates (gap below TOL).
    #[inline]
    fn close_slots(&self, sa: usize, sb: usize) -> bool {
        let p = &self.scene.particles;
        let (i, j) = (self.members[sa] as usize, self.members[sb] as usize);
        let d = self.scene.branch(&p.pos[i], &p.pos[j]);
        let reach = p.radius[i] + p.radius[j] + self.tol;
        d.norm_squared() < reach * reach
    }

    /// Cell c's pairs without periodic axes: its later slots and the five runs of slots of
    /// its forward neighbours (clipped at the sides), tested on the slot-ordered x, y, z, R.
    fn by_runs(&self, c: usize, xyzr: &[Vec<f64>; 4], hits: &mut Vec<u32>, pairs: &mut Parted) {
        let (n, start) = (self.n, self.start);
        let [sx, sy, sz, sr] = xyzr;
        let here = self.slots_of(c);
        let cz = c / (n[0] * n[1]);
        let cy = (c / n[0]) % n[1];
        let cx = c % n[0];
        let (x0, x1) = (cx.saturating_sub(1), (cx + 1).min(n[0] - 1));
        let row = |y: usize, z: usize| {
            let f = x0 + n[0] * (y + n[1] * z);
            start[f] as usize..start[f + x1 - x0 + 1] as usize
        };
        let mut runs = [0..0, 0..0, 0..0, 0..0, 0..0];
        runs[0] = here.end..start[c + 1 + usize::from(cx + 1 < n[0])] as usize;
        if cy + 1 < n[1] {
            runs[1] = row(cy + 1, cz);
        }
        if cz + 1 < n[2] {
            for (r, dy) in [(2, -1i64), (3, 0), (4, 1)] {
                let y = cy as i64 + dy;
                if y >= 0 && y < n[1] as i64 {
                    runs[r] = row(y as usize, cz + 1);
                }
            }
        }
        let most = here.len() + runs.iter().map(|r| r.len()).sum::<usize>();
        if hits.len() < most {
            hits.resize(most, 0);
        }
        let tol = self.tol;
        for sa in here.clone() {
            let (xa, ya, za, ra) = (sx[sa], sy[sa], sz[sa], sr[sa]);
            let mut nh = 0;
            // Same cell (later slots), then the runs; the test is that of `close_slots`
            // (d = x_b − x_a, |d|² as (dx² + dy²) + dz², reach (R_a + R_b) + TOL, summed in
            // that order).
            for run in std::iter::once(sa + 1..here.end).chain(runs.iter().cloned()) {
                for sb in run {
                    let (dx, dy, dz) = (sx[sb] - xa, sy[sb] - ya, sz[sb] - za);
                    let reach = ra + sr[sb] + tol;
                    hits[nh] = sb as u32;
                    nh += usize::from(dx * dx + dy * dy + dz * dz < reach * reach);
                }
            }
            for &sb in &hits[..nh] {
                pairs.push(self.key(sa, sb as usize));
            }
        }
    }

    /// Cell c's pairs with periodic axes: its later slots, then its 13 forward neighbours
    /// (by flat offsets for an interior cell, wrapped or clipped at the sides otherwise).
    fn by_stencil(&self, c: usize, pairs: &mut Parted) {
        let (n, periodic) = (self.n, self.scene.settings.periodic);
        let here = self.slots_of(c);
        let cz = c / (n[0] * n[1]);
        let cy = (c / n[0]) % n[1];
        let cx = c % n[0];
        for sa in here.clone() {
            for sb in sa + 1..here.end {
                if self.close_slots(sa, sb) {
                    pairs.push(self.key(sa, sb));
                }
            }
        }
        let with = |pairs: &mut Parted, there: std::ops::Range<usize>| {
            for sa in here.clone() {
                for sb in there.clone() {
                    if self.close_slots(sa, sb) {
                        pairs.push(self.key(sa, sb));
                    }
                }
            }
        };
        let interior = cx >= 1 && cx + 2 <= n[0] && cy >= 1 && cy + 2 <= n[1] && cz + 2 <= n[2];
        if interior {
            // All 13 neighbours exist without wrapping: flat offsets, same order.
            for &off in &self.offsets {
                with(pairs, self.slots_of(c.wrapping_add_signed(off)));
            }
            return;
        }
        for d in &self.stencil {
            let mut o = [0usize; 3];
            let mut inside = true;
            for (k, (&ck, &dk)) in [cx, cy, cz].iter().zip(d).enumerate() {
                let q = ck as i64 + dk;
                if periodic[k] {
                    o[k] = wrap(q, n[k]);
                } else if q < 0 || q >= n[k] as i64 {
                    inside = false;
                } else {
                    o[k] = q as usize;
                }
            }
            if inside {
                with(pairs, self.slots_of(o[0] + n[0] * (o[1] + n[1] * o[2])));
            }
        }
    }
}

/// Counting sort of the particles by cell: `start[c]..start[c + 1]` are cell `c`'s slots in
/// `members`, which lists each cell's particles in index order. Done in `parts` ranges of
/// cells in parallel (each part reads every particle's cell and counts and places only
/// those of its own cells), with the result of one serial pass.
fn by_cell(cell_of: &[u32], ncell: usize, parts: usize) -> (Vec<u32>, Vec<u32>) {
    let parts = parts.clamp(1, ncell.max(1));
    let cut: Vec<usize> = (0..=parts).map(|t| t * ncell / parts).collect();
    let ours = |c0: usize, c1: usize| {
        cell_of
            .iter()
            .enumerate()
            .filter(move |(_, c)| (c0..c1).contains(&(**c as usize)))
            .map(move |(i, &c)| (i as u32, c as usize - c0))
    };
    // Per part: the running sums of its cells' counts (start[c + 1] for its cells c).
    let mut start = vec![0u32; ncell + 1];
    let mut counts: Vec<&mut [u32]> = Vec::with_capacity(parts);
    let mut rest = &mut start[1..];
    for t in 0..parts {
        let (a, b) = rest.split_at_mut(cut[t + 1] - cut[t]);
        counts.push(a);
        rest = b;
    }
    counts.par_iter_mut().enumerate().for_each(|(t, n)| {
        for (_, c) in ours(cut[t], cut[t + 1]) {
            n[c] += 1;
        }
        let mut sum = 0;
        for x in n.iter_mut() {
            sum += *x;
            *x = sum;
        }
    });
    // Then each part's particles into its own stretch of `members`, and the slots before
    // it added to its sums.
    let sizes: Vec<u32> = counts
        .iter()
        .map(|n| n.last().copied().unwrap_or(0))
        .collect();
    let mut members = vec![0u32; cell_of.len()];
    let mut slots: Vec<(&mut [u32], u32)> = Vec::with_capacity(parts);
    let (mut rest, mut before) = (&mut members[..], 0);
    for &size in &sizes {
        let (a, b) = rest.split_at_mut(size as usize);
        slots.push((a, before));
        rest = b;
        before += size;
    }
    counts
        .into_par_iter()
        .zip(slots)
        .enumerate()
        .for_each(|(t, (n, (slots, before)))| {
            let mut fill: Vec<u32> = std::iter::once(0).chain(n.iter().copied()).collect();
            for (i, c) in ours(cut[t], cut[t + 1]) {
                slots[fill[c] as usize] = i;
                fill[c] += 1;
            }
            for x in n.iter_mut() {
                *x += before;
            }
        });
    (start, members)
}

/// The keys of one search block, each pushed to the part of its lower id.
struct Parted<'a>(&'a mut Vec<Vec<PairKey>>, &'a [u32]);

impl Parted<'_> {
    #[inline]
    fn push(&mut self, k: PairKey) {
        let t = KeyParts::part_of(self.1, k.ida);
        self.0[t].push(k);
    }
}

/// The boxes of the multi-entry search as link lists: `head[box]` → entry, `next[entry]` →
/// entry, `owner[entry]` = particle; and each particle's cube as its lowest and highest box.
struct LinkLists {
    head: Vec<u32>,
    next: Vec<u32>,
    owner: Vec<u32>,
    lo_cell: Vec<[i64; 3]>,
    hi_cell: Vec<[i64; 3]>,
}

/// Enters each particle in every box its cube of side 2(R + half) touches.
fn enter_cubes(scene: &Scene, n: [usize; 3], cell: [f64; 3], half: f64) -> LinkLists {
    let p = &scene.particles;
    let np = p.len();
    let ncell = n[0] * n[1] * n[2];
    let periodic = scene.settings.periodic;
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
            // (Saturating: with a reach of the order of i64::MAX cells, `hi − lo` would wrap
            // and the cube would seem to span nothing.)
            if periodic[k] && hi[k].saturating_sub(lo[k]) >= n[k] as i64 {
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
    LinkLists {
        head,
        next,
        owner,
        lo_cell,
        hi_cell,
    }
}

/// Multi-entry search (TRUBAL's): each particle is entered in every box its cube of side
/// 2(R + TOL/2) touches, so that a wide size distribution stays linear.
fn multi_entry_pairs(scene: &Scene, tol: f64) -> (Vec<PairKey>, GridInfo) {
    let p = &scene.particles;
    let (n, cell) = grid_dims(scene, tol);
    let periodic = scene.settings.periodic;
    let half = 0.5 * tol;

    let LinkLists {
        head,
        next,
        owner,
        lo_cell,
        hi_cell,
    } = enter_cubes(scene, n, cell, half);

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
                        pairs.push(key_of(p, i, j));
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
    (pairs, info)
}

/// Particle–wall candidates (gap < tol), in parallel over fixed blocks of particles, in
/// particle order.
fn wall_candidates(scene: &Scene, tol: f64) -> Vec<WallKey> {
    let p = &scene.particles;
    let np = p.len();
    if scene.walls.is_empty() {
        Vec::new()
    } else {
        let shapes: Vec<WallShape> = scene.walls.iter().map(|w| WallShape::of(&w.geom)).collect();
        let shapes = &shapes;
        (0..np)
            .into_par_iter()
            .with_min_len(1024)
            .flat_map_iter(|i| {
                shapes
                    .iter()
                    .enumerate()
                    .filter(move |(_, shape)| shape.gap(&p.pos[i], p.radius[i]).0 < tol)
                    .map(move |(w, _)| WallKey {
                        i: i as u32,
                        id: p.id[i],
                        wall: w as u32,
                    })
            })
            .collect()
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::rng::Rng;

    #[test]
    fn floor_without_the_library_call_is_floor() {
        let mut r = Rng::new(3);
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.5,
            -1.5,
            2.0 - 1e-16,
            -2.0 + 1e-16,
            4503599627370495.5,
            -4503599627370495.5,
            9007199254740993.0,
            1e300,
            -1e300,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            9.3e18,
            -9.3e18,
        ];
        xs.extend((0..10_000).map(|_| r.normal() * 1e3));
        for x in xs {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        }
    }

    /// The serial counting sort the parted one stands for.
    fn by_cell_serial(cell_of: &[u32], ncell: usize) -> (Vec<u32>, Vec<u32>) {
        let mut start = vec![0u32; ncell + 1];
        for &c in cell_of {
            start[c as usize + 1] += 1;
        }
        for c in 0..ncell {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut members = vec![0u32; cell_of.len()];
        for (i, &c) in cell_of.iter().enumerate() {
            members[fill[c as usize] as usize] = i as u32;
            fill[c as usize] += 1;
        }
        (start, members)
    }

    #[test]
    fn particles_sorted_by_cell_in_parts_as_in_one_pass() {
        let mut r = Rng::new(11);
        for (np, ncell) in [
            (0, 1),
            (1, 1),
            (5, 2),
            (1000, 37),
            (1000, 5000),
            (20_000, 3000),
        ] {
            // Runs of one cell and scattered cells, many cells empty.
            let cell_of: Vec<u32> = (0..np)
                .map(|i| {
                    if i % 3 == 0 {
                        (i * ncell / np.max(1)) as u32
                    } else {
                        ((r.uniform() * ncell as f64) as usize).min(ncell - 1) as u32
                    }
                })
                .collect();
            let want = by_cell_serial(&cell_of, ncell);
            for parts in [1, 2, 3, 7, 64] {
                assert_eq!(
                    by_cell(&cell_of, ncell, parts),
                    want,
                    "{np} in {ncell}, {parts}"
                );
            }
        }
    }
}
