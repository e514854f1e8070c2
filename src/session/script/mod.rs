//! The programmable part of a session (doc/language.md): variables, procedures, blocks
//! (`IF`, `LOOP`, `WHILE`, `DEFine` ... `END`), `INClude`, and the hooks of a `Cycle`
//! (`CALL name EVery k`, `UNTIL cond`).
//!
//! A block is read whole before it runs: the lines from its opening word to the matching
//! `END` are kept with their file and line number, then run. Every line of a block is
//! substituted (`$name`), parsed and run when it is reached, as a line of the file would be,
//! so its errors name its own file, line and column. The variables and procedures
//! ([`ScriptState`]) are part of a checkpoint.

mod block;
mod cycle;
pub mod history;
pub mod query;
mod run;

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::{Flow, LineError, Session, Source, format_error};
use crate::lang::lexer::{first_token, tokenize};
use crate::lang::table::{COMMANDS, command_keywords, find_command};

pub use cycle::{Hooks, Until};

/// One line of a block or procedure, with where it was read.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SrcLine {
    pub file: String,
    pub line: usize,
    pub text: String,
}

impl SrcLine {
    fn source(&self) -> Source {
        Source {
            name: self.file.clone(),
            line: self.line,
        }
    }
    /// The error `e` of this line, formatted with its file, line and column.
    fn error(&self, e: &LineError) -> String {
        format_error(&self.source(), &self.text, e)
    }
}

/// A procedure: its parameters and the lines of its body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Proc {
    pub params: Vec<String>,
    pub body: Vec<SrcLine>,
}

/// What a checkpoint holds of the language: the variables and the procedures.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ScriptState {
    pub vars: BTreeMap<String, f64>,
    pub procs: BTreeMap<String, Proc>,
    /// `HIStory name EVery k expr`, in the order defined.
    pub histories: Vec<history::UserHistory>,
}

/// Most passes of one LOOP or WHILE; more is a runaway loop.
pub const MAX_PASSES: u64 = 1_000_000;
/// Deepest nesting of procedure calls (a procedure may call itself).
pub const MAX_CALLS: usize = 64;
/// Deepest nesting of INClude.
pub const MAX_INCLUDES: usize = 16;

/// The interpreter's state in a session.
#[derive(Default)]
pub struct Interp {
    pub state: ScriptState,
    /// The block being read at the top level: its lines, the opening one first.
    pending: Vec<SrcLine>,
    /// Open blocks among the pending lines.
    depth: usize,
    /// The opening line of the pending block failed to parse: the block is skipped.
    pending_bad: bool,
    /// BREak or RETurn given, not yet answered by its loop or procedure.
    signal: Option<Signal>,
    /// Loops and procedure calls being run (BREak and RETurn need one).
    loops: usize,
    /// A procedure called by a Cycle's CALL is running (it may not cycle).
    pub(in crate::session) in_hook: bool,
    calls: Vec<String>,
    includes: usize,
    /// An error of a nested line, already formatted (the lines that led to it add a note).
    nested: Option<String>,
    /// The hooks of the Cycle being run.
    pub hooks: Option<Hooks>,
    /// Where in its line the expression of the failing command failed.
    span: std::cell::Cell<Option<LineError>>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Signal {
    Break,
    Return,
}

/// What a line's first word does to the block structure.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Word {
    Open(Opener),
    Else,
    End,
    Other,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Opener {
    If,
    Loop,
    While,
    Define,
}

/// The block role of a line (by its first word, without substitution).
fn word_of(text: &str) -> Word {
    let Some(t) = first_token(text) else {
        return Word::Other;
    };
    let keys = command_keywords();
    match find_command(&t.text, keys).map(|i| COMMANDS[i].name) {
        Ok("IF") => Word::Open(Opener::If),
        Ok("LOOP") => Word::Open(Opener::Loop),
        Ok("WHILE") => Word::Open(Opener::While),
        Ok("DEFine") => Word::Open(Opener::Define),
        Ok("ELSE") => Word::Else,
        Ok("END") => Word::End,
        _ => Word::Other,
    }
}

impl Session {
    /// Runs one line read from `src` (a file, standard input or the terminal): a line of a
    /// block being read is kept until its `END`; errors come formatted with their file,
    /// line and column (a line of a block or procedure names its own).
    pub fn feed(&mut self, src: &Source, text: &str) -> Result<Flow, String> {
        let line = SrcLine {
            file: src.name.clone(),
            line: src.line,
            text: text.to_string(),
        };
        if !self.script.pending.is_empty() {
            match word_of(text) {
                Word::Open(_) => self.script.depth += 1,
                Word::End => self.script.depth -= 1,
                _ => {}
            }
            self.script.pending.push(line);
            if self.script.depth > 0 {
                return Ok(Flow::Continue);
            }
            let lines = std::mem::take(&mut self.script.pending);
            if std::mem::take(&mut self.script.pending_bad) {
                return Ok(Flow::Continue);
            }
            return self.run_lines(&lines);
        }
        match word_of(text) {
            Word::Open(_) => {
                self.script.pending.push(line.clone());
                self.script.depth = 1;
                // The opening line's syntax is checked now (its expressions are read
                // when it runs).
                if let Err(e) = self.parse_only(text) {
                    self.script.pending_bad = true;
                    return Err(line.error(&e));
                }
                Ok(Flow::Continue)
            }
            Word::Else | Word::End => {
                let e = LineError {
                    start: 0,
                    end: text.trim_end().len().max(1),
                    message:
                        "ELSE and END close a block: no IF, LOOP, WHILE or DEFine is open here"
                            .into(),
                };
                Err(format_error(src, text, &e))
            }
            Word::Other => self.run_one(&line),
        }
    }

