//! The commands' changes to a [`Scene`]. The session checks a command's input and calls one
//! of these; each keeps the scene's invariants:
//!
//! * a change to what the contacts see (sizes, cohesion, walls, liquid, laws, settings) marks
//!   the contact store stale (`ContactStore::mark_stale`): the next `Cycle` rebuilds the
//!   candidate list and re-evaluates the contact states at the current positions
//!   (`cycle::prime`);
//! * a density change re-computes the masses of that material's particles;
//! * a plane wall across a periodic axis opens that axis (doc/limits.md);
//! * the kinetic energy a command adds or removes is booked in the ledger
//!   ([`Scene::booked_edit`]).
//!
//! None of these does I/O; errors are messages for the user.

use super::*;
use crate::sim::generate::sphere_mass;
use crate::sim::model::{ContactLaws, SizeDist};

impl Scene {
    /// `RAdius r n [dist]`: size type `size` (1-based) gets radius `r` and distribution
    /// `dist`; particles of that type with a fixed radius take the new radius (their density
    /// kept).
    pub fn set_size_type(&mut self, size: usize, r: f64, dist: SizeDist) -> Result<(), String> {
        if size > MAX_SIZES {
            return Err(format!(
                "size type {size} is beyond the limit of {MAX_SIZES}"
            ));
        }
        if size > self.sizes.len() {
            self.sizes.resize(size, 0.0);
            self.size_dist.resize(size, Default::default());
        }
        self.sizes[size - 1] = r;
        let fixed = dist == SizeDist::Fixed;
        self.size_dist[size - 1] = dist;
        let p = &mut self.particles;
        for i in 0..p.len() {
            if fixed && p.size[i] as usize == size {
                let rho = p.mass[i] / sphere_mass(1.0, p.radius[i]);
                p.radius[i] = r;
                p.mass[i] = sphere_mass(rho, r);
            }
        }
        self.contacts.mark_stale();
        Ok(())
    }

    /// Material `m` (1-based), the table grown to hold it.
    fn material_entry(&mut self, m: usize) -> Result<&mut Material, String> {
        if m > MAX_MATERIALS {
            return Err(format!(
                "material type {m} is beyond the limit of {MAX_MATERIALS}"
            ));
        }
        if m > self.materials.len() {
            self.materials.resize(m, Material::default());
        }
        Ok(&mut self.materials[m - 1])
    }

    /// Material `m` has been given its elastic constants and density.
    pub fn material_defined(&self, m: usize) -> bool {
        m != 0 && m <= self.materials.len() && self.materials[m - 1] != Material::default()
    }

    /// `Density rho m`: the masses of the material's particles follow.
    pub fn set_density(&mut self, m: usize, rho: f64) -> Result<(), String> {
        self.material_entry(m)?.density = rho;
        let p = &mut self.particles;
        for i in 0..p.len() {
            if p.material[i] as usize == m {
                p.mass[i] = sphere_mass(rho, p.radius[i]);
            }
        }
        Ok(())
    }

    /// `YMD e m`.
    pub fn set_young(&mut self, m: usize, e: f64) -> Result<(), String> {
        self.material_entry(m)?.young = e;
        Ok(())
    }

    /// `PRA nu m`.
    pub fn set_poisson(&mut self, m: usize, nu: f64) -> Result<(), String> {
        self.material_entry(m)?.poisson = nu;
        Ok(())
    }

    /// `FRiction mu m`.
    pub fn set_friction(&mut self, m: usize, mu: f64) -> Result<(), String> {
        self.material_entry(m)?.friction = mu;
        Ok(())
    }

    /// `COHesion gamma m [base]`: surface energy per surface, and the one of contacts made
    /// after an impact (`VELocity ... 1`).
    pub fn set_cohesion(&mut self, m: usize, gamma: f64, base: f64) -> Result<(), String> {
        let mat = self.material_entry(m)?;
        mat.gamma = gamma;
        mat.gamma_base = base;
        self.contacts.mark_stale();
        Ok(())
    }

