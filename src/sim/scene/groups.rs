//! The scene's groups (`GROup`, doc/groups.md): which particles a range selects now, and the
//! definitions kept in the scene (and so in its checkpoint).

use super::*;
use crate::sim::range::{Candidate, Group, Groups, MAX_GROUPS, Range, StandingFix};

/// How deep groups may name groups when a range is evaluated (a circle is refused when a
/// group is defined and when a checkpoint is read; this bounds a damaged one too).
const MAX_DEPTH: usize = 64;

impl Scene {
    /// The named groups, in the order they were first defined.
    pub fn groups(&self) -> &Groups {
        &self.groups
    }

    /// The indices (ascending) of the particles in `range` now: a static group's members
    /// that still exist, a dynamic group's range evaluated on the particles as they are. An
    /// error names a group the range refers to that is not defined.
    pub fn members(&self, range: &Range) -> Result<Vec<usize>, String> {
        self.check_names(range)?;
        let p = &self.particles;
        Ok((0..p.len())
            .filter(|&i| self.in_range(range, i, 0))
            .collect())
    }

    /// Every group a range names (and those they name) exists.
    fn check_names(&self, range: &Range) -> Result<(), String> {
        for n in range.groups_named() {
            if self.groups.get(n).is_none() {
                let known: Vec<&str> = self.groups.list.iter().map(|g| g.name.as_str()).collect();
                return Err(if known.is_empty() {
                    format!("group `{n}` is not defined (no group is: GROup name ... defines one)")
                } else {
                    format!(
                        "group `{n}` is not defined (the groups are {})",
                        known.join(", ")
                    )
                });
            }
        }
        Ok(())
    }

    fn candidate(&self, i: usize) -> Candidate {
        let p = &self.particles;
        let x = p.pos[i];
        Candidate {
            id: p.id[i],
            pos: [x.x, x.y, x.z],
            material: p.material[i],
            size: p.size[i],
            periods: crate::sim::range::Periods {
                size: self.size,
                periodic: self.settings.periodic,
                shift: self.cell.shift,
            },
        }
    }

    fn in_range(&self, range: &Range, i: usize, depth: usize) -> bool {
        let c = self.candidate(i);
        range.contains(&c, &mut |name| self.in_group(name, i, depth + 1))
    }

    fn in_group(&self, name: &str, i: usize, depth: usize) -> bool {
        if depth > MAX_DEPTH {
            return false;
        }
        match self.groups.get(name) {
            None => false,
            Some(Group { ids: Some(ids), .. }) => ids.binary_search(&self.particles.id[i]).is_ok(),
            Some(Group { range, .. }) => self.in_range(range, i, depth),
        }
    }

    /// `GROup name [DYNamic] range`: defines (or redefines) a group; a static one takes the
    /// ids of the particles in the range now. Refused, changing nothing, if the range names
    /// an undefined group or the group would contain itself through dynamic groups.
    pub fn define_group(
        &mut self,
        name: &str,
        range: &Range,
        dynamic: bool,
    ) -> Result<String, String> {
        self.check_names(range)?;
        if self.groups.get(name).is_none() && self.groups.list.len() >= MAX_GROUPS {
            return Err(format!(
                "a scene holds at most {MAX_GROUPS} groups: GROup name FORget removes one"
            ));
        }
        let members = self.members(range)?;
        let ids = if dynamic {
            if let Some(c) = self.groups.circle(name, range) {
                return Err(format!(
                    "group `{name}` would contain itself: {} (a dynamic group may not name itself, directly or through dynamic groups)",
                    c.join(" -> ")
                ));
            }
            None
        } else {
            let mut ids: Vec<u32> = members.iter().map(|&i| self.particles.id[i]).collect();
            ids.sort_unstable();
            Some(ids)
        };
        let kind = if dynamic {
            "dynamic: its range is evaluated whenever it is used"
        } else {
            "static: these particles' ids"
        };
        self.groups.put(Group {
            name: name.to_string(),
            range: range.clone(),
            ids,
            record: false,
            rows: Vec::new(),
            fix: None,
        });
        Ok(format!(
            "group {name}: {} particles now ({kind})",
            members.len()
        ))
    }

    /// `Fix ix iy iz irx iry irz GROup name` over a dynamic group: its members now get the
    /// degrees of freedom (bit k for x y z rx ry rz), and the Fix stands: it is applied
    /// again before every step of a Cycle ([`Scene::apply_standing_fixes`]). All zeros frees
    /// the members and ends it. The group may be empty now: particles may enter it later.
    pub fn fix_dynamic_group(&mut self, name: &str, bits: u8) -> Result<String, String> {
        let m = self.members(&Range::group(name))?;
        let Some(k) = self.groups.list.iter().position(|g| g.name == name) else {
            return Err(format!("group `{name}` is not defined"));
        };
        // (The particles a Fix standing before fixed and that have left are freed too.)
        let ids = self.groups.list[k]
            .fix
            .take()
            .map(|f| f.ids)
            .unwrap_or_default();
        self.groups.list[k].fix = Some(StandingFix { bits, ids });
        self.apply_standing_fix(k);
        if bits == 0 {
            self.groups.list[k].fix = None;
            return Ok(format!(
                "freed {} particles (no Fix stands on group {name})",
                m.len()
            ));
        }
        Ok(format!(
            "fixed {} particles; the Fix stands on the dynamic group {name}: applied again before every step",
            m.len()
        ))
    }

