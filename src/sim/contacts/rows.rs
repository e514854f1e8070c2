//! The rows of the particle pairs kept in lists beside their block's contact states
//! ([`StateBlock`]) and laid out in pair order at every merge: the spring rows of `SET
//! TANgential MDR` (`physics::mdr::MdrRow`, 288 bytes) and the JKR rows of touching JKR
//! pairs ([`JkrRow`], 72 bytes). The force loop walks them in order, as it walks the states.
//! A row behind a pointer of its own (in the contact's `ContactExt`, as particle–wall
//! contacts keep it) sat wherever the allocator put it, a cache line or more a contact a
//! step away from the state. A checkpoint holds the rows where formats 9 and 11 put them
//! (`ContactExt::mdr`, `ContactExt::end`): [`StateBlock::saved`] folds a row back in,
//! [`StateBlock::push_saved`] takes it out.

use std::borrow::Cow;

use super::*;

/// The contact states of one block of pairs, the MDR spring rows of its touching Hertz
/// contacts and the JKR rows of its touching JKR contacts (`ContactState::row` is the index
/// of a state's row). Reads as its list of states.
#[derive(Clone, Debug, Default)]
pub struct StateBlock {
    /// The states, in pair order after each merge (a pair that comes within reach between
    /// rebuilds gets its state appended).
    pub states: Vec<ContactState>,
    /// The MDR rows, in pair order after each merge (a row made between rebuilds is
    /// appended; the row of a contact that ended stays unused until the next merge or
    /// [`StateBlock::compact_rows_if_full`]).
    pub rows: Vec<MdrRow>,
    /// The JKR rows, kept as the MDR rows are.
    pub jkr: Vec<JkrRow>,
}

/// The row lists of a block, for the force loop's contact law (`sim::interact`).
pub struct Rows<'r> {
    pub mdr: &'r mut Vec<MdrRow>,
    pub jkr: &'r mut Vec<JkrRow>,
}

impl Rows<'_> {
    /// The same lists, for one contact's law.
    #[inline(always)]
    pub fn reborrow(&mut self) -> Rows<'_> {
        Rows {
            mdr: &mut *self.mdr,
            jkr: &mut *self.jkr,
        }
    }
}

impl std::ops::Deref for StateBlock {
    type Target = Vec<ContactState>;
    fn deref(&self) -> &Vec<ContactState> {
        &self.states
    }
}

impl std::ops::DerefMut for StateBlock {
    fn deref_mut(&mut self) -> &mut Vec<ContactState> {
        &mut self.states
    }
}

/// The default extension's encoding: an extension that encodes the same (bit for bit)
/// once its row is taken out is not kept.
static DEFAULT_EXT_BYTES: std::sync::LazyLock<Vec<u8>> = std::sync::LazyLock::new(|| {
    bincode::serde::encode_to_vec(&*state::DEFAULT_EXT, bincode::config::standard())
        .unwrap_or_default()
});

/// Room for `n` entries and their [`headroom`] (no room at all for none: the lists of the
/// laws a block does not use).
fn room(n: usize) -> usize {
    if n > 0 { n + headroom(n) } else { 0 }
}

impl StateBlock {
    /// A block of the given states without rows.
    pub fn of(states: Vec<ContactState>) -> StateBlock {
        StateBlock {
            states,
            rows: Vec::new(),
            jkr: Vec::new(),
        }
    }

    /// An empty block with room for `n` states, `n_rows` MDR rows and `n_jkr` JKR rows and
    /// their [`headroom`].
    pub fn with_room(n: usize, n_rows: usize, n_jkr: usize) -> StateBlock {
        StateBlock {
            states: Vec::with_capacity(n + headroom(n)),
            rows: Vec::with_capacity(room(n_rows)),
            jkr: Vec::with_capacity(room(n_jkr)),
        }
    }

    /// Gives the lists the room a merge gives them ([`headroom`]).
    pub fn trim(&mut self) {
        let (n, r, j) = (self.states.len(), self.rows.len(), self.jkr.len());
        self.states.shrink_to(n + headroom(n));
        self.rows.shrink_to(r + headroom(r));
        self.jkr.shrink_to(j + headroom(j));
    }