    /// `DAmping REStitution e [m]`: the restitution of material `m`, or of every material.
    pub fn set_restitution(&mut self, m: Option<usize>, e: f64) {
        match m {
            Some(m) => self.materials[m - 1].restitution = Some(e),
            None => self
                .materials
                .iter_mut()
                .for_each(|x| x.restitution = Some(e)),
        }
    }

    /// `DAmping` (Rayleigh) of particle–particle (`ball_ball`) or particle–wall contacts.
    pub fn set_rayleigh(&mut self, ball_ball: bool, r: Rayleigh) {
        if ball_ball {
            self.damping_pp = r;
        } else {
            self.damping_pw = r;
        }
    }

    /// `FRAction f` (`Some`), or `FRAction AUTO` (`None`: the step follows the fastest
    /// approach, worked out at the next `Cycle`).
    pub fn set_fraction(&mut self, f: Option<f64>) {
        match f {
            Some(f) => {
                self.settings.fraction = Some(f);
                self.settings.auto_step = None;
            }
            None => self.settings.auto_step = Some(0.0),
        }
    }

    /// `Window x1 x2 y1 y2 z1 z2`: the plots' window.
    pub fn set_window(&mut self, bounds: [f64; 6]) {
        self.settings.window = Some(bounds);
    }

    /// `2-D`: motion in the x–z plane only.
    pub fn set_two_d(&mut self) {
        self.settings.two_d = true;
    }

    /// A `SET` of the settings: the contacts are re-evaluated before the next step.
    pub fn edit_settings(&mut self, f: impl FnOnce(&mut Settings)) {
        let was_mdr = self.settings.tangential == TangentialChoice::Mdr;
        f(&mut self.settings);
        if was_mdr && self.settings.tangential != TangentialChoice::Mdr {
            // The spring rows of `SET TANgential MDR` stop following their contacts: drop
            // them, so that a contact that comes back to MDR starts from its force then
            // (`physics::mdr::MdrRow::holding`), not from a stale row.
            let drop_row = |s: &mut crate::sim::contacts::ContactState| {
                if let Some(e) = s.ext.as_deref_mut() {
                    e.mdr = None;
                }
                // A particle pair's row, kept in its block's list: the extension it stood
                // for stays, at its defaults (as a row in `ext.mdr` left it).
                if s.row.mdr().is_some() {
                    s.row = crate::sim::contacts::RowSlot::NONE;
                    s.ext_mut();
                }
            };
            self.contacts.for_each_state_mut(|_, s| drop_row(s));
            for c in self.contacts.wall_pairs.iter_mut() {
                drop_row(&mut c.s);
            }
        }
        if !self.settings.wall_bridges {
            // `SET WALlbridges OFF`: the wall bridges there are go (as `LIQuid 0` removes
            // all), their liquid back to the particle (conserving mode, once settled).
            for c in self.contacts.wall_pairs.iter_mut() {
                if let Some(b) = c.s.bridge.take()
                    && !b.fresh
                    && let Some(l) = self.particles.liquid.get_mut(c.i as usize)
                {
                    *l += b.share[0];
                }
            }
        }
        self.contacts.mark_stale();
    }

    /// `SET NORmal`, `SET ROLling`: the contact laws per material pair.
    pub fn edit_laws(&mut self, f: impl FnOnce(&mut ContactLaws)) {
        f(&mut self.laws);
        self.contacts.mark_stale();
    }

    /// `LIQuid`: the binder of every bridge; existing bridges take the new parameters (their
    /// rupture distance recomputed).
    pub fn set_liquid(&mut self, l: Liquid) {
        self.liquid = Some(l);
        crate::sim::liquid::reissue(self);
        self.contacts.mark_stale();
    }

    /// `LIQuid 0`: no binder; every bridge removed.
    pub fn remove_liquid(&mut self) {
        self.liquid = None;
        self.contacts.for_each_state_mut(|_, s| s.bridge = None);
        for c in self.contacts.wall_pairs.iter_mut() {
            c.s.bridge = None;
        }
    }

