//! The structure of a block's lines: which lines an IF, LOOP, WHILE or DEFine holds, found
//! by the lines' first words before anything runs (an ELSE or END out of place, or a block
//! left open, is refused with its line).

use super::{Opener, SrcLine, Word, word_of};
use crate::session::LineError;

/// A statement: one line, or a block with the index of its opening line.
#[derive(Debug, PartialEq)]
pub enum Stmt {
    Line(usize),
    If {
        at: usize,
        then: Vec<Stmt>,
        /// The ELSE line and what follows it.
        otherwise: Option<(usize, Vec<Stmt>)>,
    },
    /// LOOP or WHILE: which one, the opening line says.
    Loop {
        at: usize,
        body: Vec<Stmt>,
    },
    /// DEFine: the body is the lines between `at` and `end`, stored, not run.
    Define {
        at: usize,
        end: usize,
    },
}

/// The statements of `lines`; an error names the index of its line.
pub fn build(lines: &[SrcLine]) -> Result<Vec<Stmt>, (usize, LineError)> {
    let words: Vec<Word> = lines.iter().map(|l| word_of(&l.text)).collect();
    let mut pos = 0;
    let out = seq(lines, &words, &mut pos, None)?;
    Ok(out)
}

fn whole(l: &SrcLine, message: String) -> LineError {
    LineError {
        start: l.text.len() - l.text.trim_start().len(),
        end: l.text.trim_end().len().max(1),
        message,
    }
}

fn first_word(l: &SrcLine) -> String {
    l.text
        .split_whitespace()
        .next()
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// Statements up to the END of the block opened at `open` (or to the end of the lines).
fn seq(
    lines: &[SrcLine],
    words: &[Word],
    pos: &mut usize,
    open: Option<usize>,
) -> Result<Vec<Stmt>, (usize, LineError)> {
    let mut out = Vec::new();
    while *pos < lines.len() {
        let i = *pos;
        match words[i] {
            Word::End | Word::Else if open.is_some() => return Ok(out),
            Word::End | Word::Else => {
                return Err((
                    i,
                    whole(
                        &lines[i],
                        "ELSE and END close a block: no IF, LOOP, WHILE or DEFine is open here"
                            .into(),
                    ),
                ));
            }
            Word::Other => {
                out.push(Stmt::Line(i));
                *pos += 1;
            }
            Word::Open(kind) => {
                *pos += 1;
                let is_if = kind == Opener::If;
                let is_def = kind == Opener::Define;
                if is_def {
                    // The body is kept as text: only its END is looked for.
                    let mut depth = 1;
                    while *pos < lines.len() {
                        match words[*pos] {
                            Word::Open(_) => depth += 1,
                            Word::End => depth -= 1,
                            _ => {}
                        }
                        if depth == 0 {
                            break;
                        }
                        *pos += 1;
                    }
                    closed(lines, words, *pos, i)?;
                    out.push(Stmt::Define { at: i, end: *pos });
                    *pos += 1;
                    continue;
                }
                let then = seq(lines, words, pos, Some(i))?;
                closed(lines, words, *pos, i)?;
                if words[*pos] == Word::Else {
                    if !is_if {
                        return Err((
                            *pos,
                            whole(
                                &lines[*pos],
                                "ELSE belongs to an IF, not to a LOOP or WHILE".into(),
                            ),
                        ));
                    }
                    let e = *pos;
                    *pos += 1;
                    let other = seq(lines, words, pos, Some(i))?;
                    closed(lines, words, *pos, i)?;
                    if words[*pos] == Word::Else {
                        return Err((*pos, whole(&lines[*pos], "a second ELSE in one IF".into())));
                    }
                    out.push(Stmt::If {
                        at: i,
                        then,
                        otherwise: Some((e, other)),
                    });
                } else if is_if {
                    out.push(Stmt::If {
                        at: i,
                        then,
                        otherwise: None,
                    });
                } else {
                    out.push(Stmt::Loop { at: i, body: then });
                }
                *pos += 1;
            }
        }
    }
    Ok(out)
}

/// The block opened at `open` must have its END (or ELSE) at `pos`.
fn closed(
    lines: &[SrcLine],
    words: &[Word],
    pos: usize,
    open: usize,
) -> Result<(), (usize, LineError)> {
    if pos < lines.len() && matches!(words[pos], Word::End | Word::Else) {
        return Ok(());
    }
    Err((
        open,
        whole(
            &lines[open],
            format!(
                "this {} is not closed: END is missing",
                first_word(&lines[open]).to_uppercase()
            ),
        ),
    ))
}
