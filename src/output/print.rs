//! `PRint` items: each has a human table and a JSON object (names documented in
//! doc/output.md). JSON numbers are written by serde_json, which prints the shortest decimal
//! that reads back to the same f64 (exact round trip).

use serde_json::{Value, json};

use crate::analysis;
use crate::lang::command::{ContactsFilter, PrintItem, WallGeom};
use crate::sim::contacts::ContactState;
use crate::sim::model::{ContactLaws, NormalLaw, Pairs, TangentialChoice};
use crate::sim::scene::Scene;
use crate::sim::{cycle, energy, params, search};

fn v3(v: &crate::sim::Vec3) -> Value {
    json!([v.x, v.y, v.z])
}

fn in_window(scene: &Scene, x: &crate::sim::Vec3) -> bool {
    match scene.settings().window {
        None => true,
        Some(w) => {
            w[0] <= x.x && x.x <= w[1] && w[2] <= x.y && x.y <= w[3] && w[4] <= x.z && x.z <= w[5]
        }
    }
}

/// The time step the next `Cycle` would use (0 when it cannot run).
pub fn current_dt(scene: &Scene) -> f64 {
    crate::sim::cycle::next_step(scene)
}

/// Produces (human text, JSON object) for one item.
pub fn item(scene: &Scene, it: PrintItem) -> (String, Value) {
    match it {
        PrintItem::Info => info(scene),
        PrintItem::Balls => balls(scene),
        PrintItem::Contacts(f) => contacts(scene, f),
        PrintItem::Energy => energy_item(scene),
        PrintItem::Entries | PrintItem::Map => entries(scene, it == PrintItem::Map),
        PrintItem::Stress => stress(scene),
        PrintItem::Settings => settings(scene),
        PrintItem::Walls => walls(scene),
        PrintItem::Chist => chist(scene),
        PrintItem::Grid => grid(scene),
        PrintItem::Partitions => partitions(scene),
        PrintItem::Bonds => analysis::bonds_item(scene),
        PrintItem::Clusters => analysis::clusters_item(scene),
        PrintItem::History => history(scene),
        // (Read through `output::groups`, with the command's range.)
        PrintItem::Range => (String::new(), json!({"print": "range"})),
    }
}

fn info(scene: &Scene) -> (String, Value) {
    let dt = current_dt(scene);
    // Touching pairs (`sim::scene::touch`, the definition of every output), and of those
    // the solid contacts whose law acts (the contact states of the last Cycle).
    let (c, cw) = scene.touching_counts();
    let (ac, acw) = scene.contacts().active_counts();
    let (b, bw) = scene.contacts().bridge_counts();
    let (mut bc, mut bt) = (0, 0);
    for p in scene.contacts().iter() {
        if let Some(br) = &p.s.bridge {
            if br.gap <= 0.0 { bc += 1 } else { bt += 1 }
        }
    }
    let active = if scene.contacts_current() {
        format!("{ac} and {acw} of them with the contact law acting")
    } else {
        "forces not evaluated since the scene changed".to_string()
    };
    let mut s = format!(
        "cycle {}  time {:.6e} s  dt {}\nballs {} (capacity {}, lost through open sides or walls crossed {})  walls {}\n\
         contacts {} particle-particle, {} particle-wall  (touching: in contact or within {:e} of the smaller radius; {active}; {} candidate pairs)\n",
        scene.cycle(),
        scene.time(),
        dt_text(scene, dt),
        scene.particles().len(),
        scene.nball(),
        scene.lost(),
        scene.walls().len(),
        c,
        cw,
        crate::sim::scene::touch::TOUCH_GAP,
        scene.contacts().len(),
    );
    let (free, in_bridges) = crate::sim::liquid::total_liquid(scene);
    if scene.liquid().is_some() {
        s.push_str(&format!(
            "liquid bridges {b} particle-particle ({bc} compressive, {bt} tensile), {bw} particle-wall\n\
             liquid {:.6e} m^3 in bridges, {:.6e} m^3 on particles, total {:.6e} m^3\n",
            in_bridges,
            free,
            in_bridges + free
        ));
    }
    for (k, w) in scene.walls().iter().enumerate() {
        s.push_str(&format!(
            "wall {}: {}  normal force {:.6e} N\n",
            k + 1,
            geom_text(&w.geom),
            w.normal_force
        ));
    }
    let j = json!({
        "print": "info", "cycle": scene.cycle(), "time": scene.time(), "dt": dt,
        "balls": scene.particles().len(), "walls": scene.walls().len(), "contacts": c,
        "wall_contacts": cw, "touching": c, "active_contacts": ac, "active_wall_contacts": acw,
        "bridges": b, "wall_bridges": bw,
        "bridges_compressive": bc, "bridges_tensile": bt, "lost": scene.lost(),
        "liquid_bridges": in_bridges, "liquid_free": free, "liquid_total": in_bridges + free,
        "wall_forces": scene.walls().iter().map(|w| w.normal_force).collect::<Vec<_>>(),
    });
    (s, j)
}