    /// `DWAll`: a new wall at rest in the given state, with capacity checked. Returns the
    /// periodic axes it opened (a plane wall across a periodic axis).
    pub fn add_wall(&mut self, wall: Wall) -> Result<[bool; 3], String> {
        if self.walls.len() >= self.nwall {
            return Err(format!(
                "too many walls: nwall = {} given to Start",
                self.nwall
            ));
        }
        self.walls.push(wall);
        self.contacts.mark_stale();
        Ok(self.open_crossed_axes())
    }

    /// `AWAll n`: wall `n` (1-based, checked by the caller) changed by `f`. Returns the
    /// periodic axes it opened.
    pub fn edit_wall(&mut self, n: usize, f: impl FnOnce(&mut Wall)) -> [bool; 3] {
        f(&mut self.walls[n - 1]);
        self.contacts.mark_stale();
        self.open_crossed_axes()
    }

    /// Opens every periodic axis that a plane wall crosses (doc/limits.md, "Walls and
    /// periodic axes").
    fn open_crossed_axes(&mut self) -> [bool; 3] {
        crate::sim::walls::open_crossed(&self.walls, &mut self.settings.periodic)
    }

    /// `GRID`: the cell's strain rates.
    pub fn set_strain_rates(&mut self, rates: [f64; 6]) {
        self.cell.rate = rates;
    }

    /// `GAIN g edmax`: the stress servo's gain and largest strain rate.
    pub fn set_servo_gain(&mut self, g: f64, edmax: f64) {
        self.cell.gain = [g, edmax];
    }

    /// `Mode n`: the stress servo's mode (0 or 1, checked by the caller).
    pub fn set_servo_mode(&mut self, n: u8) {
        self.cell.mode = n;
    }

    /// The stress servo of the `Cycle` about to run; `None` after it, which keeps the servo
    /// the Cycle ended with for the next one (`Carried::servo`, [`Scene::continued_servo`]).
    pub fn set_servo(&mut self, servo: Option<super::cell::Servo>) {
        if servo.is_none()
            && let Some(ended) = self.derived.servo.take()
        {
            self.carried.servo = Some(super::KeptServo::of(ended, &self.cell));
        }
        self.derived.servo = servo;
    }

    /// The servo a `Cycle` with `targets` goes on with: the one the last Cycle ended with,
    /// if it held the same targets and no command changed the cell's rates, gain or mode
    /// since (its base rates, the axes it adjusts and its hunting count then run on as in
    /// one longer Cycle); `None`: the Cycle starts a servo of its own.
    pub fn continued_servo(
        &self,
        targets: &[(super::cell::StressTarget, f64)],
    ) -> Option<super::cell::Servo> {
        let kept = self.carried.servo.as_ref()?;
        kept.continues(targets, &self.cell)
            .then(|| kept.servo.clone())
    }

