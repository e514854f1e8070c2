//! The contact state as older checkpoint formats laid it out, read into the current state:
//! version 1 stored every contact state in one flat layout (with a contact normal that was
//! written and never read); version 2 had no `v_prev` (the velocity-dependent forces were
//! evaluated with the lagging velocity), read as +∞ (no history: the first step treats the
//! pair as isolated); versions 2 and 3 had no `walton` in the law-specific part (Walton's law
//! did not exist), read as its default; versions 2 to 4 had no `laws` state there (the
//! laws of `SET NORmal` did not exist), read as none, nor a rolling spring (`roll`, read as
//! none); versions 5 to 8 had no `mdr` there (the spring row of `SET TANgential MDR`), read
//! as none; versions 1 to 10 had no `end` there (the last evaluated point of a JKR contact's
//! step path), read as none (the next step solves (3.29) at the start of its path).
use std::cell::Cell;

use serde::{Deserialize, Deserializer};

use super::{BridgeState, ContactExt, LawState, TangentialState, Vec3, WaltonState};
use crate::physics::mdr::MdrRow;

thread_local! {
    /// The format version being decoded (0: the current one).
    static READING: Cell<u32> = const { Cell::new(0) };
}

/// Runs `f` (a decoding of a whole checkpoint payload) with contact states read in the
/// layout of format `version`.
pub fn reading<R>(version: u32, f: impl FnOnce() -> R) -> R {
    READING.with(|r| r.set(version));
    let out = f();
    READING.with(|r| r.set(0));
    out
}

/// The format version being decoded (0: the current one).
pub fn version() -> u32 {
    READING.with(|r| r.get())
}

/// The contact state as format version 1 wrote it (frozen: never change).
#[derive(Deserialize)]
struct V1 {
    touching: bool,
    overlap: f64,
    normal_force: f64,
    damp_force: f64,
    a_s: f64,
    tang_energy: f64,
    a: f64,
    gamma: f64,
    delta: Vec3,
    tforce: Vec3,
    tdamp: Vec3,
    tdelta: f64,
    tang: TangentialState,
    #[allow(dead_code)]
    normal: Vec3,
    bridge: Option<Box<BridgeState>>,
    released: [f64; 2],
}

impl From<V1> for super::ContactState {
    fn from(o: V1) -> Self {
        let ext = ContactExt {
            a_s: o.a_s,
            gamma: o.gamma,
            delta: o.delta,
            tdelta: o.tdelta,
            tang: o.tang,
            released: o.released,
            walton: WaltonState::default(),
            laws: None,
            mdr: None,
            end: None,
        };
        super::ContactState {
            touching: o.touching,
            overlap: o.overlap,
            normal_force: o.normal_force,
            damp_force: o.damp_force,
            v_prev: f64::INFINITY,
            tang_energy: o.tang_energy,
            a: o.a,
            tforce: o.tforce,
            tdamp: o.tdamp,
            ext: (ext != ContactExt::default()).then(|| Box::new(ext)),
            bridge: o.bridge,
            row: super::RowSlot::NONE,
        }
    }
}

/// The contact state as format version 2 wrote it (frozen: never change).
#[derive(Deserialize)]
struct V2 {
    touching: bool,
    overlap: f64,
    normal_force: f64,
    damp_force: f64,
    tang_energy: f64,
    a: f64,
    tforce: Vec3,
    tdamp: Vec3,
    ext: Option<Box<ExtV3>>,
    bridge: Option<Box<BridgeState>>,
}

/// The law-specific part of the contact state as format versions 2 and 3 wrote it (frozen:
/// never change).
#[derive(Deserialize)]
struct ExtV3 {
    a_s: f64,
    gamma: f64,
    delta: Vec3,
    tdelta: f64,
    tang: TangentialState,
    released: [f64; 2],
}

impl From<ExtV3> for ContactExt {
    fn from(o: ExtV3) -> Self {
        ContactExt {
            a_s: o.a_s,
            gamma: o.gamma,
            delta: o.delta,
            tdelta: o.tdelta,
            tang: o.tang,
            released: o.released,
            walton: WaltonState::default(),
            laws: None,
            mdr: None,
            end: None,
        }
    }
}

fn ext_v3(e: Option<Box<ExtV3>>) -> Option<Box<ContactExt>> {
    e.map(|e| Box::new((*e).into()))
}