/// The time step for `PRint Info`, or what it still waits for.
fn dt_text(scene: &Scene, dt: f64) -> String {
    let model = params::build(scene).ok();
    let heavy = model.as_ref().map_or(1.0, |m| m.heavy_share);
    let elastic = model.as_ref().is_some_and(|m| m.elastic_default);
    if dt.is_finite() && dt > 0.0 && elastic {
        format!(
            "{dt:.6e} s (FRAction {}: the scene dissipates nothing, and its energy holds 1e-3 over 10^7 steps at this step, doc/limits.md)",
            crate::sim::scene::DEFAULT_FRACTION_ELASTIC
        )
    } else if dt.is_finite() && dt > 0.0 && heavy < 1.0 {
        format!(
            "{dt:.6e} s (the default FRAction times {heavy:.4}: a pair's restitution is below {}, doc/limits.md)",
            crate::physics::dashpot::HEAVY_E
        )
    } else if dt.is_finite() && dt > 0.0 {
        format!("{dt:.6e} s")
    } else if scene.particles().is_empty() {
        "not yet known (no particles)".to_string()
    } else {
        "not yet known (a material property is missing: the first Cycle names it)".to_string()
    }
}

fn geom_text(g: &WallGeom) -> String {
    match g {
        WallGeom::Plane { normal, d } => {
            format!(
                "plane {}x + {}y + {}z = {}",
                normal[0], normal[1], normal[2], d
            )
        }
        WallGeom::Sphere { centre, radius } => format!(
            "sphere container centre ({}, {}, {}) radius {}",
            centre[0], centre[1], centre[2], radius
        ),
        WallGeom::Obstacle { centre, radius } => format!(
            "sphere obstacle centre ({}, {}, {}) radius {}",
            centre[0], centre[1], centre[2], radius
        ),
        WallGeom::Cylinder {
            point,
            axis,
            radius,
        } => format!(
            "cylinder (particles inside) axis through ({}, {}, {}) along ({}, {}, {}) radius {}",
            point[0], point[1], point[2], axis[0], axis[1], axis[2], radius
        ),
    }
}

fn balls(scene: &Scene) -> (String, Value) {
    let p = &scene.particles();
    let mut s = format!(
        "{:>7} {:>13} {:>13} {:>13} {:>13} {:>13} {:>13} {:>11} {:>3} {:>3} {:>3}\n",
        "id", "x", "y", "z", "vx", "vy", "vz", "radius", "siz", "mat", "agg"
    );
    let mut arr = Vec::new();
    for i in 0..p.len() {
        if !in_window(scene, &p.pos[i]) {
            continue;
        }
        s.push_str(&format!(
            "{:>7} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>11.4e} {:>3} {:>3} {:>3}\n",
            p.id[i], p.pos[i].x, p.pos[i].y, p.pos[i].z, p.vel[i].x, p.vel[i].y, p.vel[i].z,
            p.radius[i], p.size[i], p.material[i], p.agg[i]
        ));
        arr.push(json!({
            "id": p.id[i], "pos": v3(&p.pos[i]), "vel": v3(&p.vel[i]), "spin": v3(&p.spin[i]),
            "radius": p.radius[i], "size": p.size[i], "material": p.material[i],
            "agglomerate": p.agg[i], "force": v3(&p.force[i]),
        }));
    }
    // In a deforming cell the stored velocities are relative to the mean field (`sim::cell`).
    let relative = scene.cell().in_use();
    if relative {
        s.push_str("(velocities relative to the mean field of the cell's GRID, C = c - G x)\n");
    }
    let j = json!({"print": "balls", "cycle": scene.cycle(), "time": scene.time(), "balls": arr,
        "velocity": if relative { "relative to the mean field" } else { "total" }});
    (s, j)
}

