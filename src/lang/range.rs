//! Reads a range (doc/groups.md) from a command's words: conditions `BOX`, `SPHere`,
//! `CYLinder`, `ID`, `MATerial`, `SIZe`, `GROup`, each may be preceded by `NOT`; all the
//! conditions of an alternative must hold, and `OR` starts another alternative. The range
//! ends at the first word that is none of these (the next command of the line).

use super::args::{Args, ParseError};
use super::keyword::{Keyword, kw};
use crate::sim::range::{Condition, Range, Term};

#[derive(Clone, Copy, PartialEq)]
enum Word {
    Box,
    Sphere,
    Cylinder,
    Id,
    Material,
    Size,
    Group,
    Not,
    Or,
}

/// The words of a range, as `help` and `doc/commands.md` list them.
pub const RANGE_WORDS: &[&str] = &[
    "BOX", "SPHere", "CYLinder", "ID", "MATerial", "SIZe", "GROup", "NOT", "OR",
];

const WORDS: &[Keyword<Word>] = &[
    kw("BOX", Word::Box),
    kw("SPHere", Word::Sphere),
    kw("CYLinder", Word::Cylinder),
    kw("ID", Word::Id),
    kw("MATerial", Word::Material),
    kw("SIZe", Word::Size),
    kw("GROup", Word::Group),
    kw("NOT", Word::Not),
    kw("OR", Word::Or),
];

/// The syntax of a range, for the commands' syntax lines.
pub const SYNTAX: &str = "range";

/// The longest group name.
pub const MAX_NAME: usize = 32;

/// Whether the next word starts a range.
pub fn starts_range(a: &Args) -> bool {
    a.peek()
        .is_some_and(|t| super::keyword::match_keyword(&t.text, WORDS).is_ok())
}

/// A range, required: at least one condition.
pub fn range(a: &mut Args) -> Result<Range, ParseError> {
    let mut any: Vec<Vec<Term>> = Vec::new();
    let mut all: Vec<Term> = Vec::new();
    let mut not = false;
    loop {
        let tok = a.peek();
        let Some(w) = a.try_keyword(WORDS)? else {
            break;
        };
        // (Invariant: a keyword was read, so a token was there.)
        let t = tok.expect("a keyword was read");
        match w {
            Word::Not => {
                if not {
                    return Err(ParseError::at(t, "NOT NOT: say the condition itself"));
                }
                not = true;
                if !starts_range(a)
                    || a.peek()
                        .is_some_and(|n| is(n, Word::Not) || is(n, Word::Or))
                {
                    return Err(after(
                        a,
                        t,
                        "NOT needs a condition after it (BOX, SPHere, CYLinder, ID, MATerial, SIZe or GROup)",
                    ));
                }
            }
            Word::Or => {
                if all.is_empty() {
                    return Err(ParseError::at(t, "OR needs a condition before it"));
                }
                any.push(std::mem::take(&mut all));
                if !starts_range(a) || a.peek().is_some_and(|n| is(n, Word::Or)) {
                    return Err(after(
                        a,
                        t,
                        "OR needs a condition after it (BOX, SPHere, CYLinder, ID, MATerial, SIZe, GROup or NOT)",
                    ));
                }
            }
            _ => {
                let cond = condition(a, w)?;
                all.push(Term { not, cond });
                not = false;
            }
        }
    }
    if all.is_empty() {
        return Err(match a.peek() {
            Some(t) => ParseError::at(
                t,
                format!(
                    "expected a range (BOX, SPHere, CYLinder, ID, MATerial, SIZe, GROup, NOT), found `{}` (syntax: {} {})",
                    t.text, a.command, a.syntax
                ),
            ),
            None => ParseError {
                start: a.line_end,
                end: a.line_end + 1,
                message: format!(
                    "{} needs a range here: BOX, SPHere, CYLinder, ID, MATerial, SIZe or GROup (syntax: {} {})",
                    a.command, a.command, a.syntax
                ),
            },
        });
    }
    any.push(all);
    Ok(Range { any })
}

fn is(t: &super::lexer::Token, w: Word) -> bool {
    super::keyword::match_keyword(&t.text, WORDS).is_ok_and(|x| x == w)
}

