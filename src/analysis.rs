//! Agglomerate measures (Lian §6–7, doc/spec/cases-lian1994.md §5): bonds of the reference state against
//! now (damage ratio (6.2), newly-made ratio, bond probability (6.4)), and clusters.

use serde_json::{Value, json};

use crate::sim::Scene;

/// Bond counts against the reference: (initial, broken, new).
pub fn bond_counts(reference: &[(u32, u32)], now: &[(u32, u32)]) -> (usize, usize, usize) {
    // Both sorted.
    let (mut i, mut j) = (0, 0);
    let (mut kept, mut new) = (0, 0);
    while i < reference.len() && j < now.len() {
        match reference[i].cmp(&now[j]) {
            std::cmp::Ordering::Equal => {
                kept += 1;
                i += 1;
                j += 1;
            }
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => {
                new += 1;
                j += 1;
            }
        }
    }
    new += now.len() - j;
    (reference.len(), reference.len() - kept, new)
}

/// The bonds that define an agglomerate: liquid bridges in a wet scene, touching contacts
/// otherwise.
pub fn bonds_now(scene: &Scene) -> (Vec<(u32, u32)>, bool) {
    let wet = scene.liquid().is_some_and(|l| l.pvol > 0.0);
    (scene.bonded_pairs(wet), wet)
}

pub fn bonds_item(scene: &Scene) -> (String, Value) {
    let Some(r) = &scene.reference() else {
        return (
            "no reference state: give `PLot SAve` first\n".into(),
            json!({"print": "bonds", "error": "no reference state"}),
        );
    };
    let (now, wet) = bonds_now(scene);
    let refb = if wet { &r.bridges } else { &r.contacts };
    let (n0, nd, nn) = bond_counts(refb, &now);
    let dr = if n0 > 0 { nd as f64 / n0 as f64 } else { 0.0 };
    let nr = if n0 > 0 { nn as f64 / n0 as f64 } else { 0.0 };
    // Bond probability (6.4) with the reference coordination number in place of Z = 8.
    let z = if r.ids.is_empty() {
        0.0
    } else {
        2.0 * n0 as f64 / r.ids.len() as f64
    };
    let pb = z / 12.0 * (1.0 - dr + nr);
    // Olsson (2017) (67): Δ = incident kinetic energy / bonding energy of the agglomerate.
    let delta = if r.bond_energy > 0.0 {
        r.kinetic / r.bond_energy
    } else {
        0.0
    };
    let s = format!(
        "bonds ({}) since cycle {}: initial {n0}, broken {nd}, new {nn}; damage ratio {dr:.6}, new ratio {nr:.6}, bond probability {pb:.6}, delta {delta:.4e}\n",
        if wet {
            "liquid bridges"
        } else {
            "touching contacts"
        },
        r.cycle
    );
    let j = json!({
        "print": "bonds", "kind": if wet { "bridges" } else { "contacts" },
        "reference_cycle": r.cycle, "initial": n0, "broken": nd, "new": nn,
        "damage_ratio": dr, "new_ratio": nr, "bond_probability": pb,
        "incident_kinetic": r.kinetic, "bond_energy": r.bond_energy, "delta": delta,
    });
    (s, j)
}

/// Cluster sizes (largest first) of the graph of the given bonds over all particles.
pub fn cluster_sizes(ids: &[u32], bonds: &[(u32, u32)]) -> Vec<usize> {
    let labels = cluster_labels(ids, bonds);
    let mut count = vec![0usize; ids.len()];
    for &l in &labels {
        count[l] += 1;
    }
    let mut sizes: Vec<usize> = count.into_iter().filter(|&c| c > 0).collect();
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    sizes
}