/// One contact's JSON object: `overlap` ([`shown_overlap`]), `touching` (`sim::scene::touch`), `active` (the contact
/// law acts).
fn contact_json(s: &ContactState, overlap: f64, touching: bool) -> Value {
    let mut v = json!({
        "overlap": overlap, "normal_force": s.normal_force + s.damp_force,
        "tangential_force": s.tforce.norm(), "touching": touching, "active": s.touching,
        "contact_radius": s.a,
    });
    if let Some(b) = &s.bridge {
        v["bridge"] = json!({
            "volume": b.volume, "rupture_distance": b.s_c, "static_force": b.f_static,
            "viscous_force": b.f_visc, "half_filling_angle": b.phi(), "gap": b.gap,
        });
    }
    v
}

/// A contact's overlap for the table: the last step's while the contact law or a bridge
/// acts, else from the positions now (negative: the gap).
fn shown_overlap(s: &ContactState, gap: f64) -> f64 {
    if s.touching || s.bridge.is_some() {
        s.overlap
    } else {
        -gap
    }
}

fn contacts(scene: &Scene, f: ContactsFilter) -> (String, Value) {
    if f != ContactsFilter::All && !scene.contacts_current() {
        return contacts_by_gap(scene, f);
    }
    let p = &scene.particles();
    let mut s = format!(
        "{:>7} {:>7} {:>13} {:>13} {:>13} {:>13}\n",
        "a", "b", "overlap", "normal_force", "tang_force", "bridge_force"
    );
    let mut arr = Vec::new();
    for c in scene.contacts().iter() {
        let (i, j) = (c.i as usize, c.j as usize);
        let touching = scene.pair_touches(c.s, i, j);
        let keep = f == ContactsFilter::All || touching || c.s.bridge.is_some();
        if !keep || !in_window(scene, &p.pos[i]) {
            continue;
        }
        let overlap = shown_overlap(c.s, scene.pair_gap(i, j));
        let bf = c.s.bridge.as_ref().map_or(0.0, |b| b.f_visc - b.f_static);
        if f == ContactsFilter::Gap {
            s.push_str(&format!(
                "{:>7} {:>7} {:>13.6e} {:>13.6e}\n",
                c.ida, c.idb, overlap, c.s.normal_force
            ));
        } else {
            s.push_str(&format!(
                "{:>7} {:>7} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e}\n",
                c.ida,
                c.idb,
                overlap,
                c.s.normal_force + c.s.damp_force,
                c.s.tforce.norm(),
                bf
            ));
        }
        let mut v = contact_json(c.s, overlap, touching);
        v["a"] = json!(c.ida);
        v["b"] = json!(c.idb);
        arr.push(v);
    }
    for c in scene.contacts().wall_pairs() {
        let (i, w) = (c.i as usize, c.wall as usize);
        let touching = scene.wall_touches(&c.s, i, w);
        let keep = f == ContactsFilter::All || touching || c.s.bridge.is_some();
        if !keep || !in_window(scene, &p.pos[i]) {
            continue;
        }
        let overlap = shown_overlap(&c.s, scene.wall_gap(i, w));
        s.push_str(&format!(
            "{:>7} {:>7} {:>13.6e} {:>13.6e} {:>13.6e}\n",
            c.id,
            format!("W{}", c.wall + 1),
            overlap,
            c.s.normal_force + c.s.damp_force,
            c.s.tforce.norm()
        ));
        let mut v = contact_json(&c.s, overlap, touching);
        v["a"] = json!(c.id);
        v["wall"] = json!(c.wall + 1);
        arr.push(v);
    }
    if !scene.contacts_current() {
        s.push_str("(the candidate pairs of the last Cycle: commands changed the scene since; the next Cycle evaluates them again)\n");
    }
    let j = json!({"print": "contacts", "cycle": scene.cycle(), "contacts": arr,
        "evaluated": scene.contacts_current()});
    (s, j)
}

