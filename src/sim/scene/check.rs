//! The invariants the simulation relies on, checked on a decoded checkpoint
//! ([`Scene::check_consistency`]): array lengths, indices, ids and numbers within the ranges
//! the program keeps them in.

use super::*;

impl Scene {
    /// The invariants the simulation relies on (array lengths, indices, ids), so that a file
    /// that passed the checksum but holds an impossible state is refused instead of making a
    /// later command panic.
    pub fn check_consistency(&self) -> Result<(), String> {
        check_consistency(self)?;
        check_carried(self)?;
        self.check_groups()
    }
}

/// What the last Cycle handed on (`Carried`): finite work in flight, no more wall
/// velocities than walls, a kept servo's axis targets on the three axes.
fn check_carried(scene: &Scene) -> Result<(), String> {
    let c = &scene.carried;
    if !(c.in_flight_end.is_finite() && c.wall_step_work.is_finite()) {
        return Err("the work in flight carried from the last Cycle is not finite".into());
    }
    if c.wall_last_vel.len() > scene.walls.len() {
        return Err(format!(
            "{} walls' last velocities for {} walls",
            c.wall_last_vel.len(),
            scene.walls.len()
        ));
    }
    let axis_ok =
        |t: &super::cell::StressTarget| !matches!(t, super::cell::StressTarget::Axis(k) if *k > 2);
    if let Some(k) = &c.servo
        && !k
            .servo
            .targets
            .iter()
            .all(|(t, v, _)| axis_ok(t) && v.is_finite())
    {
        return Err("the kept stress servo has a target on no axis, or not finite".into());
    }
    Ok(())
}

fn check_consistency(scene: &Scene) -> Result<(), String> {
    use crate::sim::scene::{MAX_MATERIALS, MAX_SIZES};
    let p = &scene.particles;
    let n = p.len();
    let lens = [
        p.pos.len(),
        p.vel.len(),
        p.spin.len(),
        p.rot.len(),
        p.force.len(),
        p.moment.len(),
        p.radius.len(),
        p.mass.len(),
        p.size.len(),
        p.material.len(),
        p.agg.len(),
        p.fixed.len(),
        p.disp.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(format!(
            "particle arrays of unequal length ({n} ids, {lens:?})"
        ));
    }
    if scene.sizes.len() > MAX_SIZES || scene.materials.len() > MAX_MATERIALS {
        return Err("too many size or material types".into());
    }
    let mut ids = p.id.clone();
    ids.sort_unstable();
    if ids.windows(2).any(|w| w[0] == w[1]) {
        return Err("two particles share an id".into());
    }
    if ids.last().is_some_and(|&m| m >= scene.next_id) {
        return Err("a particle id is not below the next id".into());
    }
    for i in 0..n {
        let s = p.size[i] as usize;
        let m = p.material[i] as usize;
        if s == 0 || s > scene.sizes.len() || m == 0 || m > scene.materials.len() {
            return Err(format!(
                "particle {} has size type {s} or material type {m} out of range",
                p.id[i]
            ));
        }
        if !(p.radius[i] > 0.0 && p.mass[i] > 0.0) || p.agg[i] > 2 {
            return Err(format!(
                "particle {} has a bad radius, mass or agglomerate",
                p.id[i]
            ));
        }
    }
    for w in &scene.walls {
        if w.material == 0 || w.material > scene.materials.len() {
            return Err(format!(
                "a wall has material type {} out of range",
                w.material
            ));
        }
    }
    let c = &scene.contacts;
    for (k, pair) in c.pairs().iter().enumerate() {
        let (i, j) = (pair.i as usize, pair.j as usize);
        if i >= n || j >= n || pair.ida >= pair.idb {
            return Err("a contact refers to a particle that does not exist".into());
        }
        if !c.is_stale() && (p.id[i] != pair.ida || p.id[j] != pair.idb) {
            return Err("a contact's particle indices do not match its ids".into());
        }
        if k > 0 && (c.pairs()[k - 1].ida, c.pairs()[k - 1].idb) >= (pair.ida, pair.idb) {
            return Err("the contacts are not sorted by ids".into());
        }
    }
    for (k, wp) in c.wall_pairs.iter().enumerate() {
        if wp.i as usize >= n || wp.wall as usize >= scene.walls.len() {
            return Err("a wall contact refers to a particle or wall that does not exist".into());
        }
        if !c.is_stale() && p.id[wp.i as usize] != wp.id {
            return Err("a wall contact's particle index does not match its id".into());
        }
        if k > 0 && (c.wall_pairs[k - 1].id, c.wall_pairs[k - 1].wall) >= (wp.id, wp.wall) {
            return Err("the wall contacts are not sorted by ids".into());
        }
    }
    if let Some(r) = &scene.reference
        && (r.pos.len() != r.ids.len() || r.rot.len() != r.ids.len())
    {
        return Err("the reference state (PLot SAve) has arrays of unequal length".into());
    }
    let cols = crate::sim::history::COLUMNS.len();
    if scene.history.rows.iter().any(|r| r.len() != cols) {
        return Err("a history row has the wrong number of columns".into());
    }
    check_numbers(scene)
}