/// An error at the word after `t`, or at `t` when the line ends there.
fn after(a: &Args, t: &super::lexer::Token, msg: &str) -> ParseError {
    match a.peek() {
        Some(n) => ParseError::at(n, format!("{msg}, found `{}`", n.text)),
        None => ParseError::at(t, msg),
    }
}

fn condition(a: &mut Args, w: Word) -> Result<Condition, ParseError> {
    Ok(match w {
        Word::Box => {
            let mut b = [0.0; 6];
            for (k, n) in ["x1", "x2", "y1", "y2", "z1", "z2"].into_iter().enumerate() {
                let t = a.peek();
                b[k] = a.real(n)?;
                if k % 2 == 1 && b[k] < b[k - 1] {
                    let lo = ["x1", "y1", "z1"][k / 2];
                    return Err(ParseError::at(
                        t.expect("real() consumed a token"),
                        format!(
                            "BOX: `{n}` must not be below `{lo}` ({} < {})",
                            b[k],
                            b[k - 1]
                        ),
                    ));
                }
            }
            Condition::Box(b)
        }
        Word::Sphere => Condition::Sphere {
            centre: a.vec3(["xc", "yc", "zc"])?,
            radius: a.positive("r")?,
        },
        Word::Cylinder => {
            let point = a.vec3(["x", "y", "z"])?;
            let t = a.peek();
            let axis = a.vec3(["ax", "ay", "az"])?;
            if axis.iter().all(|&c| c == 0.0) || axis.iter().any(|c| !c.is_finite()) {
                return Err(ParseError::at(
                    t.expect("vec3() consumed a token"),
                    "CYLinder: the axis (ax, ay, az) must be a finite, non-zero direction",
                ));
            }
            Condition::Cylinder {
                point,
                axis,
                radius: a.positive("r")?,
            }
        }
        Word::Id => Condition::Ids(ids(a)?),
        Word::Material => Condition::Material(types(a, "mtyp", true)?),
        Word::Size => Condition::Size(types(a, "isize", false)?),
        Word::Group => Condition::Group(group_name(a)?),
        Word::Not | Word::Or => {
            return Err(ParseError {
                start: a.line_end,
                end: a.line_end + 1,
                message: "internal: NOT and OR are read by the range".into(),
            });
        }
    })
}

/// `ID i [TO j] ...`: one or more ids or closed intervals.
fn ids(a: &mut Args) -> Result<Vec<(u32, u32)>, ParseError> {
    const TO: &[Keyword<()>] = &[kw("TO", ())];
    let mut spans = Vec::new();
    loop {
        let lo = a.int_in("id", 1, u32::MAX as i64)? as u32;
        let hi = if a.try_keyword(TO)?.is_some() {
            let t = a.peek();
            let hi = a.int_in("id", 1, u32::MAX as i64)? as u32;
            if hi < lo {
                return Err(ParseError::at(
                    t.expect("int_in() consumed a token"),
                    format!("ID {lo} TO {hi}: the last id is below the first"),
                ));
            }
            hi
        } else {
            lo
        };
        spans.push((lo, hi));
        if !a.peek_is_number() {
            return Ok(spans);
        }
    }
}

/// One or more material or size types.
fn types(a: &mut Args, name: &str, material: bool) -> Result<Vec<u16>, ParseError> {
    let mut v = Vec::new();
    loop {
        let k = if material {
            a.material_type(name)?
        } else {
            a.size_type(name)?
        };
        v.push(k as u16);
        if !a.peek_is_number() {
            return Ok(v);
        }
    }
}

/// A group's name: a letter, then letters, digits, `_`, `-` or `.`, at most [`MAX_NAME`]
/// characters; case does not matter (kept in lower case). `ALL` is reserved (`PRint GROup
/// ALL`).
pub fn group_name(a: &mut Args) -> Result<String, ParseError> {
    let t = a.next_tok("a group name")?;
    let s = &t.text;
    let ok = s.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
        && s.len() <= MAX_NAME;
    if !ok {
        return Err(ParseError::at(
            t,
            format!(
                "`{s}` is not a group name: a letter, then letters, digits, `_`, `-` or `.`, at most {MAX_NAME} characters"
            ),
        ));
    }
    if s.eq_ignore_ascii_case("all") {
        return Err(ParseError::at(
            t,
            "`ALL` is not a group name: PRint GROup ALL means every group",
        ));
    }
    Ok(s.to_ascii_lowercase())
}