/// `PRint Contacts` of a scene that commands changed since the last Cycle: the pairs that
/// touch by their positions now (`sim::scene::touch`), without forces (the next Cycle
/// evaluates them).
fn contacts_by_gap(scene: &Scene, f: ContactsFilter) -> (String, Value) {
    let p = &scene.particles();
    let (pairs, walls) = scene.touching_by_gap();
    let mut s = if f == ContactsFilter::Gap {
        format!(
            "{:>7} {:>7} {:>13} {:>13}\n",
            "a", "b", "overlap", "normal_force"
        )
    } else {
        format!(
            "{:>7} {:>7} {:>13} {:>13} {:>13} {:>13}\n",
            "a", "b", "overlap", "normal_force", "tang_force", "bridge_force"
        )
    };
    let none = ContactState::default();
    let mut arr = Vec::new();
    let row = |a: String, b: String, overlap: f64, s: &mut String| {
        let zeros = if f == ContactsFilter::Gap { 1 } else { 3 };
        s.push_str(&format!("{a:>7} {b:>7} {overlap:>13.6e}"));
        for _ in 0..zeros {
            s.push_str(&format!(" {:>13.6e}", 0.0));
        }
        s.push('\n');
    };
    for (i, j) in pairs {
        if !in_window(scene, &p.pos[i]) {
            continue;
        }
        let overlap = -scene.pair_gap(i, j);
        row(p.id[i].to_string(), p.id[j].to_string(), overlap, &mut s);
        let mut v = contact_json(&none, overlap, true);
        v["a"] = json!(p.id[i]);
        v["b"] = json!(p.id[j]);
        arr.push(v);
    }
    for (i, w) in walls {
        if !in_window(scene, &p.pos[i]) {
            continue;
        }
        let overlap = -scene.wall_gap(i, w);
        row(p.id[i].to_string(), format!("W{}", w + 1), overlap, &mut s);
        let mut v = contact_json(&none, overlap, true);
        v["a"] = json!(p.id[i]);
        v["wall"] = json!(w + 1);
        arr.push(v);
    }
    s.push_str("(touching by the positions now: commands changed the scene since the last Cycle, which evaluates the forces)\n");
    let j = json!({"print": "contacts", "cycle": scene.cycle(), "contacts": arr,
        "evaluated": false});
    (s, j)
}

fn energy_item(scene: &Scene) -> (String, Value) {
    let st = energy::stored(scene);
    let l = &scene.ledger();
    let res = energy::residual(scene);
    let input = l.input() + scene.cell().work;
    let frac = |x: f64| if input != 0.0 { x / input } else { 0.0 };
    // The periodic cell's work (`sim::cell`), shown once a GRID or servo has deformed it.
    let cell = if scene.cell().work != 0.0 {
        format!("  cell {:.6e}", scene.cell().work)
    } else {
        String::new()
    };
    let s = format!(
        "energy (J) at cycle {}\n  kinetic        translation {:.6e}  rotation {:.6e}\n  \
         stored         normal {:.6e}  tangential {:.6e}  bridges {:.6e}\n  \
         input          commands {:.6e}  gravity {:.6e}  walls {:.6e}{cell}  total {:.6e}\n  \
         dissipated     friction {:.6e}  mass damping {:.6e}  contact damping {:.6e}\n                 \
         viscous {:.6e}  adhesion {:.6e}  rupture {:.6e}  total {:.6e}\n  \
         residual       {:.6e} (stored - input + dissipated)\n",
        scene.cycle(),
        st.kinetic_translation,
        st.kinetic_rotation,
        st.strain_normal,
        st.strain_tangential,
        st.bridge,
        l.commands,
        l.gravity,
        l.walls,
        input,
        l.friction,
        l.damping_mass,
        l.damping_contact,
        l.viscous,
        l.adhesion,
        l.rupture,
        l.dissipated(),
        res
    );
    let j = json!({
        "print": "energy", "cycle": scene.cycle(), "time": scene.time(),
        "kinetic": st.kinetic_translation + st.kinetic_rotation,
        "kinetic_translation": st.kinetic_translation, "kinetic_rotation": st.kinetic_rotation,
        "strain": st.strain_normal + st.strain_tangential,
        "strain_normal": st.strain_normal, "strain_tangential": st.strain_tangential,
        "bridge": st.bridge,
        "input": input,
        "inputs": {"commands": l.commands, "gravity": l.gravity, "walls": l.walls,
            "cell": scene.cell().work},
        "dissipated": {
            "friction": l.friction, "damping_mass": l.damping_mass,
            "damping_contact": l.damping_contact, "viscous": l.viscous,
            "adhesion": l.adhesion, "rupture": l.rupture, "total": l.dissipated(),
        },
        "residual": res,
        "fractions": {
            "friction": frac(l.friction), "damping_mass": frac(l.damping_mass),
            "damping_contact": frac(l.damping_contact), "viscous": frac(l.viscous),
            "adhesion": frac(l.adhesion), "rupture": frac(l.rupture),
        },
    });
    (s, j)
}