/// Every number of a decoded state is one the program could have written: finite, and
/// positive or within its range where the program keeps it so (a damaged payload with a
/// recomputed checksum can hold anything). The message names the first bad field.
fn check_numbers(scene: &Scene) -> Result<(), String> {
    check_scene_values(scene)?;
    check_particle_values(scene)?;
    check_wall_values(scene)?;
    check_contact_values(scene)?;
    check_ledger_values(scene)
}

fn fin(x: f64) -> bool {
    x.is_finite()
}

fn fin3(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn bad(what: String) -> Result<(), String> {
    Err(what)
}

/// Part of [`check_numbers`]: the scene's own values: work-space, time, gravity, damping, liquid, settings, sizes, materials, regions.
fn check_scene_values(scene: &Scene) -> Result<(), String> {
    if !(scene.size.iter().all(|&x| x > 0.0 && x.is_finite())) {
        return bad("the work-space size is not positive and finite".into());
    }
    if !(scene.time >= 0.0 && fin(scene.time)) {
        return bad("the time is not finite".into());
    }
    if !fin3(&scene.gravity) || !fin3(&scene.cgravity) || !fin(scene.fmm) {
        return bad("gravity or its mass factor (FMM) is not finite".into());
    }
    for d in [&scene.damping_pp, &scene.damping_pw] {
        if !(d.alpha >= 0.0 && fin(d.alpha) && d.beta >= 0.0 && fin(d.beta)) {
            return bad("a damping coefficient is negative or not finite".into());
        }
    }
    if let Some(l) = &scene.liquid
        && !(l.pvol >= 0.0
            && fin(l.pvol)
            && l.gamma >= 0.0
            && fin(l.gamma)
            && fin(l.theta)
            && l.eta >= 0.0
            && fin(l.eta))
    {
        return bad("the liquid's parameters are negative or not finite".into());
    }
    let st = &scene.settings;
    for (name, v) in [
        ("TOL", st.tol),
        ("XRES", st.xres),
        ("SMIN", st.smin),
        ("FRAction", st.fraction),
        ("FRAgment", st.fragment_eps),
    ] {
        if let Some(x) = v
            && !(x > 0.0 && fin(x))
        {
            return bad(format!(
                "the setting {name} is {x}: not positive and finite"
            ));
        }
    }
    if let Some(x) = st.auto_step
        && !(x >= 0.0 && fin(x))
    {
        return bad(format!("the step of FRAction AUTO is {x}"));
    }
    if !(st.gen_overlap >= 0.0 && st.gen_overlap < 0.1) || st.window.is_some_and(|w| !fin3(&w)) {
        return bad("the setting GENoverlap or Window is out of range".into());
    }
    for (k, &r) in scene.sizes.iter().enumerate() {
        if !(r >= 0.0 && fin(r)) {
            return bad(format!("size type {} has radius {r}", k + 1));
        }
    }
    for (k, m) in scene.materials.iter().enumerate() {
        let ok = [m.density, m.young, m.friction, m.gamma, m.gamma_base]
            .iter()
            .all(|&x| x >= 0.0 && fin(x))
            && fin(m.poisson)
            && m.poisson < 0.5 + 1e-12
            && m.poisson > -1.0
            && m.restitution.is_none_or(|e| (0.0..=1.0).contains(&e));
        if !ok {
            return bad(format!("material type {} has a value out of range", k + 1));
        }
    }
    for (k, r) in scene.regions.iter().enumerate() {
        if let Some(r) = r
            && !(fin3(&r.centre) && r.radius > 0.0 && fin(r.radius))
        {
            return bad(format!("agglomerate region {} is not finite", k + 1));
        }
    }
    Ok(())
}

/// Part of [`check_numbers`]: the particles' vectors, radii, masses and liquid.
fn check_particle_values(scene: &Scene) -> Result<(), String> {
    let p = &scene.particles;
    for i in 0..p.len() {
        let named =
            |what: &str| Err::<(), String>(format!("particle {} has a non-finite {what}", p.id[i]));
        for (what, v) in [
            ("position", &p.pos[i]),
            ("velocity", &p.vel[i]),
            ("angular velocity", &p.spin[i]),
            ("rotation", &p.rot[i]),
            ("force", &p.force[i]),
            ("moment", &p.moment[i]),
            ("displacement", &p.disp[i]),
        ] {
            if !v.iter().all(|x| x.is_finite()) {
                return named(what);
            }
        }
        if !fin(p.radius[i]) || !fin(p.mass[i]) {
            return named("radius or mass");
        }
        if p.liquid.get(i).is_some_and(|&l| !(l >= 0.0 && fin(l))) {
            return named("liquid");
        }
    }
    Ok(())
}

/// Part of [`check_numbers`]: the walls' geometry, motion, servo and forces.
fn check_wall_values(scene: &Scene) -> Result<(), String> {
    for (k, w) in scene.walls.iter().enumerate() {
        use crate::sim::model::WallGeom;
        let geom_ok = match w.geom {
            WallGeom::Plane { normal, d } => {
                fin3(&normal) && normal.iter().any(|&x| x != 0.0) && fin(d)
            }
            WallGeom::Sphere { centre, radius } | WallGeom::Obstacle { centre, radius } => {
                fin3(&centre) && radius >= 0.0 && fin(radius)
            }
            WallGeom::Cylinder {
                point,
                axis,
                radius,
            } => {
                fin3(&point)
                    && fin3(&axis)
                    && axis.iter().any(|&x| x != 0.0)
                    && radius >= 0.0
                    && fin(radius)
            }
        };
        let servo_ok = w.servo.is_none_or(|s| {
            fin(s.force) && s.vmax >= 0.0 && fin(s.vmax) && s.gain >= 0.0 && fin(s.gain)
        });
        if !(geom_ok
            && servo_ok
            && fin3(&w.vel)
            && fin(w.vr)
            && fin3(&w.force)
            && fin(w.normal_force)
            && fin3(&w.disp)
            && w.travel >= 0.0
            && fin(w.travel))
        {
            return bad(format!(
                "wall {} has a geometry, motion or force out of range",
                k + 1
            ));
        }
    }
    Ok(())
}

/// Part of [`check_numbers`]: the contact states of particle pairs and particle–wall pairs, and the list's TOL.
fn check_contact_values(scene: &Scene) -> Result<(), String> {
    let state_ok = |s: &crate::sim::contacts::ContactState| {
        let e = s.ext();
        let t = &e.tang;
        let w = &e.walton;
        let ext_ok = [
            e.a_s,
            e.gamma,
            e.tdelta,
            t.t,
            t.stored,
            e.released[0],
            e.released[1],
            w.t_star,
            w.fn_prev,
            w.stored,
        ]
        .iter()
        .all(|x| x.is_finite())
            && e.delta.iter().all(|x| x.is_finite())
            && t.tp.iter().all(|x| x.is_finite())
            && (t.n_tp as usize) <= t.tp.len();
        let bridge_ok = s.bridge.as_deref().is_none_or(|b| {
            [
                b.volume, b.s_c, b.f_static, b.f_visc, b.gap, b.work, b.share[0], b.share[1],
            ]
            .iter()
            .all(|x| x.is_finite())
                && b.volume >= 0.0
                && b.f_tang.iter().all(|x| x.is_finite())
        });
        [s.overlap, s.normal_force, s.damp_force, s.tang_energy, s.a]
            .iter()
            .all(|x| x.is_finite())
            && s.a >= 0.0
            && (s.v_prev.is_finite() || s.v_prev.is_infinite())
            && s.tforce.iter().all(|x| x.is_finite())
            && s.tdamp.iter().all(|x| x.is_finite())
            && ext_ok
            && bridge_ok
    };
    for c in scene.contacts.iter() {
        if !state_ok(c.s) {
            return bad(format!(
                "the contact of particles {} and {} holds a value that is not finite",
                c.ida, c.idb
            ));
        }
    }
    for c in &scene.contacts.wall_pairs {
        if !state_ok(&c.s) {
            return bad(format!(
                "the contact of particle {} and wall {} holds a value that is not finite",
                c.id,
                c.wall + 1
            ));
        }
    }
    if !(scene.contacts.tol() >= 0.0 && fin(scene.contacts.tol())) {
        return bad("the candidate list's TOL is not finite".into());
    }
    Ok(())
}

/// Part of [`check_numbers`]: the energy ledger, the reference state and the history rows.
fn check_ledger_values(scene: &Scene) -> Result<(), String> {
    let l = &scene.ledger;
    if ![
        l.commands,
        l.gravity,
        l.walls,
        l.friction,
        l.damping_mass,
        l.damping_contact,
        l.viscous,
        l.adhesion,
        l.rupture,
    ]
    .iter()
    .all(|x| x.is_finite())
    {
        return bad("the energy ledger holds a value that is not finite".into());
    }
    if let Some(r) = &scene.reference
        && !(r.pos.iter().chain(&r.rot).all(|v| fin3(v)) && fin(r.kinetic))
    {
        return bad("the reference state (PLot SAve) holds a value that is not finite".into());
    }
    if scene
        .history
        .rows
        .iter()
        .any(|r| !r.iter().all(|x| x.is_finite()))
    {
        return bad("a history row holds a value that is not finite".into());
    }
    Ok(())
}