    /// Frees the lists' spare room.
    pub fn shrink_to_fit(&mut self) {
        self.states.shrink_to_fit();
        self.rows.shrink_to_fit();
        self.jkr.shrink_to_fit();
    }

    /// The spring row of state `slot`, if it has one in this block's list.
    #[inline(always)]
    pub fn row(&self, slot: usize) -> Option<&MdrRow> {
        self.states[slot].row.mdr().map(|r| &self.rows[r])
    }

    /// The JKR row of state `slot`, if it has one in this block's list.
    #[inline(always)]
    pub fn jkr_row(&self, slot: usize) -> Option<&JkrRow> {
        self.states[slot].row.jkr().map(|r| &self.jkr[r])
    }

    /// State `slot` in the checkpoint's shape: its MDR row, if any, in `ext.mdr` (where the
    /// MDR law kept it before the rows had a list of their own: an extension at its
    /// defaults but for the row); its JKR row's path end, if any, in `ext.end` (its `gamma`
    /// and `a_s` are the extension's).
    pub fn saved(&self, slot: usize) -> Cow<'_, ContactState> {
        let s = &self.states[slot];
        if let Some(r) = self.row(slot) {
            let mut o = s.clone();
            o.row = RowSlot::NONE;
            o.ext_mut().mdr = Some(Box::new(r.clone()));
            Cow::Owned(o)
        } else if let Some(r) = self.jkr_row(slot) {
            let mut o = s.clone();
            o.row = RowSlot::NONE;
            o.ext_mut().end = r.end;
            Cow::Owned(o)
        } else {
            Cow::Borrowed(s)
        }
    }

    /// Appends a state given in the checkpoint's shape: a row in `ext.mdr` goes to the MDR
    /// list, and an extension left at its defaults (bit for bit) is dropped ([`saved`]
    /// makes the same state again); a touching contact with a surface energy gets a JKR
    /// row, with the extension's path end. Returns the state's slot.
    ///
    /// [`saved`]: StateBlock::saved
    pub fn push_saved(&mut self, mut s: ContactState) -> u32 {
        if let Some(e) = s.ext.as_deref_mut()
            && let Some(r) = e.mdr.take()
        {
            s.row = RowSlot::mdr_at(self.rows.len());
            self.rows.push(*r);
            if bincode::serde::encode_to_vec(&*e, bincode::config::standard())
                .is_ok_and(|b| b == *DEFAULT_EXT_BYTES)
            {
                s.ext = None;
            }
        } else if s.touching
            && let Some(e) = s.ext.as_deref_mut()
            && e.gamma > 0.0
        {
            s.row = RowSlot::jkr_at(self.jkr.len());
            self.jkr.push(JkrRow::of(e));
            e.end = None;
        }
        self.states.push(s);
        (self.states.len() - 1) as u32
    }

    /// Appends a copy of state `slot` of `from` with its row (the row appended to its list).
    #[inline]
    pub fn push_copy(&mut self, from: &StateBlock, slot: usize) -> u32 {
        let mut s = from.states[slot].clone();
        if let Some(r) = s.row.mdr() {
            s.row = RowSlot::mdr_at(self.rows.len());
            self.rows.push(from.rows[r].clone());
        } else if let Some(r) = s.row.jkr() {
            s.row = RowSlot::jkr_at(self.jkr.len());
            self.jkr.push(from.jkr[r]);
        }
        self.states.push(s);
        (self.states.len() - 1) as u32
    }

    /// Takes state `slot` out in the checkpoint's shape (its place keeps a default state).
    pub fn take_saved(&mut self, slot: usize) -> ContactState {
        let saved = self.saved(slot).into_owned();
        self.states[slot] = ContactState::default();
        saved
    }

    /// The states and the rows for a step of the force loop, the rows first compacted if
    /// their list is full ([`StateBlock::compact_rows_if_full`]; `slots` as there).
    #[inline(always)]
    pub fn for_step(
        &mut self,
        slots: impl Iterator<Item = u32> + Clone,
    ) -> (&mut Vec<ContactState>, Rows<'_>) {
        self.compact_rows_if_full(slots);
        (
            &mut self.states,
            Rows {
                mdr: &mut self.rows,
                jkr: &mut self.jkr,
            },
        )
    }

    /// When a row list is full: drops its unused rows (of contacts that ended since the
    /// last merge) and lays the others out in the order of the block's pairs (`slots`, the
    /// state slot of each pair in pair order, `NO_STATE` for none), with room for
    /// [`headroom`] more. A block whose contacts come and go between rebuilds keeps bounded
    /// lists.
    pub fn compact_rows_if_full(&mut self, slots: impl Iterator<Item = u32> + Clone) {
        if full(&self.rows) {
            compact(&mut self.states, &mut self.rows, slots.clone(), Kind::Mdr);
        }
        if full(&self.jkr) {
            compact(&mut self.states, &mut self.jkr, slots, Kind::Jkr);
        }
    }
}