fn entries(scene: &Scene, map: bool) -> (String, Value) {
    let (tol, xres) = match params::build(scene) {
        Ok(m) => cycle::search_distances(scene, &m),
        Err(_) => (0.0, 0.0),
    };
    let (pairs, walls, g) = search::candidates(scene, tol.max(0.0));
    let s = format!(
        "grid {} x {} x {} boxes of {:.4e} x {:.4e} x {:.4e} m; {} box entries, at most {} in a box, {} empty boxes\n\
         TOL {:.4e} m, XRES {:.4e} m; {} candidate pairs, {} particle-wall candidates; {} rebuilds so far\n",
        g.n[0],
        g.n[1],
        g.n[2],
        g.cell[0],
        g.cell[1],
        g.cell[2],
        g.entries,
        g.max_entries_per_box,
        g.empty_boxes,
        tol,
        xres,
        pairs.len(),
        walls.len(),
        scene.contacts().rebuilds()
    );
    // The list in use may have been made with a larger TOL (automatic TOL, fast particles:
    // cycle::rebuild_tol).
    let list_tol = scene.contacts().tol();
    let s = if list_tol > tol && scene.contacts().rebuilds() > 0 {
        format!(
            "{s}the candidate list in use was made with TOL {:.4e} m, XRES {:.4e} m (grown for fast particles)\n",
            list_tol,
            cycle::xres_of(list_tol)
        )
    } else {
        s
    };
    let j = json!({
        "print": if map { "map" } else { "entries" }, "boxes": g.n, "box_size": g.cell,
        "entries": g.entries, "max_entries_per_box": g.max_entries_per_box,
        "empty_boxes": g.empty_boxes, "tol": tol, "xres": xres,
        "candidate_pairs": pairs.len(), "wall_candidates": walls.len(),
        "rebuilds": scene.contacts().rebuilds(), "list_tol": list_tol,
    });
    (s, j)
}