    /// What the last `Cycle` had to tell that is not an error; the list is emptied.
    pub fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.derived.notes)
    }

    /// Forgets the overlap index of a run of `CReate` commands (any other command).
    pub fn end_create_run(&mut self) {
        self.derived.create_index = None;
    }

    /// Forgets the lattice of the last `AGEnerate` (any other command).
    pub fn end_lattice_run(&mut self) {
        self.derived.lattice_run = None;
    }

    /// Runs a command's change `f` and books the kinetic energy it adds or removes (new
    /// particles, `VELocity`, `Zero`, ...) in the ledger; strain energy of new overlaps is
    /// booked when the next Cycle evaluates the contacts (`cycle::prime`). A `CReate`
    /// (`create`) appends one particle: the total after it is the total before plus its
    /// term, the same bits as the sum over all (`energy::kinetic_of`), and a run of `CReate`s
    /// keeps the total between them (`scene::CreateIndex`). `f` must change nothing when
    /// it fails.
    ///
    /// The kinetic energy is that of the half-step velocities; the energy of the scene at
    /// the step holds also the work in flight, `½Δt Σ (F·v + M·ω)` with the last step's
    /// forces (`cycle::in_flight`). A command that changes velocities (or removes particles)
    /// while forces act changes that work too, by `½Δt Σ (F·Δv + M·Δω)`: it is booked as
    /// the command's (and carried in `Carried::in_flight_end`), so that a `VELocity` inside a
    /// contact leaves the books closed (`hard_cases`,
    /// `a_velocity_set_inside_a_contact_is_booked_with_its_work_in_flight`).
    pub fn booked_edit<T>(
        &mut self,
        create: bool,
        f: impl FnOnce(&mut Scene) -> Result<T, String>,
    ) -> Result<T, String> {
        use crate::sim::energy;
        let n0 = self.particles.len();
        let before = match &self.derived.create_index {
            Some(c) if create && c.n == n0 => c.kinetic,
            _ => None,
        }
        .unwrap_or_else(|| energy::kinetic(self));
        let power_before = if create { 0.0 } else { self.force_power() };
        let out = f(self)?;
        if !create {
            self.book_flight_change(self.force_power() - power_before);
        }
        let after = if create {
            let after = before + energy::kinetic_of(self, n0);
            if let Some(c) = self.derived.create_index.as_mut() {
                c.kinetic = Some(after);
            }
            after
        } else {
            energy::kinetic(self)
        };
        self.ledger.commands += after - before;
        Ok(out)
    }

    /// `Σ (F·v + M·ω)` with the forces the last step left (0 for a new scene): twice the
    /// work in flight over Δt (`cycle::in_flight`).
    pub(in crate::sim) fn force_power(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| p.force[i].dot(&p.vel[i]) + p.moment[i].dot(&p.spin[i]))
            .sum()
    }

    /// Books `½Δt · d_power`, the change of the work in flight a command made
    /// ([`Scene::booked_edit`]), with the step the last Cycle's forces were made with, the one
    /// `cycle::in_flight` used: under `FRAction AUTO` the step kept since its last rebuild,
    /// else the FRAction step (`params::build`; a FRAction changed between that Cycle and the
    /// command is taken as the step).
    fn book_flight_change(&mut self, d_power: f64) {
        if d_power == 0.0 || !d_power.is_finite() {
            return;
        }
        if let Ok(model) = crate::sim::params::build(self) {
            let dt = match self.settings.auto_step {
                Some(kept) if kept > 0.0 => kept,
                _ => model.dt,
            };
            let w = 0.5 * dt * d_power;
            if w.is_finite() {
                self.ledger.commands += w;
                if self.carried.in_flight_end != 0.0 {
                    self.carried.in_flight_end += w;
                }
            }
        }
    }

    /// `PLot SAve`: the reference state for displacement and bond plots. Contacts of a scene
    /// that changed since the last cycle are evaluated first, so that the reference holds
    /// its bonds.
    pub fn take_reference(&mut self) {
        crate::sim::cycle::prime_if_stale(self);
        self.reference = Some(super::Reference::take(self));
    }

    /// Frees the spare capacity of the particle arrays (a decoded checkpoint's arrays grew by
    /// doubling).
    pub fn shrink_to_fit(&mut self) {
        self.particles.shrink_to_fit();
    }

    /// After a checkpoint was read: the energy audit measures from the residual the state
    /// holds (a checkpoint of format 8 or older does not say what commands left: all of its
    /// residual is taken as theirs).
    pub fn resume_audit(&mut self) {
        let r = crate::sim::energy::residual(self);
        if self.ledger.unbooked.is_nan() {
            self.ledger.unbooked = r;
        }
        if self.carried.audit_end.is_nan() {
            self.carried.audit_end = r;
        }
    }

    /// Pads history rows of an older checkpoint to the current columns (the missing ones
    /// read as 0).
    pub fn pad_history_rows(&mut self) {
        for row in &mut self.history.rows {
            row.resize(crate::sim::history::COLUMNS.len(), 0.0);
        }
    }
}

/// `Fix`, `FMM`, `FRO`, `GRAvity`, `CGRavity`, `VELocity`, `VMU`, `Zero`, `RESet`: the
/// particles' motion.
impl Scene {
    /// `Fix`: the fixed degrees of freedom (bit k for x y z rx ry rz) of particle index `i`,
    /// or of every particle.
    pub fn fix(&mut self, bits: u8, i: Option<usize>) {
        match i {
            Some(i) => self.particles.fixed[i] = bits,
            None => self.particles.fixed.iter_mut().for_each(|f| *f = bits),
        }
    }