/// A row list with no room left (and rows in it).
#[inline(always)]
fn full<T>(rows: &Vec<T>) -> bool {
    rows.len() == rows.capacity() && !rows.is_empty()
}

/// Which of a block's row lists.
#[derive(Clone, Copy)]
enum Kind {
    Mdr,
    Jkr,
}

impl Kind {
    fn index(self, r: RowSlot) -> Option<usize> {
        match self {
            Kind::Mdr => r.mdr(),
            Kind::Jkr => r.jkr(),
        }
    }
    fn slot(self, i: usize) -> RowSlot {
        match self {
            Kind::Mdr => RowSlot::mdr_at(i),
            Kind::Jkr => RowSlot::jkr_at(i),
        }
    }
}

/// [`StateBlock::compact_rows_if_full`] for one list.
fn compact<T: Default>(
    states: &mut [ContactState],
    rows: &mut Vec<T>,
    slots: impl Iterator<Item = u32>,
    kind: Kind,
) {
    let live = states
        .iter()
        .filter(|s| kind.index(s.row).is_some())
        .count();
    let mut out = Vec::with_capacity(live + headroom(live));
    for slot in slots.filter(|&s| s != NO_STATE) {
        let s = &mut states[slot as usize];
        if let Some(r) = kind.index(s.row) {
            s.row = kind.slot(out.len());
            out.push(std::mem::take(&mut rows[r]));
        }
    }
    *rows = out;
}

/// The row of state `s` in its block's list `rows`, made by `make` and appended if it has
/// none.
#[inline(always)]
pub fn row_in<'r>(
    s: &mut ContactState,
    rows: &'r mut Vec<MdrRow>,
    make: impl FnOnce() -> MdrRow,
) -> &'r mut MdrRow {
    let r = match s.row.mdr() {
        Some(r) => r,
        None => {
            s.row = RowSlot::mdr_at(rows.len());
            rows.push(make());
            rows.len() - 1
        }
    };
    &mut rows[r]
}

