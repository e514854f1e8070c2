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
    // Whole cells the offset spans, for the images above (+) and below (−).
    let s = floor_i64(scene.cell.shift / cell[0]);
    // With at least four columns and three rows and layers the neighbour cells are distinct:
    // each pair is met once, by the half stencil within the cell and from the top row across
    // the sheared side (`half_stencil`). In a smaller grid the cells repeat: every particle
    // meets its 27 neighbour cells' particles, keeps those of higher index, sorted and made
    // unique.
    let distinct = n[0] >= 4 && n[1] >= 3 && (n[2] >= 3 || !periodic[2]);
    let cell_at = |x: i64, y: usize, z: i64| -> Option<usize> {
        let z = if periodic[2] {
            wrap(z, n[2])
        } else if z < 0 || z >= n[2] as i64 {
            return None;
        } else {
            z as usize
        };
        Some(flat([wrap(x, n[0]), y, z]))
    };
    let slots = |f: usize| &members[start[f] as usize..start[f + 1] as usize];
    // The cells whose particles a distinct grid pairs a particle of cell (cx, cy, cz) with,
    // besides the later ones of its own cell: its 13 forward neighbours that do not lie
    // across the sheared side, and, from the top row, the bottom row's images (displaced by
    // the offset: four columns, three layers).
    let half_stencil = |[cx, cy, cz]: [i64; 3], cells: &mut Vec<usize>| {
        cells.clear();
        for dz in -1..=1i64 {
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    let y = cy + dy;
                    if (dz, dy, dx) <= (0, 0, 0) || y < 0 || y >= n[1] as i64 {
                        continue;
                    }
                    if let Some(f) = cell_at(cx + dx, y as usize, cz + dz) {
                        cells.push(f);
                    }
                }
            }
        }
        if cy == n[1] as i64 - 1 {
            for dz in -1..=1i64 {
                for x in cx - s - 2..=cx - s + 1 {
                    if let Some(f) = cell_at(x, 0, cz + dz) {
                        cells.push(f);
                    }
                }
            }
        }
    };
    let close = |i: usize, j: usize| {
        let d = scene.branch(&p.pos[i], &p.pos[j]);
        let reach = p.radius[i] + p.radius[j] + tol;
        d.norm_squared() < reach * reach
    };
    const CHUNK: usize = 512;
    let per_chunk: Vec<Vec<PairKey>> = (0..np.div_ceil(CHUNK))
        .into_par_iter()
        .map(|k| {
            let mut keys = Vec::new();
            let mut found: Vec<u32> = Vec::new();
            let mut cells: Vec<usize> = Vec::with_capacity(26);
            for a in k * CHUNK..((k + 1) * CHUNK).min(np) {
                let c = cell_of[a] as usize;
                let (cx, cy, cz) = (
                    (c % n[0]) as i64,
                    ((c / n[0]) % n[1]) as i64,
                    (c / (n[0] * n[1])) as i64,
                );
                if distinct {
                    for &b in slots(c) {
                        let b = b as usize;
                        if b > a && close(a, b) {
                            keys.push(key_of(p, a, b));
                        }
                    }
                    half_stencil([cx, cy, cz], &mut cells);
                    for &f in &cells {
                        for &b in slots(f) {
                            let b = b as usize;
                            if close(a, b) {
                                keys.push(key_of(p, a, b));
                            }
                        }
                    }
                    continue;
                }
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
                            let Some(f) = cell_at(x, wrap(y, n[1]), cz + dz) else {
                                continue;
                            };
                            found.extend(slots(f).iter().filter(|&&b| b as usize > a));
                        }
                    }
                }
                found.sort_unstable();
                found.dedup();
                for &b in &found {
                    if close(a, b as usize) {
                        keys.push(key_of(p, a, b as usize));
                    }
                }
            }
            keys
        })
        .collect();
    let pairs: Vec<PairKey> = per_chunk.into_iter().flatten().collect();
    (pairs, GridInfo::of_cells(n, cell, &start))
}
