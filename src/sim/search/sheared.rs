//! The contact search of a sheared cell (Lees–Edwards images, `sim::cell`).

use rayon::prelude::*;

use super::super::contacts::PairKey;
use super::super::scene::Scene;
use super::{GridInfo, by_cell, cell_index, floor_i64, grid_of, key_of, wrap};

/// Search of a sheared cell (Lees–Edwards offset `shift ≠ 0`, `sim::cell`): one cell per
/// particle, cells at least 2 R_max + TOL wide. Across the y sides the neighbours are the
/// images, whose columns are displaced by the offset (four columns instead of three, since
/// the offset is not a whole number of cells); the nearest image decides (`Scene::branch`).
/// Each pair is found once: by a half stencil where the neighbour cells are distinct, else
/// (a small grid, whose neighbour cells repeat) by the 27 cells around each particle, keeping
/// the partners of higher index, sorted and made unique.
pub(super) fn sheared_pairs(scene: &Scene, tol: f64) -> (Vec<PairKey>, GridInfo) {
    let p = &scene.particles;
    let np = p.len();
    let periodic = scene.settings.periodic;
    let (n, cell) = grid_of(scene, 2.0 * scene.max_radius() + tol, 2);
    let ncell = n[0] * n[1] * n[2];
    let coord = |i: usize, k: usize| -> usize {
        let c = cell_index(p.pos[i][k], k, &n, &cell, periodic[k]);
        if periodic[k] {
            wrap(c, n[k])
        } else {
            c as usize
        }
    };
    let flat = |c: [usize; 3]| c[0] + n[0] * (c[1] + n[1] * c[2]);
    let cell_of: Vec<u32> = (0..np)
        .map(|i| flat([coord(i, 0), coord(i, 1), coord(i, 2)]) as u32)
        .collect();
    let (start, members) = by_cell(&cell_of, ncell, 1);
    let grid = Sheared {
        scene,
        tol,
        n,
        periodic,
        // Whole cells the offset spans, for the images above (+) and below (−).
        s: floor_i64(scene.cell.shift / cell[0]),
        start: &start,
        members: &members,
    };
    // With at least four columns and three rows and layers the neighbour cells are distinct:
    // each pair is met once, by the half stencil within the cell and from the top row across
    // the sheared side (`half_stencil`). In a smaller grid the cells repeat: every particle
    // meets its 27 neighbour cells' particles, keeps those of higher index, sorted and made
    // unique.
    let distinct = n[0] >= 4 && n[1] >= 3 && (n[2] >= 3 || !periodic[2]);
    const CHUNK: usize = 512;
    let per_chunk: Vec<Vec<PairKey>> = (0..np.div_ceil(CHUNK))
        .into_par_iter()
        .map(|k| {
            let mut keys = Vec::new();
            let mut found: Vec<u32> = Vec::new();
            let mut cells: Vec<usize> = Vec::with_capacity(26);
            for a in k * CHUNK..((k + 1) * CHUNK).min(np) {
                let c = cell_of[a] as usize;
                if distinct {
                    grid.pairs_distinct(a, c, &mut cells, &mut keys);
                } else {
                    grid.pairs_repeating(a, c, &mut found, &mut keys);
                }
            }
            keys
        })
        .collect();
    let pairs: Vec<PairKey> = per_chunk.into_iter().flatten().collect();
    (pairs, GridInfo::of_cells(n, cell, &start))
}

/// The sheared cell's grid, as [`sheared_pairs`] walks it.
struct Sheared<'a> {
    scene: &'a Scene,
    tol: f64,
    n: [usize; 3],
    periodic: [bool; 3],
    /// Whole cells the Lees–Edwards offset spans.
    s: i64,
    start: &'a [u32],
    members: &'a [u32],
}