/// The contact state as format versions 3 to 10 wrote it, with the law-specific part of
/// each (`ExtV3`, `ExtV4`, `ExtV8`, `ExtV9`; frozen: never change).
#[derive(Deserialize)]
struct V3<E> {
    touching: bool,
    overlap: f64,
    normal_force: f64,
    damp_force: f64,
    v_prev: f64,
    tang_energy: f64,
    a: f64,
    tforce: Vec3,
    tdamp: Vec3,
    ext: Option<Box<E>>,
    bridge: Option<Box<BridgeState>>,
}

type V4 = V3<ExtV4>;

impl<E: Into<ContactExt>> From<V3<E>> for super::ContactState {
    fn from(o: V3<E>) -> Self {
        super::ContactState {
            touching: o.touching,
            overlap: o.overlap,
            normal_force: o.normal_force,
            damp_force: o.damp_force,
            v_prev: o.v_prev,
            tang_energy: o.tang_energy,
            a: o.a,
            tforce: o.tforce,
            tdamp: o.tdamp,
            ext: o.ext.map(|e| Box::new((*e).into())),
            bridge: o.bridge,
            row: super::RowSlot::NONE,
        }
    }
}

impl From<V2> for super::ContactState {
    fn from(o: V2) -> Self {
        super::ContactState {
            touching: o.touching,
            overlap: o.overlap,
            normal_force: o.normal_force,
            damp_force: o.damp_force,
            v_prev: f64::INFINITY,
            tang_energy: o.tang_energy,
            a: o.a,
            tforce: o.tforce,
            tdamp: o.tdamp,
            ext: ext_v3(o.ext),
            bridge: o.bridge,
            row: super::RowSlot::NONE,
        }
    }
}

/// The law-specific part of the contact state as format version 4 wrote it (frozen: never
/// change).
#[derive(Deserialize)]
struct ExtV4 {
    a_s: f64,
    gamma: f64,
    delta: Vec3,
    tdelta: f64,
    tang: TangentialState,
    released: [f64; 2],
    walton: WaltonState,
}

impl From<ExtV4> for ContactExt {
    fn from(e: ExtV4) -> Self {
        ContactExt {
            a_s: e.a_s,
            gamma: e.gamma,
            delta: e.delta,
            tdelta: e.tdelta,
            tang: e.tang,
            released: e.released,
            walton: e.walton,
            laws: None,
            mdr: None,
            end: None,
        }
    }
}

/// The law-specific part of the contact state as format versions 5 to 8 wrote it (frozen:
/// never change).
#[derive(Deserialize)]
struct ExtV8 {
    a_s: f64,
    gamma: f64,
    delta: Vec3,
    tdelta: f64,
    tang: TangentialState,
    released: [f64; 2],
    walton: WaltonState,
    laws: Option<Box<LawState>>,
}

impl From<ExtV8> for ContactExt {
    fn from(e: ExtV8) -> Self {
        ContactExt {
            a_s: e.a_s,
            gamma: e.gamma,
            delta: e.delta,
            tdelta: e.tdelta,
            tang: e.tang,
            released: e.released,
            walton: e.walton,
            laws: e.laws,
            mdr: None,
            end: None,
        }
    }
}

/// The law-specific part of the contact state as format versions 9 and 10 wrote it (frozen: never
/// change).
#[derive(Deserialize)]
struct ExtV9 {
    a_s: f64,
    gamma: f64,
    delta: Vec3,
    tdelta: f64,
    tang: TangentialState,
    released: [f64; 2],
    walton: WaltonState,
    laws: Option<Box<LawState>>,
    mdr: Option<Box<MdrRow>>,
}

impl From<ExtV9> for ContactExt {
    fn from(e: ExtV9) -> Self {
        ContactExt {
            a_s: e.a_s,
            gamma: e.gamma,
            delta: e.delta,
            tdelta: e.tdelta,
            tang: e.tang,
            released: e.released,
            walton: e.walton,
            laws: e.laws,
            mdr: e.mdr,
            end: None,
        }
    }
}

/// Reads a contact state in the layout of the checkpoint being decoded.
pub fn deserialize_state<'de, D: Deserializer<'de>>(
    de: D,
) -> Result<super::ContactState, D::Error> {
    match version() {
        1 => V1::deserialize(de).map(Into::into),
        2 => V2::deserialize(de).map(Into::into),
        3 => V3::<ExtV3>::deserialize(de).map(Into::into),
        4 => V4::deserialize(de).map(Into::into),
        5..=8 => V3::<ExtV8>::deserialize(de).map(Into::into),
        9 | 10 => V3::<ExtV9>::deserialize(de).map(Into::into),
        _ => super::ContactState::deserialize(de),
    }
}