    /// `FMM r`: the mass multiplier scaled by `r`.
    pub fn scale_fmm(&mut self, r: f64) {
        self.fmm *= r;
    }

    /// `FRO`: every spin zeroed.
    pub fn stop_spins(&mut self) {
        self.particles
            .spin
            .iter_mut()
            .for_each(|w| *w = Vec3::zeros());
    }

    /// `GRAvity gx gy gz`.
    pub fn set_gravity(&mut self, g: [f64; 3]) {
        self.gravity = g;
    }

    /// `CGRavity nagg g`: centripetal gravity towards agglomerate region `nagg` (1 or 2).
    pub fn set_cgravity(&mut self, nagg: usize, g: f64) -> Result<(), String> {
        if self.regions[nagg - 1].is_none() {
            return Err(format!("agglomerate region {nagg} is not defined"));
        }
        self.cgravity[nagg - 1] = g;
        Ok(())
    }

    /// `VELocity v1 [v2] [ivd]`: the velocity of every particle of agglomerate 1 (and 2);
    /// `ivd`: contacts made from now on take the materials' `gamma_base`.
    pub fn set_agglomerate_velocity(
        &mut self,
        v1: [f64; 3],
        v2: Option<[f64; 3]>,
        ivd: bool,
    ) -> Result<(), String> {
        let p = &mut self.particles;
        if p.agg.iter().all(|&a| a != 1) {
            return Err("agglomerate 1 has no particles".into());
        }
        if v2.is_some() && p.agg.iter().all(|&a| a != 2) {
            return Err("agglomerate 2 has no particles".into());
        }
        for i in 0..p.len() {
            match (p.agg[i], v2) {
                (1, _) => p.vel[i] = Vec3::from(v1),
                (2, Some(v)) => p.vel[i] = Vec3::from(v),
                _ => {}
            }
        }
        self.impact = ivd;
        Ok(())
    }

    /// `VMU r`: the prescribed (fixed) velocity and spin components scaled by `r`.
    pub fn scale_fixed_velocities(&mut self, r: f64) {
        let p = &mut self.particles;
        for i in 0..p.len() {
            for k in 0..3 {
                if p.fixed[i] & (1 << k) != 0 {
                    p.vel[i][k] *= r;
                }
                if p.fixed[i] & (8 << k) != 0 {
                    p.spin[i][k] *= r;
                }
            }
        }
    }

    /// `Zero [1]`: velocities and spins zeroed (at every step with `always`).
    pub fn zero_velocities(&mut self, always: bool) {
        self.particles
            .vel
            .iter_mut()
            .for_each(|v| *v = Vec3::zeros());
        self.particles
            .spin
            .iter_mut()
            .for_each(|v| *v = Vec3::zeros());
        self.zero_always = always;
    }

    /// `RESet`: the accumulated rotations zeroed.
    pub fn reset_rotations(&mut self) {
        self.particles
            .rot
            .iter_mut()
            .for_each(|v| *v = Vec3::zeros());
    }
}

/// `Fix`, `VELocity` and `PROPerty` over a range (doc/groups.md): the particles of index
/// `members` (from [`Scene::members`]).
impl Scene {
    /// `Fix ... range`: the fixed degrees of freedom of the members.
    pub fn fix_members(&mut self, bits: u8, members: &[usize]) {
        for &i in members {
            self.particles.fixed[i] = bits;
        }
    }

    /// `PROPerty VELocity` / `VELocity vx vy vz range`.
    pub fn set_velocity_of(&mut self, members: &[usize], v: [f64; 3]) {
        for &i in members {
            self.particles.vel[i] = Vec3::from(v);
        }
    }

    /// `PROPerty SPIn`.
    pub fn set_spin_of(&mut self, members: &[usize], w: [f64; 3]) {
        for &i in members {
            self.particles.spin[i] = Vec3::from(w);
        }
    }

