//! The spring rows of `SET TANgential MDR` (`physics::mdr::MdrRow`, 288 bytes) of the
//! particle pairs, kept in a list beside their block's contact states ([`StateBlock`]) and
//! laid out in pair order at every merge: the force loop walks them in order, as it walks
//! the states. A row behind a pointer of its own (in the contact's `ContactExt`, as
//! particle–wall contacts keep it) sat wherever the allocator put it when the contact
//! formed, a cache miss a contact a step. A checkpoint holds the rows where format 9 put
//! them (`ContactExt::mdr`): [`StateBlock::saved`] folds a row back in,
//! [`StateBlock::push_saved`] takes it out.

use std::borrow::Cow;

use super::*;

/// The contact states of one block of pairs and the MDR spring rows of its touching Hertz
/// contacts (`ContactState::row` is the index of a state's row). Reads as its list of states.
#[derive(Clone, Debug, Default)]
pub struct StateBlock {
    /// The states, in pair order after each merge (a pair that comes within reach between
    /// rebuilds gets its state appended).
    pub states: Vec<ContactState>,
    /// The rows, in pair order after each merge (a row made between rebuilds is appended;
    /// the row of a contact that ended stays unused until the next merge or
    /// [`StateBlock::compact_rows`]).
    pub rows: Vec<MdrRow>,
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

impl StateBlock {
    /// A block of the given states without rows.
    pub fn of(states: Vec<ContactState>) -> StateBlock {
        StateBlock {
            states,
            rows: Vec::new(),
        }
    }

    /// An empty block with room for `n` states and `n_rows` rows and their [`headroom`] (no
    /// row list at all without rows: the other laws' blocks).
    pub fn with_room(n: usize, n_rows: usize) -> StateBlock {
        let room = |n: usize| if n > 0 { n + headroom(n) } else { 0 };
        StateBlock {
            states: Vec::with_capacity(n + headroom(n)),
            rows: Vec::with_capacity(room(n_rows)),
        }
    }

    /// The spring row of state `slot`, if it has one in this block's list.
    #[inline(always)]
    pub fn row(&self, slot: usize) -> Option<&MdrRow> {
        self.states[slot].row.index().map(|r| &self.rows[r])
    }

    /// State `slot` in the checkpoint's shape: its row, if any, in `ext.mdr` (where the
    /// MDR law kept it before the rows had a list of their own: an extension at its
    /// defaults but for the row).
    pub fn saved(&self, slot: usize) -> Cow<'_, ContactState> {
        let s = &self.states[slot];
        match self.row(slot) {
            None => Cow::Borrowed(s),
            Some(r) => {
                let mut o = s.clone();
                o.row = RowSlot::NONE;
                o.ext_mut().mdr = Some(Box::new(r.clone()));
                Cow::Owned(o)
            }
        }
    }

    /// Appends a state given in the checkpoint's shape: a row in `ext.mdr` goes to the
    /// list, and an extension left at its defaults (bit for bit) is dropped ([`saved`]
    /// makes the same state again). Returns the state's slot.
    ///
    /// [`saved`]: StateBlock::saved
    pub fn push_saved(&mut self, mut s: ContactState) -> u32 {
        if let Some(e) = s.ext.as_deref_mut()
            && let Some(r) = e.mdr.take()
        {
            s.row = RowSlot(self.rows.len() as u32);
            self.rows.push(*r);
            if bincode::serde::encode_to_vec(&*e, bincode::config::standard())
                .is_ok_and(|b| b == *DEFAULT_EXT_BYTES)
            {
                s.ext = None;
            }
        }
        self.states.push(s);
        (self.states.len() - 1) as u32
    }

    /// Appends a copy of state `slot` of `from` with its row (the row appended to the list).
    #[inline]
    pub fn push_copy(&mut self, from: &StateBlock, slot: usize) -> u32 {
        let mut s = from.states[slot].clone();
        if let Some(r) = s.row.index() {
            s.row = RowSlot(self.rows.len() as u32);
            self.rows.push(from.rows[r].clone());
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
        slots: impl Iterator<Item = u32>,
    ) -> (&mut Vec<ContactState>, &mut Vec<MdrRow>) {
        self.compact_rows_if_full(slots);
        (&mut self.states, &mut self.rows)
    }

    /// When the row list is full: drops the unused rows (of contacts that ended since the
    /// last merge) and lays the others out in the order of the block's pairs (`slots`, the
    /// state slot of each pair in pair order, `NO_STATE` for none), with room for
    /// [`headroom`] more. A block whose contacts come and go between rebuilds keeps a
    /// bounded list.
    pub fn compact_rows_if_full(&mut self, slots: impl Iterator<Item = u32>) {
        if self.rows.len() < self.rows.capacity() || self.rows.is_empty() {
            return;
        }
        let live = self.states.iter().filter(|s| s.row.is_some()).count();
        let mut rows = Vec::with_capacity(live + headroom(live));
        for slot in slots.filter(|&s| s != NO_STATE) {
            let s = &mut self.states[slot as usize];
            if let Some(r) = s.row.index() {
                s.row = RowSlot(rows.len() as u32);
                rows.push(std::mem::take(&mut self.rows[r]));
            }
        }
        self.rows = rows;
    }
}

/// The row of state `s` in its block's list `rows`, made by `make` and appended if it has
/// none.
#[inline(always)]
pub fn row_in<'r>(
    s: &mut ContactState,
    rows: &'r mut Vec<MdrRow>,
    make: impl FnOnce() -> MdrRow,
) -> &'r mut MdrRow {
    let r = match s.row.index() {
        Some(r) => r,
        None => {
            s.row = RowSlot(rows.len() as u32);
            rows.push(make());
            rows.len() - 1
        }
    };
    &mut rows[r]
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
}