    /// Before each step of a Cycle: every standing Fix of a dynamic group applied again.
    pub(in crate::sim) fn apply_standing_fixes(&mut self) {
        for k in 0..self.groups.list.len() {
            if self.groups.list[k].fix.is_some() {
                self.apply_standing_fix(k);
            }
        }
    }

    /// The standing Fix of group `k`: its members now get its degrees of freedom, the
    /// particles it fixed that are no longer members are freed.
    fn apply_standing_fix(&mut self, k: usize) {
        let Some(fix) = self.groups.list[k].fix.take() else {
            return;
        };
        let name = self.groups.list[k].name.clone();
        // (An undefined group inside the range was refused when it was defined.)
        let members = self.members(&Range::group(&name)).unwrap_or_default();
        let mut ids: Vec<u32> = members.iter().map(|&i| self.particles.id[i]).collect();
        ids.sort_unstable();
        let p = &mut self.particles;
        for i in 0..p.id.len() {
            let id = p.id[i];
            if fix.ids.binary_search(&id).is_ok() && ids.binary_search(&id).is_err() {
                p.fixed[i] = 0;
            }
        }
        for &i in &members {
            p.fixed[i] = fix.bits;
        }
        self.groups.list[k].fix = Some(StandingFix {
            bits: fix.bits,
            ids,
        });
    }

    /// `GROup name FORget`: removes a group no dynamic group names.
    pub fn forget_group(&mut self, name: &str) -> Result<String, String> {
        self.check_names(&Range::group(name))?;
        let users = self.groups.users_of(name);
        if !users.is_empty() {
            return Err(format!(
                "group `{name}` is named by the dynamic group(s) {}: forget or redefine them first",
                users.join(", ")
            ));
        }
        self.groups.remove(name);
        Ok(format!("group {name} forgotten"))
    }

    /// `GROup name HIStory [OFF]`: the group's quantities recorded with every history row
    /// (`SET HIStory n`), or no longer; the rows recorded stay.
    pub fn record_group(&mut self, name: &str, on: bool) -> Result<String, String> {
        self.check_names(&Range::group(name))?;
        if let Some(g) = self.groups.list.iter_mut().find(|g| g.name == name) {
            g.record = on;
        }
        let every = self.settings.history_every;
        Ok(match (on, every) {
            (false, _) => format!("group {name}: no longer recorded in the history"),
            (true, 0) => format!(
                "group {name}: recorded in the history once SET HIStory n records (it is off)"
            ),
            (true, n) => format!("group {name}: recorded in the history every {n} cycles"),
        })
    }

    /// The groups of a decoded checkpoint: names unique, static ids sorted, no circle.
    pub(super) fn check_groups(&self) -> Result<(), String> {
        let gs = &self.groups;
        if gs.list.len() > MAX_GROUPS {
            return Err("too many groups".into());
        }
        for (k, g) in gs.list.iter().enumerate() {
            if gs.list[..k].iter().any(|h| h.name == g.name) {
                return Err(format!("two groups are named `{}`", g.name));
            }
            if g.range.any.is_empty() || g.range.any.iter().any(|a| a.is_empty()) {
                return Err(format!("group `{}` has an empty range", g.name));
            }
            let width = crate::sim::range::QUANTITIES.len() + 1;
            if g.rows.iter().any(|r| r.len() != width)
                || g.rows.windows(2).any(|w| !(w[0][0] < w[1][0]))
            {
                return Err(format!("group `{}` has malformed history rows", g.name));
            }
            if let Some(ids) = &g.ids
                && ids.windows(2).any(|w| w[0] >= w[1])
            {
                return Err(format!("group `{}` has unsorted ids", g.name));
            }
            if let Some(f) = &g.fix
                && (g.ids.is_some() || f.ids.windows(2).any(|w| w[0] >= w[1]))
            {
                return Err(format!(
                    "group `{}` has a malformed standing Fix (on a static group, or unsorted ids)",
                    g.name
                ));
            }
            if g.ids.is_none() {
                if let Some(n) = g
                    .range
                    .groups_named()
                    .into_iter()
                    .find(|n| gs.get(n).is_none())
                {
                    return Err(format!(
                        "group `{}` names the undefined group `{n}`",
                        g.name
                    ));
                }
                if let Some(c) = gs.circle(&g.name, &g.range) {
                    return Err(format!(
                        "group `{}` contains itself: {}",
                        g.name,
                        c.join(" -> ")
                    ));
                }
            }
        }
        Ok(())
    }
}
