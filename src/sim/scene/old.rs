//! The layouts of the scene's parts in older checkpoint formats (frozen types, never
//! changed) and the readers that turn them into the current ones, chosen by the format
//! being decoded (`sim::contacts::old::version`; `src/checkpoint.rs`, "Format evolution").

use serde::Deserialize;

use super::{Ledger, Settings, TunnelAction, Wall};
use crate::sim::model::{BridgeChoice, LiquidMode, Servo, TangentialChoice, View, WallGeom};

/// The settings as checkpoint formats 1 and 2 wrote them (frozen: never change).
#[derive(Deserialize)]
struct SettingsV2 {
    tol: Option<f64>,
    xres: Option<f64>,
    smin: Option<f64>,
    bridge: BridgeChoice,
    tangential: TangentialChoice,
    liquid_mode: LiquidMode,
    periodic: [bool; 3],
    out_dir: String,
    view: View,
    snapshot_every: u64,
    history_every: u64,
    two_d: bool,
    fraction: Option<f64>,
    window: Option<[f64; 6]>,
    gen_overlap: f64,
    fragment_eps: Option<f64>,
    goldman: bool,
}

/// The settings as checkpoint formats 3 to 11 wrote them (frozen: never change).
#[derive(Deserialize)]
struct SettingsV11 {
    tol: Option<f64>,
    xres: Option<f64>,
    smin: Option<f64>,
    bridge: BridgeChoice,
    tangential: TangentialChoice,
    liquid_mode: LiquidMode,
    periodic: [bool; 3],
    out_dir: String,
    view: View,
    snapshot_every: u64,
    history_every: u64,
    two_d: bool,
    fraction: Option<f64>,
    window: Option<[f64; 6]>,
    gen_overlap: f64,
    fragment_eps: Option<f64>,
    goldman: bool,
    tunnel: TunnelAction,
    auto_step: Option<f64>,
}

/// Reads the settings in the layout of the checkpoint being decoded
/// (`sim::contacts::old::version`); formats 1 and 2 had no `tunnel` and `auto_step`, formats
/// 1 to 11 no `wall_bridges` (read as on: they always formed).
pub(super) fn old_settings<'de, D: serde::Deserializer<'de>>(de: D) -> Result<Settings, D::Error> {
    match crate::sim::contacts::old::version() {
        1 | 2 => SettingsV2::deserialize(de).map(|o| Settings {
            tol: o.tol,
            xres: o.xres,
            smin: o.smin,
            bridge: o.bridge,
            tangential: o.tangential,
            liquid_mode: o.liquid_mode,
            periodic: o.periodic,
            out_dir: o.out_dir,
            view: o.view,
            snapshot_every: o.snapshot_every,
            history_every: o.history_every,
            two_d: o.two_d,
            fraction: o.fraction,
            window: o.window,
            gen_overlap: o.gen_overlap,
            fragment_eps: o.fragment_eps,
            goldman: o.goldman,
            tunnel: TunnelAction::Stop,
            auto_step: None,
            wall_bridges: true,
        }),
        3..=11 => SettingsV11::deserialize(de).map(|o| Settings {
            tol: o.tol,
            xres: o.xres,
            smin: o.smin,
            bridge: o.bridge,
            tangential: o.tangential,
            liquid_mode: o.liquid_mode,
            periodic: o.periodic,
            out_dir: o.out_dir,
            view: o.view,
            snapshot_every: o.snapshot_every,
            history_every: o.history_every,
            two_d: o.two_d,
            fraction: o.fraction,
            window: o.window,
            gen_overlap: o.gen_overlap,
            fragment_eps: o.fragment_eps,
            goldman: o.goldman,
            tunnel: o.tunnel,
            auto_step: o.auto_step,
            wall_bridges: true,
        }),
        _ => Settings::deserialize(de),
    }
}

/// A wall as checkpoint formats 1 and 2 wrote it (frozen: never change): without `travel`,
/// read as 0 (the restarted run re-maps when it has moved XRES from where it was saved).
#[derive(Deserialize)]
struct WallV2 {
    geom: WallGeom,
    vel: [f64; 3],
    vr: f64,
    material: usize,
    servo: Option<Servo>,
    force: [f64; 3],
    normal_force: f64,
    disp: [f64; 3],
}

/// Reads the cell in the layout of the checkpoint being decoded: formats 1–3 had none (a
/// cell at rest, nothing read).
pub(super) fn old_cell<'de, D: serde::Deserializer<'de>>(
    de: D,
) -> Result<super::cell::Cell, D::Error> {
    match crate::sim::contacts::old::version() {
        1..=3 => Ok(Default::default()),
        _ => super::cell::Cell::deserialize(de),
    }
}