fn stress(scene: &Scene) -> (String, Value) {
    let st = crate::sim::stress::of(scene);
    let total = st.total();
    let angle = crate::sim::cell::principal_angle(&total);
    let matrix = |name: &str, m: &[[f64; 3]; 3]| {
        format!(
            "  {name:<8} {:>13.6e} {:>13.6e} {:>13.6e}\n  {:8} {:>13.6e} {:>13.6e} {:>13.6e}\n  {:8} {:>13.6e} {:>13.6e} {:>13.6e}\n",
            m[0][0], m[0][1], m[0][2], "", m[1][0], m[1][1], m[1][2], "", m[2][0], m[2][1], m[2][2]
        )
    };
    let mut s = format!(
        "average stress (Pa, compression positive; row: force component, column: branch component), mean {:.6e}, major principal stress in x-y at {:.3} deg from x\n{}{}{}",
        st.mean(),
        angle,
        matrix("total", &total),
        matrix("contact", &st.contact),
        matrix("kinetic", &st.kinetic),
    );
    let mut j = json!({"print": "stress", "cycle": scene.cycle(), "stress": total,
        "contact": st.contact, "kinetic": st.kinetic, "mean": st.mean(),
        "angle_xy": angle, "temperature": crate::sim::stress::temperature(scene)});
    // With a Window: the stress in that bin (Pasha 2013 (5.1)-(5.3)).
    if let Some(b) = scene.settings().window {
        let (bs, count) = crate::sim::stress::in_box(scene, &b);
        let bt = bs.total();
        let dev = crate::sim::stress::deviatoric_pasha(&bt);
        s.push_str(&format!(
            "stress in the window (the {count} particles whose centre is in it, all their contacts, walls included; Pasha 2013 (5.1)), hydrostatic {:.6e}, deviatoric (5.3) {:.6e}\n{}{}{}",
            bs.mean(),
            dev,
            matrix("total", &bt),
            matrix("contact", &bs.contact),
            matrix("kinetic", &bs.kinetic),
        ));
        j["window"] = json!({"bounds": b, "particles": count, "stress": bt,
            "contact": bs.contact, "kinetic": bs.kinetic, "hydrostatic": bs.mean(),
            "deviatoric": dev});
    }
    (s, j)
}

fn partitions(scene: &Scene) -> (String, Value) {
    // Contributions of compressive solid contacts, tensile solid contacts and bridges to the
    // mean stress.
    let p = &scene.particles();
    let vol = scene.size()[0] * scene.size()[1] * scene.size()[2];
    let (mut comp, mut tens, mut brid) = (0.0, 0.0, 0.0);
    for c in scene.contacts().iter() {
        let l = scene
            .branch(&p.pos[c.i as usize], &p.pos[c.j as usize])
            .norm();
        if c.s.touching {
            let f = c.s.normal_force + c.s.damp_force;
            if f >= 0.0 {
                comp += f * l
            } else {
                tens += f * l
            }
        }
        if let Some(b) = &c.s.bridge {
            brid += (b.f_visc - b.f_static) * l;
        }
    }
    let k = 1.0 / (3.0 * vol);
    let s = format!(
        "mean-stress partitions (Pa): compressive contacts {:.6e}, tensile contacts {:.6e}, liquid bridges {:.6e}\n",
        comp * k,
        tens * k,
        brid * k
    );
    (
        s,
        json!({"print": "partitions", "compressive": comp * k, "tensile": tens * k, "bridges": brid * k}),
    )
}

/// The tangential law as `SET TANgential` names it.
fn tangential_name(t: TangentialChoice) -> &'static str {
    match t {
        TangentialChoice::Md => "Md",
        TangentialChoice::NoSlip => "NoSlip",
        TangentialChoice::Walton => "Walton",
        TangentialChoice::HertzMindlin => "HM",
        TangentialChoice::Mdr => "MDR",
    }
}

fn settings(scene: &Scene) -> (String, Value) {
    let st = &scene.settings();
    let (tol, xres) = match params::build(scene) {
        Ok(m) => cycle::search_distances(scene, &m),
        Err(_) => (0.0, 0.0),
    };
    let s = format!(
        "TOL {:.4e} m ({})  XRES {:.4e} m ({})  SMIN {}\nBRIdge {:?}  TANgential {}  LIQuid {:?}\n\
         periodic x {} y {} z {}  OUTdir {}  VIEw {:?}  SNApshot {}  HIStory {}  FRAction {}  2-D {}\n",
        tol,
        if st.tol.is_some() { "set" } else { "automatic" },
        xres,
        if st.xres.is_some() {
            "set"
        } else {
            "automatic"
        },
        st.smin
            .map(|x| format!("{x:.4e} m"))
            .unwrap_or_else(|| "automatic (R*/100)".into()),
        st.bridge,
        tangential_name(st.tangential),
        st.liquid_mode,
        st.periodic[0],
        st.periodic[1],
        st.periodic[2],
        st.out_dir,
        st.view,
        st.snapshot_every,
        st.history_every,
        st.fraction.map(|f| f.to_string()).unwrap_or_else(|| {
            "default (0.2; 0.1 with adhesion or without any dissipation)".into()
        }),
        st.two_d
    );
    let (rules_text, rules) = contact_rules(scene.laws());
    let s = s + &rules_text;
    let j = json!({
        "print": "settings", "tol": tol, "xres": xres, "smin": st.smin,
        "contact_rules": rules,
        "bridge": format!("{:?}", st.bridge).to_lowercase(),
        "tangential": tangential_name(st.tangential).to_lowercase(),
        "liquid_mode": format!("{:?}", st.liquid_mode).to_lowercase(),
        "periodic": st.periodic, "out_dir": st.out_dir, "view": format!("{:?}", st.view).to_lowercase(),
        "snapshot": st.snapshot_every, "history": st.history_every, "fraction": st.fraction,
        "two_d": st.two_d,
    });
    (s, j)
}

