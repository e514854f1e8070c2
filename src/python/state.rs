//! The scene as numpy arrays, read through `sim/scene/access.rs` and the measures the
//! `PRint` items use (`sim::energy`, `sim::stress`, `output::fields`): every array a copy
//! (one `memcpy` for the particle vectors, which are already arrays of structures of three
//! f64), never text.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::sim::scene::Vec3;
use crate::sim::{Scene, energy, stress};

type Dict<'py> = Bound<'py, PyDict>;

/// An (n, 3) array of vectors.
fn vectors<'py>(py: Python<'py>, v: &[Vec3]) -> PyResult<Bound<'py, PyAny>> {
    let flat: &[f64] = bytemuck::cast_slice(v);
    Ok(PyArray1::from_slice(py, flat)
        .reshape([v.len(), 3])?
        .into_any())
}

/// A (n, k) array from rows.
fn rows<'py, const K: usize>(py: Python<'py>, v: &[[f64; K]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = v.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([v.len(), K])?
        .into_any())
}

fn matrix<'py>(py: Python<'py>, m: &[[f64; 3]; 3]) -> PyResult<Bound<'py, PyAny>> {
    rows(py, &m[..])
}

pub fn particles<'py>(py: Python<'py>, s: &Scene) -> PyResult<Dict<'py>> {
    let p = s.particles();
    let d = PyDict::new(py);
    d.set_item("id", PyArray1::from_slice(py, &p.id))?;
    d.set_item("position", vectors(py, &p.pos)?)?;
    d.set_item("velocity", vectors(py, &p.vel)?)?;
    d.set_item("spin", vectors(py, &p.spin)?)?;
    d.set_item("force", vectors(py, &p.force)?)?;
    d.set_item("moment", vectors(py, &p.moment)?)?;
    d.set_item("radius", PyArray1::from_slice(py, &p.radius))?;
    d.set_item("mass", PyArray1::from_slice(py, &p.mass))?;
    d.set_item("material", PyArray1::from_slice(py, &p.material))?;
    d.set_item("size", PyArray1::from_slice(py, &p.size))?;
    d.set_item("agglomerate", PyArray1::from_slice(py, &p.agg))?;
    d.set_item("fixed", PyArray1::from_slice(py, &p.fixed))?;
    Ok(d)
}

/// One contact's columns, filled pair by pair.
#[derive(Default)]
struct Columns {
    ids: Vec<[u32; 2]>,
    index: Vec<[u64; 2]>,
    overlap: Vec<f64>,
    normal_force: Vec<f64>,
    force: Vec<[f64; 3]>,
    touching: Vec<bool>,
    active: Vec<bool>,
    contact_radius: Vec<f64>,
    bridge: Vec<bool>,
    bridge_volume: Vec<f64>,
    bridge_force: Vec<f64>,
}

impl Columns {
    fn push_state(&mut self, c: &crate::sim::contacts::ContactState, overlap: f64, touching: bool) {
        self.overlap.push(overlap);
        self.normal_force.push(c.normal_force + c.damp_force);
        self.touching.push(touching);
        self.active.push(c.touching);
        self.contact_radius.push(c.a);
        self.bridge.push(c.bridge.is_some());
        self.bridge_volume
            .push(c.bridge.as_ref().map_or(0.0, |b| b.volume));
        self.bridge_force
            .push(c.bridge.as_ref().map_or(0.0, |b| b.f_visc - b.f_static));
    }

    fn into_dict<'py>(self, py: Python<'py>, evaluated: bool, two: &str) -> PyResult<Dict<'py>> {
        let d = PyDict::new(py);
        let n = self.ids.len();
        let ids: Vec<u32> = self.ids.iter().flatten().copied().collect();
        let index: Vec<u64> = self.index.iter().flatten().copied().collect();
        d.set_item(two, PyArray1::from_vec(py, ids).reshape([n, 2])?)?;
        d.set_item("index", PyArray1::from_vec(py, index).reshape([n, 2])?)?;
        d.set_item("overlap", PyArray1::from_vec(py, self.overlap))?;
        d.set_item("normal_force", PyArray1::from_vec(py, self.normal_force))?;
        if !self.force.is_empty() || n == 0 {
            d.set_item("force", rows(py, &self.force)?)?;
        }
        d.set_item("touching", PyArray1::from_vec(py, self.touching))?;
        d.set_item("active", PyArray1::from_vec(py, self.active))?;
        d.set_item(
            "contact_radius",
            PyArray1::from_vec(py, self.contact_radius),
        )?;
        d.set_item("bridge", PyArray1::from_vec(py, self.bridge))?;
        d.set_item("bridge_volume", PyArray1::from_vec(py, self.bridge_volume))?;
        d.set_item("bridge_force", PyArray1::from_vec(py, self.bridge_force))?;
        d.set_item("evaluated", evaluated)?;
        Ok(d)
    }
}

