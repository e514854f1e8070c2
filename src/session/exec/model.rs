//! Model settings of the scene: DAmping, FRAction, LIQuid, Window, 2-D, SET.

use super::*;

pub(super) fn apply(scene: &mut Scene, cmd: &Command) -> Result<String, String> {
    match cmd {
        Command::Damping(DampingSpec::Rayleigh {
            frac,
            freq,
            mass_off,
            stiff_off,
            ball_ball,
        }) => {
            let w = 2.0 * std::f64::consts::PI * freq;
            let r = Rayleigh {
                alpha: if *mass_off { 0.0 } else { frac * w },
                beta: if *stiff_off { 0.0 } else { frac / w },
            };
            scene.set_rayleigh(*ball_ball, r);
            Ok(String::new())
        }
        Command::Damping(DampingSpec::Restitution { e, material }) => {
            if let Some(m) = material {
                existing_material(scene, *m)?;
            }
            scene.set_restitution(*material, *e);
            Ok(String::new())
        }
        Command::Fraction { f } => {
            scene.set_fraction(*f);
            Ok(String::new())
        }
        Command::Liquid {
            pvol,
            gsurf,
            theta_deg,
            eta,
        } => liquid(scene, *pvol, *gsurf, *theta_deg, *eta),
        Command::Window { bounds } => {
            if bounds[0] > bounds[1] || bounds[2] > bounds[3] || bounds[4] > bounds[5] {
                return Err("Window needs x1 <= x2, y1 <= y2, z1 <= z2".into());
            }
            scene.set_window(*bounds);
            Ok(String::new())
        }
        Command::TwoD => {
            scene.set_two_d();
            Ok(String::new())
        }
        Command::Set(s) => set(scene, s),
        other => Err(not_here(other)),
    }
}

/// `LIQuid pvol gsurf gcon gvis`: the liquid of every bridge (pvol = 0 removes them all),
/// checked against the chosen bridge model's validity range for the sizes in use.
fn liquid(
    scene: &mut Scene,
    pvol: f64,
    gsurf: f64,
    theta_deg: f64,
    eta: f64,
) -> Result<String, String> {
    if pvol == 0.0 {
        scene.remove_liquid();
        return Ok("all liquid bridges removed".into());
    }
    let l = crate::sim::scene::Liquid {
        pvol,
        gamma: gsurf,
        theta: theta_deg.to_radians(),
        eta,
    };
    let warn =
        liquid_warnings(scene, scene.settings().bridge, &l).map_err(|e| format!("LIQuid: {e}"))?;
    scene.set_liquid(l);
    Ok(warn)
}

/// Checks the bridges of the smallest and largest sizes in use (equal and unequal pairs; a
/// unit sphere if there are no particles yet) against a bridge model's validity range:
/// `Err` if the model cannot take them, else the warnings, one `warning: ` line each.
fn liquid_warnings(
    scene: &Scene,
    choice: crate::sim::model::BridgeChoice,
    l: &crate::sim::scene::Liquid,
) -> Result<String, String> {
    let model = crate::sim::model::bridge_model(choice);
    let mut radii: Vec<f64> = scene.particles().radius.clone();
    radii.sort_by(f64::total_cmp);
    let (rmin, rmax) = (
        radii.first().copied().unwrap_or(1.0),
        radii.last().copied().unwrap_or(1.0),
    );
    let mut warn = Vec::new();
    for (r1, r2) in [(rmin, rmin), (rmin, rmax)] {
        let b = crate::physics::bridge::Bridge {
            r1,
            r2,
            volume: crate::sim::liquid::bridge_volume(l.pvol, r1, r2),
            gamma: l.gamma,
            theta: l.theta,
        };
        warn.extend(crate::physics::bridge::validate(model, &b)?);
    }
    let mut seen = std::collections::HashSet::new();
    warn.retain(|w| seen.insert(w.clone()));
    Ok(warn.iter().map(|w| format!("warning: {w}\n")).collect())
}

/// `SET name value`: a setting of the scene (the periodic axes refused while a plane wall
/// crosses them).
fn set(scene: &mut Scene, s: &Setting) -> Result<String, String> {
    if let Setting::Normal { pairs, .. }
    | Setting::Rolling { pairs, .. }
    | Setting::Dashpot { pairs, .. } = s
    {
        let mats = match *pairs {
            crate::sim::model::Pairs::All => vec![],
            crate::sim::model::Pairs::With(m) => vec![m],
            crate::sim::model::Pairs::Pair(m, n) => vec![m, n],
        };
        for m in mats {
            super::existing_material(scene, m as usize)?;
        }
        scene.edit_laws(|laws| match s {
            Setting::Normal { law, .. } => laws.set_normal(*pairs, *law),
            Setting::Rolling { mu_r, .. } => laws.set_rolling(*pairs, *mu_r),
            Setting::Dashpot { form, .. } => laws.set_dashpot(*pairs, *form),
            _ => {}
        });
        return Ok(String::new());
    }
    if let Setting::Pair { m1, m2, values } = s {
        super::existing_material(scene, *m1 as usize)?;
        super::existing_material(scene, *m2 as usize)?;
        scene.edit_laws(|laws| laws.set_pair_values(*m1, *m2, *values));
        return Ok(String::new());
    }
    if let Setting::Boundary { axes, periodic } = s {
        let mut want = scene.settings().periodic;
        for k in 0..3 {
            if axes[k] {
                want[k] = *periodic;
            }
        }
        for (w, wall) in scene.walls().iter().enumerate() {
            let crossed = walls::crossed_axes(&wall.geom, &want);
            if crossed != [false; 3] {
                return Err(format!(
                    "plane wall {} crosses the {} axis, which must stay open (a particle leaving through one side would re-enter behind the wall); turn the wall parallel to the axis first (AWAll n P ...)",
                    w + 1,
                    walls::axis_names(&crossed)
                ));
            }
        }
    }
    // A new bridge model is checked against the liquid in place, as `LIQuid` checks it.
    let mut warn = String::new();
    if let Setting::Bridge(b) = s
        && let Some(l) = scene.liquid()
    {
        warn = liquid_warnings(scene, *b, &l).map_err(|e| format!("SET BRIdge: {e}"))?;
    }
    scene.edit_settings(|st| match s {
        Setting::Tol(v) => st.tol = *v,
        Setting::Xres(v) => st.xres = *v,
        Setting::Smin(v) => st.smin = *v,
        Setting::Bridge(b) => st.bridge = *b,
        Setting::Tangential(t) => st.tangential = *t,
        Setting::Liquid(m) => st.liquid_mode = *m,
        Setting::Boundary { axes, periodic } => {
            for k in 0..3 {
                if axes[k] {
                    st.periodic[k] = *periodic;
                }
            }
        }
        Setting::OutDir(d) => st.out_dir = d.clone(),
        Setting::View(v) => st.view = *v,
        Setting::Snapshot(n) => st.snapshot_every = *n,
        Setting::History(n) => st.history_every = *n,
        Setting::GenOverlap(f) => st.gen_overlap = *f,
        Setting::Fragment(e) => st.fragment_eps = *e,
        Setting::Goldman(on) => st.goldman = *on,
        Setting::WallBridges(on) => st.wall_bridges = *on,
        Setting::Tunnel(t) => st.tunnel = *t,
        Setting::Normal { .. }
        | Setting::Rolling { .. }
        | Setting::Pair { .. }
        | Setting::Dashpot { .. } => {}
    });
    Ok(warn)
}