    /// `PROPerty MATerial m`: the members take material `m` (defined: the caller checks),
    /// their masses its density; the contacts see new constants.
    pub fn set_material_of(&mut self, members: &[usize], m: usize) {
        let rho = self.materials[m - 1].density;
        let p = &mut self.particles;
        for &i in members {
            p.material[i] = m as u16;
            p.mass[i] = sphere_mass(rho, p.radius[i]);
        }
        self.contacts.mark_stale();
    }
}

/// Whole arrays set by a library caller (the Python module, `session::arrays`): checked
/// whole before anything changes, as a command's input is.
impl Scene {
    /// Every particle's position (in the order of [`Scene::particles`]): each finite and in
    /// the work-space as `CReate` places one (an open side at least a radius away, a periodic
    /// axis in [0, L)), and none behind a wall. Contacts are re-made at the next `Cycle`
    /// (the store marked stale, as `MOve` does), which books the strain energy of the
    /// overlaps as it finds them (`cycle::prime`); the kinetic energy does not change.
    pub fn set_positions(&mut self, pos: &[[f64; 3]]) -> Result<(), String> {
        self.check_rows(pos.len(), "positions")?;
        for (i, x) in pos.iter().enumerate() {
            let v = Vec3::from(*x);
            let r = self.particles.radius[i];
            if !x.iter().all(|c| c.is_finite()) {
                return Err(format!(
                    "position of particle {} (row {i}) is not finite: {x:?}",
                    self.particles.id[i]
                ));
            }
            if !crate::sim::generate::inside(self, None, &v, r) {
                return Err(format!(
                    "position of particle {} (row {i}) ({:.6e}, {:.6e}, {:.6e}) is outside the work-space {:?} (its radius {r:.4e} from an open side; a periodic axis takes 0 <= x < L)",
                    self.particles.id[i], x[0], x[1], x[2], self.size
                ));
            }
            if self.settings.two_d && x[2] != self.particles.pos[i].z {
                return Err(format!(
                    "position of particle {} (row {i}): a 2-D scene keeps z (it was {:e}, the array has {:e})",
                    self.particles.id[i], self.particles.pos[i].z, x[2]
                ));
            }
        }
        let new: Vec<Vec3> = pos.iter().map(|x| Vec3::from(*x)).collect();
        let old = std::mem::replace(&mut self.particles.pos, new);
        if let Some(m) = crate::sim::cycle::behind_a_wall(self) {
            self.particles.pos = old;
            return Err(format!("positions refused: {m}"));
        }
        self.contacts.mark_stale();
        Ok(())
    }

    /// Every particle's velocity (the stored one: in a deforming cell relative to the mean
    /// field, as `PRint Balls` shows it), each finite; a 2-D scene's z velocities 0. The
    /// caller books the kinetic energy (`Scene::booked_edit`), as for `VELocity`.
    pub fn set_velocities(&mut self, vel: &[[f64; 3]]) -> Result<(), String> {
        self.check_rows(vel.len(), "velocities")?;
        for (i, v) in vel.iter().enumerate() {
            if !v.iter().all(|c| c.is_finite()) {
                return Err(format!(
                    "velocity of particle {} (row {i}) is not finite: {v:?}",
                    self.particles.id[i]
                ));
            }
            if self.settings.two_d && v[2] != 0.0 {
                return Err(format!(
                    "velocity of particle {} (row {i}): a 2-D scene has no z velocity (the array has {:e})",
                    self.particles.id[i], v[2]
                ));
            }
        }
        for (dst, v) in self.particles.vel.iter_mut().zip(vel) {
            *dst = Vec3::from(*v);
        }
        Ok(())
    }

    fn check_rows(&self, rows: usize, what: &str) -> Result<(), String> {
        let n = self.particles.len();
        if rows != n {
            return Err(format!(
                "{what}: the array has {rows} rows, the scene {n} particles (one row each, in the order of the particle arrays)"
            ));
        }
        Ok(())
    }
}