/// A new JKR row for state `s` (snap-in), appended to its block's list.
#[inline(always)]
pub fn new_jkr_row(s: &mut ContactState, rows: &mut Vec<JkrRow>, row: JkrRow) {
    s.row = RowSlot::jkr_at(rows.len());
    rows.push(row);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(x: f64) -> MdrRow {
        MdrRow {
            a_ref: x,
            ..Default::default()
        }
    }

    /// A state with a row in `ext.mdr` (the checkpoint's shape) is kept with the row in the
    /// list and its extension dropped when nothing else is in it; saved, it is the same
    /// state again, bit for bit (a signed zero in the extension keeps the extension).
    #[test]
    fn rows_leave_and_rejoin_the_saved_state_unchanged() {
        let with = |ext: ContactExt| ContactState {
            touching: true,
            overlap: 1e-6,
            ext: Some(Box::new(ext)),
            ..Default::default()
        };
        let plain = with(ContactExt {
            mdr: Some(Box::new(row(2e-5))),
            ..Default::default()
        });
        let signed = with(ContactExt {
            tdelta: -0.0,
            mdr: Some(Box::new(row(3e-5))),
            ..Default::default()
        });
        let none = ContactState {
            touching: true,
            ..Default::default()
        };
        let mut b = StateBlock::default();
        for s in [&plain, &none, &signed] {
            b.push_saved(s.clone());
        }
        assert!(b.states[0].ext.is_none() && b.states[0].row.is_some());
        assert!(b.states[2].ext.is_some() && b.states[2].row.is_some());
        assert_eq!(b.rows.len(), 2);
        let bytes = |s: &ContactState| {
            bincode::serde::encode_to_vec(s, bincode::config::standard()).expect("encodes")
        };
        for (k, s) in [&plain, &none, &signed].into_iter().enumerate() {
            assert_eq!(bytes(&b.saved(k)), bytes(s), "state {k}");
        }
        // A copy carries the rows; a compaction keeps the used rows in pair order.
        let mut c = StateBlock::default();
        for k in [2, 0, 1] {
            c.push_copy(&b, k);
        }
        assert_eq!(c.row(0), Some(&row(3e-5)));
        assert_eq!(c.row(1), Some(&row(2e-5)));
        let mut kinematics = crate::sim::kinematics::Acc::default();
        crate::sim::kinematics::reset_solid(&mut c.states[0], &mut kinematics);
        c.rows.shrink_to_fit();
        c.compact_rows_if_full([1, 2, 0].into_iter());
        assert_eq!(c.rows, vec![row(2e-5)]);
        assert_eq!(c.row(1), Some(&row(2e-5)));
        assert_eq!(c.row(0), None);
        assert!(c.rows.capacity() > c.rows.len(), "room for more");
    }

    /// A touching state with a surface energy (a JKR contact, the checkpoint's shape: its
    /// path end in `ext.end`) is kept with a JKR row; saved, it is the same state again, bit
    /// for bit; a copy carries the row, and a compaction keeps the rows in use in pair order.
    #[test]
    fn jkr_rows_leave_and_rejoin_the_saved_state_unchanged() {
        let end = |x: f64| crate::physics::jkr::PathEnd {
            alpha: x,
            e: 1.0,
            p: 2.0,
            k: 3.0,
            e_star: 4.0,
            r_star: 5.0,
        };
        let ext = |end| {
            Some(Box::new(ContactExt {
                gamma: 0.1,
                a_s: 1e-5,
                end,
                ..Default::default()
            }))
        };
        let jkr = |x: f64| ContactState {
            touching: true,
            overlap: x,
            ext: ext(Some(end(x))),
            ..Default::default()
        };
        // A JKR contact that ended: no row.
        let ended = ContactState {
            ext: ext(None),
            ..Default::default()
        };
        let mut b = StateBlock::default();
        for s in [&jkr(1e-9), &ended, &jkr(2e-9)] {
            b.push_saved(s.clone());
        }
        assert_eq!(b.jkr.len(), 2);
        assert!(b.rows.is_empty() && b.states[1].row.jkr().is_none());
        assert!(b.states[0].ext().end.is_none(), "the path end is the row's");
        assert_eq!(
            b.jkr_row(2).map(|r| (r.gamma, r.a_s, r.end)),
            Some((0.1, 1e-5, Some(end(2e-9))))
        );
        let bytes = |s: &ContactState| {
            bincode::serde::encode_to_vec(s, bincode::config::standard()).expect("encodes")
        };
        for (k, s) in [jkr(1e-9), ended, jkr(2e-9)].iter().enumerate() {
            assert_eq!(bytes(&b.saved(k)), bytes(s), "state {k}");
        }
        let mut c = StateBlock::default();
        for k in [2, 0, 1] {
            c.push_copy(&b, k);
        }
        assert_eq!(c.jkr_row(0).and_then(|r| r.end), Some(end(2e-9)));
        assert_eq!(c.jkr_row(1).and_then(|r| r.end), Some(end(1e-9)));
        let mut kinematics = crate::sim::kinematics::Acc::default();
        crate::sim::kinematics::reset_solid(&mut c.states[0], &mut kinematics);
        c.jkr.shrink_to_fit();
        c.compact_rows_if_full([1, 2, 0].into_iter());
        assert_eq!(c.jkr.len(), 1);
        assert_eq!(c.jkr_row(1).and_then(|r| r.end), Some(end(1e-9)));
        assert_eq!(c.jkr_row(0), None);
        assert!(c.jkr.capacity() > c.jkr.len(), "room for more");
    }
}