/// A contact's overlap as `PRint Contacts` shows it: the last step's while the law or a
/// bridge acts, else the gap now, negative.
fn shown_overlap(c: &crate::sim::contacts::ContactState, gap: f64) -> f64 {
    if c.touching || c.bridge.is_some() {
        c.overlap
    } else {
        -gap
    }
}

/// Particle pairs: `ids` (a, b), `index` (rows of the particle arrays), `overlap`,
/// `normal_force` (elastic + dashpot), `force` (the vector on b of the last step: normal,
/// tangential and bridge), `touching`, `active` (the law acts), `contact_radius`, `bridge`,
/// `bridge_volume`, `bridge_force` (viscous − static), and `evaluated`: false when commands
/// changed the scene since the last Cycle (then the pairs touching by their positions, no
/// forces, as `PRint Contacts`).
pub fn contacts<'py>(py: Python<'py>, s: &Scene, all: bool) -> PyResult<Dict<'py>> {
    let p = s.particles();
    let none = crate::sim::contacts::ContactState::default();
    let mut c = Columns::default();
    if !all && !s.contacts_current() {
        for (i, j) in s.touching_by_gap().0 {
            c.ids.push([p.id[i], p.id[j]]);
            c.index.push([i as u64, j as u64]);
            c.force.push([0.0; 3]);
            c.push_state(&none, -s.pair_gap(i, j), true);
        }
        return c.into_dict(py, false, "ids");
    }
    for v in s.contacts().iter() {
        let (i, j) = (v.i as usize, v.j as usize);
        let touching = s.pair_touches(v.s, i, j);
        if !(all || touching || v.s.bridge.is_some()) {
            continue;
        }
        let l = s.branch(&p.pos[i], &p.pos[j]);
        let dist = l.norm();
        let f = if dist > 0.0 {
            stress::pair_force(v.s, &(l / dist))
        } else {
            Vec3::zeros()
        };
        c.ids.push([v.ida, v.idb]);
        c.index.push([i as u64, j as u64]);
        c.force.push([f.x, f.y, f.z]);
        c.push_state(v.s, shown_overlap(v.s, s.pair_gap(i, j)), touching);
    }
    c.into_dict(py, s.contacts_current(), "ids")
}

/// Particle–wall pairs: `ids` (particle id, wall number from 1), `index` (particle row,
/// wall row), and the columns of [`contacts`] but `force`.
pub fn wall_contacts<'py>(py: Python<'py>, s: &Scene, all: bool) -> PyResult<Dict<'py>> {
    let p = s.particles();
    let none = crate::sim::contacts::ContactState::default();
    let mut c = Columns::default();
    if !all && !s.contacts_current() {
        for (i, w) in s.touching_by_gap().1 {
            c.ids.push([p.id[i], w as u32 + 1]);
            c.index.push([i as u64, w as u64]);
            c.push_state(&none, -s.wall_gap(i, w), true);
        }
        return c.into_dict(py, false, "ids");
    }
    for v in s.contacts().wall_pairs() {
        let (i, w) = (v.i as usize, v.wall as usize);
        let touching = s.wall_touches(&v.s, i, w);
        if !(all || touching || v.s.bridge.is_some()) {
            continue;
        }
        c.ids.push([v.id, v.wall + 1]);
        c.index.push([i as u64, w as u64]);
        c.push_state(&v.s, shown_overlap(&v.s, s.wall_gap(i, w)), touching);
    }
    c.into_dict(py, s.contacts_current(), "ids")
}

pub fn walls<'py>(py: Python<'py>, s: &Scene) -> PyResult<Dict<'py>> {
    let w = s.walls();
    let d = PyDict::new(py);
    let force: Vec<[f64; 3]> = w.iter().map(|w| w.force).collect();
    let vel: Vec<[f64; 3]> = w.iter().map(|w| w.vel).collect();
    let disp: Vec<[f64; 3]> = w.iter().map(|w| w.disp).collect();
    let normal: Vec<f64> = w.iter().map(|w| w.normal_force).collect();
    let material: Vec<u64> = w.iter().map(|w| w.material as u64).collect();
    d.set_item("force", rows(py, &force)?)?;
    d.set_item("normal_force", PyArray1::from_vec(py, normal))?;
    d.set_item("velocity", rows(py, &vel)?)?;
    d.set_item("displacement", rows(py, &disp)?)?;
    d.set_item("material", PyArray1::from_vec(py, material))?;
    Ok(d)
}

