//! The datasets of one VTK frame (doc/output.md, "VTK files"): the particles as points, the
//! contacts as lines between centres, the periodic cell's box. The walls' surfaces are in
//! [`super::surfaces`]. Pure functions of the scene: [`super::write_frame`] writes them.

use std::collections::HashMap;

use super::xml::{Array, PolyData, Values};
use crate::lang::command::{CONTACT_ARRAYS, PARTICLE_ARRAYS};
use crate::sim::scene::Vec3;
use crate::sim::stress::pair_force;
use crate::sim::walls::wall_gap;
use crate::sim::{Scene, contacts::ContactState};

fn a3(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The time and cycle of the frame, as field data (ParaView reads `TimeValue`).
pub fn time_fields(scene: &Scene) -> Vec<Array> {
    vec![
        Array::new("TimeValue", 1, Values::F64(vec![scene.time()])),
        Array::new("cycle", 1, Values::I64(vec![scene.cycle() as i64])),
    ]
}

/// Touching particle pairs per particle (`sim::scene::touch`: the one definition of every
/// output; particle pairs only, as `PRint CHist` counts them).
pub fn coordination(scene: &Scene) -> Vec<i32> {
    scene.coordination().into_iter().map(|k| k as i32).collect()
}

/// Every particle array (`VTk` without `ARRays`).
pub const ALL_ARRAYS: u16 = (1 << PARTICLE_ARRAYS.len()) - 1;

/// Every contact array (`VTk` without `CONtacts`).
pub const ALL_CONTACT_ARRAYS: u16 = (1 << CONTACT_ARRAYS.len()) - 1;

/// The particles: points at their centres (one vertex cell each) with the arrays of
/// `arrays` (a bit per entry of [`PARTICLE_ARRAYS`], in that order): id, radius, velocity
/// (relative to the mean field in a deforming cell, as `PRint Balls`), spin, force, moment,
/// material, size type, agglomerate, coordination number, cluster (the smallest id of the
/// particle's cluster of bonds, `PRint CLUsters`) and, after `PLot SAve`, the displacement
/// since that reference (NaN for a particle created since). An array not chosen is not
/// computed.
pub fn particles(scene: &Scene, arrays: u16) -> PolyData {
    let p = scene.particles();
    let n = p.len();
    let mut d = PolyData {
        points: p.pos.iter().map(a3).collect(),
        field_data: time_fields(scene),
        ..Default::default()
    };
    for k in 0..n {
        d.verts.push(&[k]);
    }
    let ints = |v: Vec<i32>| Values::I32(v);
    let on = |name: &str| {
        PARTICLE_ARRAYS
            .iter()
            .position(|&a| a == name)
            .is_some_and(|k| arrays & (1 << k) != 0)
    };
    let pd = &mut d.point_data;
    for name in PARTICLE_ARRAYS.into_iter().filter(|a| on(a)) {
        let array = match name {
            "id" => Array::new(name, 1, ints(p.id.iter().map(|&x| x as i32).collect())),
            "radius" => Array::scalars(name, p.radius.iter().copied()),
            "velocity" => Array::vectors(name, p.vel.iter().map(a3)),
            "spin" => Array::vectors(name, p.spin.iter().map(a3)),
            "force" => Array::vectors(name, p.force.iter().map(a3)),
            "moment" => Array::vectors(name, p.moment.iter().map(a3)),
            "material" => Array::new(
                name,
                1,
                ints(p.material.iter().map(|&x| x as i32).collect()),
            ),
            "size_type" => Array::new(name, 1, ints(p.size.iter().map(|&x| x as i32).collect())),
            "agglomerate" => Array::new(name, 1, ints(p.agg.iter().map(|&x| x as i32).collect())),
            "coordination" => Array::new(name, 1, ints(coordination(scene))),
            "cluster" => {
                let (bonds, _) = crate::analysis::bonds_now(scene);
                let labels = crate::analysis::cluster_labels(&p.id, &bonds);
                Array::new(
                    name,
                    1,
                    ints(labels.iter().map(|&l| p.id[l] as i32).collect()),
                )
            }
            _ => {
                let Some(r) = scene.reference() else { continue };
                let at: HashMap<u32, usize> =
                    r.ids.iter().enumerate().map(|(k, &id)| (id, k)).collect();
                let disp = (0..n).map(|k| match at.get(&p.id[k]).and_then(|&m| r.pos.get(m)) {
                    Some(x0) => a3(&scene.branch(&Vec3::from(*x0), &p.pos[k])),
                    None => [f64::NAN; 3],
                });
                Array::vectors(name, disp)
            }
        };
        pd.push(array);
    }
    d
}

/// One contact's values, whichever its kind.
struct Row {
    a: i32,
    b: i32,
    wall: i32,
    force: [f64; 3],
    fnv: [f64; 3],
    ftv: [f64; 3],
    /// normal_force, tangential_force, overlap, contact_radius, bridge_volume.
    scalars: [f64; 5],
    bridge: bool,
}

/// The contacts that touch or hold a bridge (those `PRint Contacts` lists), as lines from
/// the centre of A to the centre of B's nearest image (a point of its own when that image
/// is not B itself: a contact across a periodic side), or to the contact point on a wall's
/// surface. Cell arrays: `a`, `b` (ids; −1 for a wall), `wall` (its number, 0 for a pair),
/// `normal_force` and `tangential_force` (the elastic + dashpot normal force and the
/// tangential spring force's magnitude, as in `PRint Contacts`), `overlap`, `contact_radius`,
/// `bridge` (1 or 0), `bridge_volume`, and the vectors `force` (the whole force on B of the
/// last step, bridge included: `sim::stress::pair_force`), `normal_force_vector` and
/// `tangential_force_vector` (its normal and tangential parts); of those, the ones of
/// `arrays` (a bit per entry of [`CONTACT_ARRAYS`], in that order).
pub fn contacts(scene: &Scene, arrays: u16) -> PolyData {
    let p = scene.particles();
    let mut d = PolyData {
        points: p.pos.iter().map(a3).collect(),
        field_data: time_fields(scene),
        ..Default::default()
    };
    let mut rows = Vec::new();
    // The pairs that touch (`sim::scene::touch`) or hold a bridge.
    for c in scene.contacts().iter() {
        let (i, j) = (c.i as usize, c.j as usize);
        if !(scene.pair_touches(c.s, i, j) || c.s.bridge.is_some()) {
            continue;
        }
        let l = scene.branch(&p.pos[i], &p.pos[j]);
        let end = if p.pos[i] + l == p.pos[j] {
            j
        } else {
            d.points.push(a3(&(p.pos[i] + l)));
            d.points.len() - 1
        };
        d.lines.push(&[i, end]);
        let dist = l.norm();
        let n = if dist > 0.0 { l / dist } else { Vec3::zeros() };
        rows.push(row(c.ida as i32, c.idb as i32, 0, c.s, &n));
    }
    for c in scene.contacts().wall_pairs() {
        if !(scene.wall_touches(&c.s, c.i as usize, c.wall as usize) || c.s.bridge.is_some()) {
            continue;
        }
        let Some(w) = scene.walls().get(c.wall as usize) else {
            continue;
        };
        let i = c.i as usize;
        let (gap, n) = wall_gap(&w.geom, &p.pos[i], p.radius[i]);
        d.points.push(a3(&(p.pos[i] + n * (gap + p.radius[i]))));
        d.lines.push(&[i, d.points.len() - 1]);
        rows.push(row(c.id as i32, -1, c.wall as i32 + 1, &c.s, &n));
    }
    let on = |k: usize| arrays & (1 << k) != 0;
    for (k, name) in CONTACT_ARRAYS
        .into_iter()
        .enumerate()
        .filter(|&(k, _)| on(k))
    {
        let int = |f: &dyn Fn(&Row) -> i32| Values::I32(rows.iter().map(f).collect());
        let array = match k {
            0 => Array::new(name, 1, int(&|r| r.a)),
            1 => Array::new(name, 1, int(&|r| r.b)),
            2 => Array::new(name, 1, int(&|r| r.wall)),
            3 => Array::vectors(name, rows.iter().map(|r| r.force)),
            4 => Array::vectors(name, rows.iter().map(|r| r.fnv)),
            5 => Array::vectors(name, rows.iter().map(|r| r.ftv)),
            6..=10 => Array::scalars(name, rows.iter().map(|r| r.scalars[k - 6])),
            _ => Array::new(
                name,
                1,
                Values::U8(rows.iter().map(|r| r.bridge as u8).collect()),
            ),
        };
        d.cell_data.push(array);
    }
    d
}

fn row(a: i32, b: i32, wall: i32, s: &ContactState, n: &Vec3) -> Row {
    let f = pair_force(s, n);
    let fnv = n * f.dot(n);
    Row {
        a,
        b,
        wall,
        force: a3(&f),
        fnv: a3(&fnv),
        ftv: a3(&(f - fnv)),
        scalars: [
            s.normal_force + s.damp_force,
            s.tforce.norm(),
            s.overlap,
            s.a,
            s.bridge.as_ref().map_or(0.0, |b| b.volume),
        ],
        bridge: s.bridge.is_some(),
    }
}

/// The periodic cell (the work-space box, 0 ≤ x_k ≤ size_k) as its 12 edges, with the
/// work-space size and the Lees–Edwards offset as field data.
pub fn cell_box(scene: &Scene) -> PolyData {
    let s = scene.size();
    let mut d = PolyData {
        field_data: time_fields(scene),
        ..Default::default()
    };
    for k in 0..8 {
        d.points.push([
            if k & 1 != 0 { s[0] } else { 0.0 },
            if k & 2 != 0 { s[1] } else { 0.0 },
            if k & 4 != 0 { s[2] } else { 0.0 },
        ]);
    }
    for a in 0..8usize {
        for bit in [1, 2, 4] {
            if a & bit == 0 {
                d.lines.push(&[a, a | bit]);
            }
        }
    }
    d.field_data
        .push(Array::new("size", 3, Values::F64(s.to_vec())));
    d.field_data.push(Array::new(
        "periodic",
        3,
        Values::U8(scene.settings().periodic.iter().map(|&b| b as u8).collect()),
    ));
    d.field_data.push(Array::new(
        "offset",
        1,
        // The representative in [−L_x/2, L_x/2), as `PRint Grid` prints it.
        Values::F64(vec![scene.cell().signed_offset(s[0])]),
    ));
    d
}