/// Cluster label (the smallest particle index of its cluster) of every particle.
pub fn cluster_labels(ids: &[u32], bonds: &[(u32, u32)]) -> Vec<usize> {
    let mut index = std::collections::HashMap::new();
    for (k, &id) in ids.iter().enumerate() {
        index.insert(id, k);
    }
    let mut parent: Vec<usize> = (0..ids.len()).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for (a, b) in bonds {
        if let (Some(&i), Some(&j)) = (index.get(a), index.get(b)) {
            let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
            if ri != rj {
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    (0..ids.len()).map(|i| find(&mut parent, i)).collect()
}

/// Olsson's fragments (2017 §3.5.6): DBSCAN on particle centres with neighbour radius `eps`
/// and at least `min_pts` points (the point itself included) for a core point. Returns the
/// fragment sizes, largest first; points in no fragment (singles, pairs) are not counted.
pub fn dbscan_sizes(pos: &[crate::sim::Vec3], eps: f64, min_pts: usize) -> Vec<usize> {
    use std::collections::HashMap;
    let n = pos.len();
    let key = |x: &crate::sim::Vec3| {
        (
            (x.x / eps).floor() as i64,
            (x.y / eps).floor() as i64,
            (x.z / eps).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, x) in pos.iter().enumerate() {
        grid.entry(key(x)).or_default().push(i);
    }
    let neighbours = |i: usize| -> Vec<usize> {
        let (cx, cy, cz) = key(&pos[i]);
        let mut v = Vec::new();
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(c) = grid.get(&(cx + dx, cy + dy, cz + dz)) {
                        for &j in c {
                            if (pos[j] - pos[i]).norm() <= eps {
                                v.push(j);
                            }
                        }
                    }
                }
            }
        }
        v
    };
    let mut label = vec![usize::MAX; n];
    let mut sizes = Vec::new();
    for i in 0..n {
        if label[i] != usize::MAX {
            continue;
        }
        let nb = neighbours(i);
        if nb.len() < min_pts {
            continue;
        }
        let id = sizes.len();
        let mut size = 0;
        let mut stack = vec![i];
        label[i] = id;
        size += 1;
        while let Some(k) = stack.pop() {
            let nk = neighbours(k);
            if nk.len() < min_pts {
                continue; // border point: in the fragment, does not extend it
            }
            for j in nk {
                if label[j] == usize::MAX {
                    label[j] = id;
                    size += 1;
                    stack.push(j);
                }
            }
        }
        sizes.push(size);
    }
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    sizes
}

/// Fractal dimension (Lian (7.1), φ_s = 1): D_f = ln N_p / ln(R_c/R), R_c the radius of the
/// sphere about the centroid that encloses all particles, R the mean particle radius.
pub fn fractal_dimension(pos: &[crate::sim::Vec3], radius: &[f64]) -> f64 {
    let n = pos.len();
    if n < 2 {
        return 0.0;
    }
    let c = pos.iter().fold(crate::sim::Vec3::zeros(), |a, x| a + x) / n as f64;
    let rc = pos
        .iter()
        .zip(radius)
        .map(|(x, r)| (x - c).norm() + r)
        .fold(0.0, f64::max);
    let rm = radius.iter().sum::<f64>() / n as f64;
    (n as f64).ln() / (rc / rm).ln()
}

/// The particles (indices) of the largest cluster of bonded particles (ties: the lowest
/// label).
fn largest_cluster(p: &crate::sim::scene::Particles, bonds: &[(u32, u32)]) -> Vec<usize> {
    let mut index = std::collections::HashMap::new();
    for (k, &id) in p.id.iter().enumerate() {
        index.insert(id, k);
    }
    let labels = cluster_labels(&p.id, bonds);
    let mut count = std::collections::HashMap::new();
    for &l in &labels {
        *count.entry(l).or_insert(0usize) += 1;
    }
    let best = count
        .iter()
        .max_by_key(|(l, c)| (**c, std::cmp::Reverse(**l)))
        .map(|(l, _)| *l);
    (0..p.len()).filter(|&k| Some(labels[k]) == best).collect()
}

pub fn clusters_item(scene: &Scene) -> (String, Value) {
    let (bonds, wet) = bonds_now(scene);
    let sizes = cluster_sizes(&scene.particles().id, &bonds);
    let p = &scene.particles();
    let coordination = if p.is_empty() {
        0.0
    } else {
        2.0 * bonds.len() as f64 / p.len() as f64
    };
    // Particles held by a wall (solid contact or bridge): Olsson's capture ratio.
    let mut on_wall = vec![false; p.len()];
    for (i, _) in scene.touching_pairs().1 {
        on_wall[i] = true;
    }
    for c in scene.contacts().wall_pairs() {
        if c.s.bridge.is_some() {
            on_wall[c.i as usize] = true;
        }
    }
    let captured = on_wall.iter().filter(|&&b| b).count();
    let capture_ratio = if p.is_empty() {
        0.0
    } else {
        captured as f64 / p.len() as f64
    };
    let rmean = if p.is_empty() {
        0.0
    } else {
        p.radius.iter().sum::<f64>() / p.len() as f64
    };
    let eps = scene.settings().fragment_eps.unwrap_or(4.0 * rmean);
    let frags = dbscan_sizes(&p.pos, eps, 3);
    let fragmentation = p.len() - frags.first().copied().unwrap_or(0);
    // Fractal dimension of the largest cluster.
    let largest_members = largest_cluster(p, &bonds);
    // Where the largest cluster's particles come from (agglomerate 0 = none, 1, 2). The two
    // agglomerates coalesced (Lian ch. 7) when it holds most of each (a few particles carried
    // across by a grazing contact do not count).
    let mut largest_by_agglomerate = [0usize; 3];
    let mut by_agglomerate = [0usize; 3];
    for &k in &largest_members {
        largest_by_agglomerate[(p.agg[k] as usize).min(2)] += 1;
    }
    for &a in &p.agg {
        by_agglomerate[(a as usize).min(2)] += 1;
    }
    let coalesced =
        (1..3).all(|a| by_agglomerate[a] > 0 && 2 * largest_by_agglomerate[a] > by_agglomerate[a]);
    let df = fractal_dimension(
        &largest_members
            .iter()
            .map(|&k| p.pos[k])
            .collect::<Vec<_>>(),
        &largest_members
            .iter()
            .map(|&k| p.radius[k])
            .collect::<Vec<_>>(),
    );
    let n = scene.particles().len();
    let largest = sizes.first().copied().unwrap_or(0);
    let debris = n - largest;
    let count = |k: usize| sizes.iter().skip(1).filter(|&&s| s == k).count();
    let (s1, s2, s3) = (count(1), count(2), count(3));
    let frac = |x: usize| {
        if debris > 0 {
            x as f64 / debris as f64
        } else {
            0.0
        }
    };
    let s = format!(
        "clusters by {}: {} clusters, largest {} ({:.2} % of particles); debris {} particles: singlets {:.2} %, doublets {:.2} %, triplets {:.2} %\n",
        if wet {
            "liquid bridges"
        } else {
            "touching contacts"
        },
        sizes.len(),
        largest,
        if n > 0 {
            100.0 * largest as f64 / n as f64
        } else {
            0.0
        },
        debris,
        100.0 * frac(s1),
        100.0 * frac(2 * s2),
        100.0 * frac(3 * s3)
    );
    let s = if largest_by_agglomerate[2] > 0 {
        format!(
            "{s}largest cluster: {} particles of agglomerate 1, {} of agglomerate 2{}\n",
            largest_by_agglomerate[1],
            largest_by_agglomerate[2],
            if coalesced { " (coalesced)" } else { "" }
        )
    } else {
        s
    };
    let s = format!(
        "{s}coordination {coordination:.4}; fractal dimension of the largest cluster {df:.4}; capture ratio {capture_ratio:.4}; \
         Olsson fragmentation {fragmentation} particles (DBSCAN eps {eps:.3e} m, {} fragments)\n",
        frags.len()
    );
    let j = json!({
        "print": "clusters", "kind": if wet { "bridges" } else { "contacts" },
        "sizes": sizes, "largest": largest, "debris": debris,
        "singlets": s1, "doublets": s2, "triplets": s3,
        "coordination": coordination, "fractal_dimension": df,
        "capture_ratio": capture_ratio, "fragmentation": fragmentation,
        "fragments": frags, "fragment_eps": eps,
        "largest_by_agglomerate": largest_by_agglomerate, "coalesced": coalesced,
    });
    (s, j)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_that_breaks_in_two() {
        // A chain 1-2-3-4-5 loses bond 3-4: two clusters of 3 and 2.
        let ids = [1, 2, 3, 4, 5];
        let before = [(1, 2), (2, 3), (3, 4), (4, 5)];
        let after = [(1, 2), (2, 3), (4, 5)];
        assert_eq!(cluster_sizes(&ids, &before), vec![5]);
        assert_eq!(cluster_sizes(&ids, &after), vec![3, 2]);
        assert_eq!(bond_counts(&before, &after), (4, 1, 0));
        // A new bond 1-5 is counted as new.
        assert_eq!(bond_counts(&before, &[(1, 2), (1, 5)]), (4, 3, 1));
    }

    #[test]
    fn three_bridges_make_one_cluster_and_dbscan_finds_fragments() {
        // A triangle of bridges 1-2, 2-3, 1-3 plus an isolated particle 4.
        assert_eq!(
            cluster_sizes(&[1, 2, 3, 4], &[(1, 2), (1, 3), (2, 3)]),
            vec![3, 1]
        );
        use crate::sim::Vec3;
        // Two lines of 5 points spaced 1 apart, far from each other, and a lone pair.
        let mut pos: Vec<Vec3> = (0..5).map(|k| Vec3::new(k as f64, 0.0, 0.0)).collect();
        pos.extend((0..5).map(|k| Vec3::new(k as f64, 100.0, 0.0)));
        pos.push(Vec3::new(50.0, 50.0, 0.0));
        pos.push(Vec3::new(50.5, 50.0, 0.0));
        assert_eq!(dbscan_sizes(&pos, 1.01, 3), vec![5, 5]);
    }

    #[test]
    fn fractal_dimension_of_a_compact_ball() {
        // A dense cubic block of N = 1000 unit spheres: R_c/R ≈ 5·√3+1 → D_f = ln N / ln(R_c/R).
        use crate::sim::Vec3;
        let mut pos = Vec::new();
        for i in 0..10 {
            for j in 0..10 {
                for k in 0..10 {
                    pos.push(Vec3::new(2.0 * i as f64, 2.0 * j as f64, 2.0 * k as f64));
                }
            }
        }
        let r = vec![1.0; pos.len()];
        let rc = (3.0f64 * 81.0).sqrt() + 1.0;
        let want = 1000f64.ln() / rc.ln();
        assert!((fractal_dimension(&pos, &r) - want).abs() < 1e-12);
    }

    #[test]
    fn singletons_are_clusters() {
        assert_eq!(cluster_sizes(&[7, 8, 9], &[]), vec![1, 1, 1]);
        assert_eq!(
            cluster_sizes(&[1, 2, 3, 4], &[(1, 2), (2, 3), (1, 3)]),
            vec![3, 1]
        );
    }
}
