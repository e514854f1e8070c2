//! Agglomerate measures (Lian §6–7, cases-lian1994 §5): bonds of the reference state against
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

/// The bonds that define an agglomerate: liquid bridges in a wet scene, solid contacts
/// otherwise.
pub fn bonds_now(scene: &Scene) -> (Vec<(u32, u32)>, bool) {
    let wet = scene.liquid.is_some_and(|l| l.pvol > 0.0);
    (scene.contacts.bonded_pairs(&scene.particles, wet), wet)
}

pub fn bonds_item(scene: &Scene) -> (String, Value) {
    let Some(r) = &scene.reference else {
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
    let s = format!(
        "bonds ({}) since cycle {}: initial {n0}, broken {nd}, new {nn}; damage ratio {dr:.6}, new ratio {nr:.6}, bond probability {pb:.6}\n",
        if wet {
            "liquid bridges"
        } else {
            "solid contacts"
        },
        r.cycle
    );
    let j = json!({
        "print": "bonds", "kind": if wet { "bridges" } else { "contacts" },
        "reference_cycle": r.cycle, "initial": n0, "broken": nd, "new": nn,
        "damage_ratio": dr, "new_ratio": nr, "bond_probability": pb,
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

pub fn clusters_item(scene: &Scene) -> (String, Value) {
    let (bonds, wet) = bonds_now(scene);
    let sizes = cluster_sizes(&scene.particles.id, &bonds);
    let n = scene.particles.len();
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
            "solid contacts"
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
    let j = json!({
        "print": "clusters", "kind": if wet { "bridges" } else { "contacts" },
        "sizes": sizes, "largest": largest, "debris": debris,
        "singlets": s1, "doublets": s2, "triplets": s3,
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
    fn singletons_are_clusters() {
        assert_eq!(cluster_sizes(&[7, 8, 9], &[]), vec![1, 1, 1]);
        assert_eq!(
            cluster_sizes(&[1, 2, 3, 4], &[(1, 2), (2, 3), (1, 3)]),
            vec![3, 1]
        );
    }
}