/// The material pairs a rule covers, as the command takes them.
fn pairs_text(p: &Pairs) -> String {
    match *p {
        Pairs::All => String::new(),
        Pairs::With(m) => format!(" {m}"),
        Pairs::Pair(a, b) => format!(" {a} {b}"),
    }
}

/// A normal law as `SET NORmal` takes it.
fn normal_law_text(l: &NormalLaw) -> String {
    match *l {
        NormalLaw::Hertz => "HERTZ".into(),
        NormalLaw::ModifiedJkr => "MJKR".into(),
        NormalLaw::ModifiedJkrEdem { rolling: false } => "MJKR EDEM".into(),
        NormalLaw::ModifiedJkrEdem { rolling: true } => "MJKR EDEM ROLLING".into(),
        NormalLaw::ThorntonNing { p_y } => format!("TNING {p_y}"),
        NormalLaw::PashaFull { k_e, k_p, k_t } => format!("PFULL {k_e} {k_p} KT {k_t}"),
        NormalLaw::PashaSimplified {
            k_e,
            k_p,
            k_cp,
            f_0p,
            k_t,
        } => {
            format!("PASHA {k_e} {k_p} {k_cp} {f_0p} KT {k_t}")
        }
        NormalLaw::Nguyen => "NGUYEN".into(),
    }
}

/// The rules of `SET NORmal`, `SET ROLling`, `SET PAIr` and `SET DASHpot` in force, in the order given (the
/// last that covers a pair decides), as the commands that would make them.
fn contact_rules(laws: &ContactLaws) -> (String, Vec<String>) {
    let mut rules: Vec<String> = Vec::new();
    for (p, l) in &laws.normal {
        rules.push(format!(
            "SET NORmal {}{}",
            normal_law_text(l),
            pairs_text(p)
        ));
    }
    for (p, mu_r) in &laws.rolling {
        rules.push(format!("SET ROLling {mu_r}{}", pairs_text(p)));
    }
    for (p, v) in &laws.pair_values {
        let mut r = format!("SET PAIr{}", pairs_text(p));
        if let Some(mu) = v.friction {
            r += &format!(" FRIction {mu}");
        }
        if let Some(e) = v.restitution {
            r += &format!(" RESTitution {e}");
        }
        rules.push(r);
    }
    for (p, form) in &laws.dashpot {
        let name = match form {
            crate::sim::model::DashpotForm::Exact => "TRUBAL",
            crate::sim::model::DashpotForm::Liggghts => "LIGGGHTS",
            crate::sim::model::DashpotForm::LiggghtsLimited => "LIMITFORCE",
        };
        rules.push(format!("SET DASHpot {name}{}", pairs_text(p)));
    }
    let text = if rules.is_empty() {
        "contact laws: HERTZ (JKR with COHesion) for all pairs, no rolling friction\n".to_string()
    } else {
        format!("contact laws: {}\n", rules.join("; "))
    };
    (text, rules)
}