/// The names and values of `PRint ENergy`'s JSON object, flat.
pub fn energy<'py>(py: Python<'py>, s: &Scene) -> PyResult<Dict<'py>> {
    let st = energy::stored(s);
    let l = s.ledger();
    let d = PyDict::new(py);
    let items = [
        ("kinetic", st.kinetic_translation + st.kinetic_rotation),
        ("kinetic_translation", st.kinetic_translation),
        ("kinetic_rotation", st.kinetic_rotation),
        ("strain", st.strain_normal + st.strain_tangential),
        ("strain_normal", st.strain_normal),
        ("strain_tangential", st.strain_tangential),
        ("bridge", st.bridge),
        ("input", l.input() + s.cell().work),
        ("input_commands", l.commands),
        ("input_gravity", l.gravity),
        ("input_walls", l.walls),
        ("input_cell", s.cell().work),
        ("friction", l.friction),
        ("damping_mass", l.damping_mass),
        ("damping_contact", l.damping_contact),
        ("viscous", l.viscous),
        ("adhesion", l.adhesion),
        ("rupture", l.rupture),
        ("dissipated", l.dissipated()),
        ("residual", energy::residual(s)),
    ];
    for (k, v) in items {
        d.set_item(k, v)?;
    }
    Ok(d)
}

pub fn stress<'py>(py: Python<'py>, s: &Scene) -> PyResult<Dict<'py>> {
    let st = stress::of(s);
    let d = PyDict::new(py);
    d.set_item("total", matrix(py, &st.total())?)?;
    d.set_item("contact", matrix(py, &st.contact)?)?;
    d.set_item("kinetic", matrix(py, &st.kinetic)?)?;
    d.set_item("mean", st.mean())?;
    d.set_item("temperature", stress::temperature(s))?;
    Ok(d)
}

pub fn history<'py>(py: Python<'py>, s: &Scene) -> PyResult<Dict<'py>> {
    let cols = crate::sim::history::COLUMNS;
    let rows = &s.history().rows;
    let d = PyDict::new(py);
    for (k, name) in cols.iter().enumerate() {
        let col: Vec<f64> = rows
            .iter()
            .map(|r| r.get(k).copied().unwrap_or(f64::NAN))
            .collect();
        d.set_item(*name, PyArray1::from_vec(py, col))?;
    }
    Ok(d)
}

pub fn field<'py>(
    py: Python<'py>,
    s: &Scene,
    nodes: [usize; 3],
    width: f64,
    lucy: bool,
) -> PyResult<Dict<'py>> {
    use crate::output::fields;
    let spec = fields::Spec {
        nodes,
        width,
        kernel: if lucy {
            fields::Kernel::Lucy
        } else {
            fields::Kernel::Gauss
        },
        region: None,
    };
    fields::check(s, &spec).map_err(super::CommandError::new_err)?;
    let f = fields::compute(s, &spec);
    let [nx, ny, nz] = nodes;
    let d = PyDict::new(py);
    d.set_item(
        "density",
        PyArray1::from_slice(py, &f.density).reshape([nz, ny, nx])?,
    )?;
    d.set_item(
        "solid_fraction",
        PyArray1::from_slice(py, &f.solid_fraction).reshape([nz, ny, nx])?,
    )?;
    d.set_item(
        "coordination",
        PyArray1::from_slice(py, &f.coordination).reshape([nz, ny, nx])?,
    )?;
    let flat3: Vec<f64> = f.velocity.iter().flatten().copied().collect();
    d.set_item(
        "velocity",
        PyArray1::from_vec(py, flat3).reshape([nz, ny, nx, 3])?,
    )?;
    for (name, t) in [
        ("stress_contact", &f.stress_contact),
        ("stress_kinetic", &f.stress_kinetic),
    ] {
        let flat: Vec<f64> = t.iter().flatten().copied().collect();
        d.set_item(
            name,
            PyArray1::from_vec(py, flat).reshape([nz, ny, nx, 3, 3])?,
        )?;
    }
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        let c: Vec<f64> = (0..nodes[k])
            .map(|a| (a as f64 + 0.5) * f.spacing[k])
            .collect();
        d.set_item(*name, PyArray1::from_vec(py, c))?;
    }
    Ok(d)
}