    /// At the end of a file or of standard input: a block left open is an error (its lines
    /// are dropped).
    pub fn end_of_input(&mut self) -> Option<String> {
        let lines = std::mem::take(&mut self.script.pending);
        self.script.depth = 0;
        self.script.pending_bad = false;
        let first = lines.first()?;
        Some(unclosed(first))
    }

    /// Whether a block is being read (the terminal's prompt says so).
    pub fn in_block(&self) -> bool {
        !self.script.pending.is_empty()
    }

    /// The lines of a block, read whole: checked for structure, then run.
    fn run_lines(&mut self, lines: &[SrcLine]) -> Result<Flow, String> {
        let stmts = block::build(lines).map_err(|(i, e)| lines[i].error(&e))?;
        let r = self.exec(lines, &stmts);
        self.script.signal = None;
        r
    }

    /// Parses a line with the session's names, running nothing.
    fn parse_only(&self, text: &str) -> Result<(), LineError> {
        let line = self.substituted(text)?;
        crate::lang::parse_line_in(&line, &self.names())
            .map(|_| ())
            .map_err(|e| LineError {
                start: e.start,
                end: e.end,
                message: e.message,
            })
    }

    /// The names expressions see now: the variables and the scene.
    pub(super) fn names(&self) -> query::Names<'_> {
        query::Names {
            vars: &self.script.state.vars,
            scene: self.scene.as_ref(),
        }
    }

    /// The line with its `$name`s replaced: by `--set` values, else by variables.
    pub(super) fn substituted(&self, raw: &str) -> Result<String, LineError> {
        if !raw.contains('$') {
            return Ok(raw.to_string());
        }
        let mut all = self.vars.clone();
        for p in super::vars::placeholders(raw)? {
            if !all.contains_key(&p.name)
                && let Some(v) = self.script.state.vars.get(&p.name.to_ascii_lowercase())
            {
                all.insert(p.name.clone(), format!("{v}"));
            }
        }
        super::vars::substitute(raw, &all)
    }

    /// Runs one line that is not part of a block being read; a nested error (from a
    /// procedure or an included file) comes as it was formatted there.
    fn run_one(&mut self, line: &SrcLine) -> Result<Flow, String> {
        match self.run_line(&line.text) {
            Ok(f) => Ok(f),
            Err(e) => Err(match self.script.nested.take() {
                Some(inner) => format!("{inner}\n{}", note(line)),
                None => line.error(&e),
            }),
        }
    }

    /// A script command (`Command::Script`), from `Session::execute`.
    pub(super) fn script_command(
        &mut self,
        c: &crate::lang::script::ScriptCmd,
    ) -> Result<Flow, String> {
        self.script.span.set(None);
        self.script_cmd(c)
    }

    /// The located error of the script command that just failed, if it was in an expression.
    pub(super) fn take_span(&self) -> Option<LineError> {
        self.script.span.take()
    }

    /// Whether the rest of the line is to be skipped (BREak or RETurn was given).
    pub(super) fn line_cut(&self) -> bool {
        self.script.signal.is_some()
    }
}

/// The note an error from a nested line gets from the line that led to it.
fn note(line: &SrcLine) -> String {
    format!(
        "  (from {}:{}: `{}`)",
        line.file,
        line.line,
        line.text.trim()
    )
}

/// The error of a block not closed by END.
fn unclosed(first: &SrcLine) -> String {
    let w = tokenize(&first.text)
        .first()
        .map(|t| t.text.clone())
        .unwrap_or_default();
    let e = LineError {
        start: 0,
        end: w.len().max(1),
        message: format!(
            "this {} is not closed: END is missing before the end of the input",
            w.to_uppercase()
        ),
    };
    first.error(&e)
}