fn walls(scene: &Scene) -> (String, Value) {
    let mut s = String::new();
    let mut arr = Vec::new();
    for (k, w) in scene.walls().iter().enumerate() {
        s.push_str(&format!(
            "wall {}: {}  velocity ({}, {}, {}) vr {}  material {}  force ({:.6e}, {:.6e}, {:.6e}) normal {:.6e}{}\n",
            k + 1, geom_text(&w.geom), w.vel[0], w.vel[1], w.vel[2], w.vr, w.material,
            w.force[0], w.force[1], w.force[2], w.normal_force,
            w.servo.map(|s| format!("  servo F {} vmax {} g {}", s.force, s.vmax, s.gain)).unwrap_or_default()
        ));
        arr.push(json!({
            "wall": k + 1, "geometry": serde_json::to_value(w.geom).unwrap_or(Value::Null),
            "velocity": w.vel, "radial_velocity": w.vr, "material": w.material,
            "force": w.force, "normal_force": w.normal_force,
        }));
    }
    if s.is_empty() {
        s.push_str("no walls\n");
    }
    (s, json!({"print": "walls", "walls": arr}))
}

fn chist(scene: &Scene) -> (String, Value) {
    // Histogram of the number of touching contacts per particle (`sim::scene::touch`).
    let n = scene.particles().len();
    let z = scene.coordination();
    let zmax = z.iter().copied().max().unwrap_or(0);
    let mut h = vec![0usize; zmax + 1];
    for &k in &z {
        h[k] += 1;
    }
    let mean = if n > 0 {
        z.iter().sum::<usize>() as f64 / n as f64
    } else {
        0.0
    };
    let mut s = format!("contacts per particle (mean coordination {mean:.4})\n");
    for (k, c) in h.iter().enumerate() {
        s.push_str(&format!("  {k:>3}: {c}\n"));
    }
    (
        s,
        json!({"print": "chist", "histogram": h, "coordination": mean}),
    )
}

fn grid(scene: &Scene) -> (String, Value) {
    let c = &scene.cell();
    let offset = c.signed_offset(scene.size()[0]);
    let mut s = format!(
        "work-space {} x {} x {} m; periodic x {} y {} z {}\n",
        scene.size()[0],
        scene.size()[1],
        scene.size()[2],
        scene.settings().periodic[0],
        scene.settings().periodic[1],
        scene.settings().periodic[2]
    );
    s.push_str(&format!(
        "strain rates (1/s) ed11 {:e} ed22 {:e} ed33 {:e} ed12 {:e} ed23 {:e} ed31 {:e}\n\
         strains        e11 {:e} e22 {:e} e33 {:e} e12 {:e} e23 {:e} e31 {:e}\n\
         image offset (x step between the bottom and top y sides) {:e} m; servo gain {:e} edmax {:e} mode {}; cell work {:e} J\n",
        c.rate[0], c.rate[1], c.rate[2], c.rate[3], c.rate[4], c.rate[5],
        c.strain[0], c.strain[1], c.strain[2], c.strain[3], c.strain[4], c.strain[5],
        offset, c.gain[0], c.gain[1], c.mode, c.work
    ));
    (
        s,
        json!({"print": "grid", "size": scene.size(), "periodic": scene.settings().periodic,
            "rates": c.rate, "strains": c.strain, "offset": offset, "gain": c.gain,
            "mode": c.mode, "work": c.work}),
    )
}

fn history(scene: &Scene) -> (String, Value) {
    let mut cols: Vec<String> = crate::sim::history::COLUMNS
        .iter()
        .map(|c| c.to_string())
        .collect();
    // The groups recorded with the history (`GROup name HIStory`): their columns follow,
    // empty (null) in the rows recorded before or while they were not.
    let (group_cols, group_rows) = super::groups::history_columns(scene);
    cols.extend(group_cols);
    let mut s = cols.join(",");
    s.push('\n');
    let mut rows = Vec::new();
    for (r, g) in scene.history().rows.iter().zip(&group_rows) {
        let mut line: Vec<String> = r.iter().map(|x| format!("{x:e}")).collect();
        line.extend(
            g.iter()
                .map(|x| x.map(|x| format!("{x:e}")).unwrap_or_default()),
        );
        s.push_str(&line.join(","));
        s.push('\n');
        let mut row: Vec<Value> = r.iter().map(|&x| json!(x)).collect();
        row.extend(g.iter().map(|x| {
            x.filter(|x| x.is_finite())
                .map_or(Value::Null, |x| json!(x))
        }));
        rows.push(Value::Array(row));
    }
    (
        s,
        json!({"print": "history", "columns": cols, "rows": rows}),
    )
}
