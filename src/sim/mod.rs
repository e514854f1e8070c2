//! The simulation core: state, generation, contact search, contact forces, time stepping and
//! the energy ledger. No I/O happens here: the session asks and formats.

pub mod cell;
pub mod contact_time;
pub mod contacts;
pub mod cycle;
pub mod elastoplastic;
pub mod energy;
pub mod generate;
pub mod history;
pub mod interact;
pub mod lanes;
pub mod leapfrog;
pub mod liquid;
pub mod mdr;
pub mod model;
pub mod parallel;
pub mod params;
pub mod place;
pub mod reference;
pub mod rng;
pub mod rolling;
pub mod scene;
pub mod search;
pub mod stress;
pub mod walls;

pub use scene::{Scene, Vec3};

/// Appends one row to the history (columns of [`history::COLUMNS`]).
pub fn record_history(scene: &mut Scene) {
    let st = energy::stored(scene);
    let (c, cw) = scene.touching_counts();
    let (b, bw) = scene.contacts.bridge_counts();
    let wf: f64 = scene.walls.iter().map(|w| w.normal_force).sum();
    let mut row = vec![
        scene.cycle as f64,
        scene.time,
        st.kinetic_translation + st.kinetic_rotation,
        st.strain_normal + st.strain_tangential + st.bridge,
        scene.ledger.input() + scene.cell.work,
        scene.ledger.dissipated(),
        energy::residual(scene),
        (c + cw) as f64,
        (b + bw) as f64,
        wf,
    ];
    // The average stress (`stress`: total, compression positive, Pa; rows recorded before
    // checkpoint format 4 hold 0) and the granular temperature ⟨C·C⟩/3.
    let s = stress::of(scene).total();
    row.extend([s[0][0], s[1][1], s[2][2], s[0][1], s[1][2], s[2][0]]);
    row.push(stress::temperature(scene));
    // The periodic cell's accumulated strains (`sim::cell`).
    let e = scene.cell.strain;
    row.extend([e[0], e[1], e[2], e[3]]);
    scene.history.rows.push(row);
}