/// The contact laws as checkpoint format 5 wrote them (frozen: never change): without
/// `pair_values` (`SET PAIr`), read as none.
#[derive(Deserialize)]
struct ContactLawsV5 {
    normal: Vec<(crate::sim::model::Pairs, crate::sim::model::NormalLaw)>,
    rolling: Vec<(crate::sim::model::Pairs, f64)>,
}

/// The contact laws as formats 6 to 9 wrote them (frozen: never change).
#[derive(Deserialize)]
struct ContactLawsV9 {
    normal: Vec<(crate::sim::model::Pairs, crate::sim::model::NormalLaw)>,
    rolling: Vec<(crate::sim::model::Pairs, f64)>,
    pair_values: Vec<(crate::sim::model::Pairs, crate::sim::model::PairValues)>,
}

/// Reads the contact laws in the layout of the checkpoint being decoded: formats 1–4 had
/// none (the defaults, nothing read), format 5 no pair values, formats 5–9 no dashpot forms
/// (trubal's everywhere).
pub(super) fn old_laws<'de, D: serde::Deserializer<'de>>(
    de: D,
) -> Result<crate::sim::model::ContactLaws, D::Error> {
    match crate::sim::contacts::old::version() {
        1..=4 => Ok(Default::default()),
        5 => ContactLawsV5::deserialize(de).map(|o| crate::sim::model::ContactLaws {
            normal: o.normal,
            rolling: o.rolling,
            pair_values: Vec::new(),
            dashpot: Vec::new(),
        }),
        6..=9 => ContactLawsV9::deserialize(de).map(|o| crate::sim::model::ContactLaws {
            normal: o.normal,
            rolling: o.rolling,
            pair_values: o.pair_values,
            dashpot: Vec::new(),
        }),
        _ => crate::sim::model::ContactLaws::deserialize(de),
    }
}

/// A group as formats 10 to 12 wrote it (frozen: never change): without a standing Fix.
#[derive(Deserialize)]
struct GroupV11 {
    name: String,
    range: crate::sim::range::Range,
    ids: Option<Vec<u32>>,
    record: bool,
    rows: Vec<Vec<f64>>,
}

/// The groups as formats 10 to 12 wrote them (frozen: never change).
#[derive(Deserialize)]
struct GroupsV11 {
    list: Vec<GroupV11>,
}

/// Reads the groups in the layout of the checkpoint being decoded: formats 1–9 had none
/// (nothing read), formats 10 to 12 no standing Fix (read as none: a Fix over a dynamic
/// group acted once).
pub(super) fn old_groups<'de, D: serde::Deserializer<'de>>(
    de: D,
) -> Result<crate::sim::range::Groups, D::Error> {
    match crate::sim::contacts::old::version() {
        1..=9 => Ok(Default::default()),
        10..=12 => GroupsV11::deserialize(de).map(|o| crate::sim::range::Groups {
            list: o
                .list
                .into_iter()
                .map(|g| crate::sim::range::Group {
                    name: g.name,
                    range: g.range,
                    ids: g.ids,
                    record: g.record,
                    rows: g.rows,
                    fix: None,
                })
                .collect(),
        }),
        _ => crate::sim::range::Groups::deserialize(de),
    }
}

/// Reads the ledger in the layout of the checkpoint being decoded: formats 1–8 had no
/// `unbooked` (read as unknown, NaN).
pub(super) fn old_ledger<'de, D: serde::Deserializer<'de>>(de: D) -> Result<Ledger, D::Error> {
    match crate::sim::contacts::old::version() {
        1..=8 => super::ledger::LedgerV8::deserialize(de).map(Into::into),
        _ => Ledger::deserialize(de),
    }
}

/// Reads the walls in the layout of the checkpoint being decoded
/// (`sim::contacts::old::version`).
pub(super) fn old_walls<'de, D: serde::Deserializer<'de>>(de: D) -> Result<Vec<Wall>, D::Error> {
    match crate::sim::contacts::old::version() {
        1 | 2 => Vec::<WallV2>::deserialize(de).map(|v| {
            v.into_iter()
                .map(|w| Wall {
                    geom: w.geom,
                    vel: w.vel,
                    vr: w.vr,
                    material: w.material,
                    servo: w.servo,
                    force: w.force,
                    normal_force: w.normal_force,
                    disp: w.disp,
                    travel: 0.0,
                })
                .collect()
        }),
        _ => Vec::<Wall>::deserialize(de),
    }
}

/// Reads what the last `Cycle` handed on in the layout of the checkpoint being decoded:
/// formats 1 to 13 had none (nothing read: [`super::Carried::unknown`], the audit's
/// reference taken at the RESTart, nothing in flight, no servo to go on with).
pub(super) fn old_carried<'de, D: serde::Deserializer<'de>>(
    de: D,
) -> Result<super::Carried, D::Error> {
    match crate::sim::contacts::old::version() {
        1..=13 => Ok(super::Carried::unknown()),
        _ => super::Carried::deserialize(de),
    }
}