impl Sheared<'_> {
    fn flat(&self, c: [usize; 3]) -> usize {
        c[0] + self.n[0] * (c[1] + self.n[1] * c[2])
    }

    /// The cell at column `x` (wrapped), row `y`, layer `z` (wrapped if periodic, else
    /// `None` outside).
    fn cell_at(&self, x: i64, y: usize, z: i64) -> Option<usize> {
        let n = self.n;
        let z = if self.periodic[2] {
            wrap(z, n[2])
        } else if z < 0 || z >= n[2] as i64 {
            return None;
        } else {
            z as usize
        };
        Some(self.flat([wrap(x, n[0]), y, z]))
    }

    /// The particles of cell `f`.
    fn slots(&self, f: usize) -> &[u32] {
        &self.members[self.start[f] as usize..self.start[f + 1] as usize]
    }

    /// The column, row and layer of cell `c`.
    fn coords(&self, c: usize) -> (i64, i64, i64) {
        let n = self.n;
        (
            (c % n[0]) as i64,
            ((c / n[0]) % n[1]) as i64,
            (c / (n[0] * n[1])) as i64,
        )
    }

    /// The cells whose particles a distinct grid pairs a particle of cell (cx, cy, cz) with,
    /// besides the later ones of its own cell: its 13 forward neighbours that do not lie
    /// across the sheared side, and, from the top row, the bottom row's images (displaced by
    /// the offset: four columns, three layers).
    fn half_stencil(&self, (cx, cy, cz): (i64, i64, i64), cells: &mut Vec<usize>) {
        let n = self.n;
        cells.clear();
        for dz in -1..=1i64 {
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    let y = cy + dy;
                    if (dz, dy, dx) <= (0, 0, 0) || y < 0 || y >= n[1] as i64 {
                        continue;
                    }
                    if let Some(f) = self.cell_at(cx + dx, y as usize, cz + dz) {
                        cells.push(f);
                    }
                }
            }
        }
        if cy == n[1] as i64 - 1 {
            for dz in -1..=1i64 {
                for x in cx - self.s - 2..=cx - self.s + 1 {
                    if let Some(f) = self.cell_at(x, 0, cz + dz) {
                        cells.push(f);
                    }
                }
            }
        }
    }

    /// Particles `i` and `j` are within reach (nearest image).
    fn close(&self, i: usize, j: usize) -> bool {
        let p = &self.scene.particles;
        let d = self.scene.branch(&p.pos[i], &p.pos[j]);
        let reach = p.radius[i] + p.radius[j] + self.tol;
        d.norm_squared() < reach * reach
    }

    /// The pairs of particle `a` (in cell `c`) in a grid whose neighbour cells are distinct:
    /// the later particles of its cell and those of its half stencil.
    fn pairs_distinct(&self, a: usize, c: usize, cells: &mut Vec<usize>, keys: &mut Vec<PairKey>) {
        let p = &self.scene.particles;
        for &b in self.slots(c) {
            let b = b as usize;
            if b > a && self.close(a, b) {
                keys.push(key_of(p, a, b));
            }
        }
        self.half_stencil(self.coords(c), cells);
        for &f in cells.iter() {
            for &b in self.slots(f) {
                let b = b as usize;
                if self.close(a, b) {
                    keys.push(key_of(p, a, b));
                }
            }
        }
    }

    /// The pairs of particle `a` (in cell `c`) in a small grid whose neighbour cells repeat:
    /// the particles of higher index in its 27 neighbour cells (images across the sheared
    /// side), sorted and made unique.
    fn pairs_repeating(&self, a: usize, c: usize, found: &mut Vec<u32>, keys: &mut Vec<PairKey>) {
        let (n, s) = (self.n, self.s);
        let (cx, cy, cz) = self.coords(c);
        found.clear();
        for dz in -1..=1i64 {
            for dy in -1..=1i64 {
                let y = cy + dy;
                let cols = if y >= n[1] as i64 {
                    cx - s - 2..=cx - s + 1
                } else if y < 0 {
                    cx + s - 1..=cx + s + 2
                } else {
                    cx - 1..=cx + 1
                };
                for x in cols {
                    let Some(f) = self.cell_at(x, wrap(y, n[1]), cz + dz) else {
                        continue;
                    };
                    found.extend(self.slots(f).iter().filter(|&&b| b as usize > a));
                }
            }
        }
        found.sort_unstable();
        found.dedup();
        for &b in found.iter() {
            if self.close(a, b as usize) {
                keys.push(key_of(&self.scene.particles, a, b as usize));
            }
        }
    }
}
