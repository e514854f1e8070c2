//! Where lines come from: a command file, standard input, TRUBAL.DIR/TRUBAL.DAT batch mode,
//! or an interactive terminal (rustyline: line editing, history file, completion, help).

use std::io::{BufRead, Read};

use rustyline::completion::{Completer, Pair};
use rustyline::error::ReadlineError;
use rustyline::{Context, Helper, highlight::Highlighter, hint::Hinter, validate::Validator};

use super::{Flow, Session, Source, format_error};
use crate::lang::table::COMMANDS;

/// Runs lines from a reader. Returns the number of errors. With `keep_going` false the first
/// error stops the run.
pub fn run_reader(session: &mut Session, name: &str, text: &[u8], keep_going: bool) -> usize {
    let text = String::from_utf8_lossy(text);
    let mut errors = 0;
    for (k, line) in text.lines().enumerate() {
        let src = Source {
            name: name.to_string(),
            line: k + 1,
        };
        match session.run_line(line) {
            Ok(Flow::Stop) => break,
            Ok(Flow::Continue) => {}
            Err(e) => {
                errors += 1;
                let msg = format_error(&src, line, &e);
                session.emit_err(&msg);
                if !keep_going {
                    break;
                }
            }
        }
    }
    session.flush();
    errors
}

/// Runs a command file.
pub fn run_file(session: &mut Session, path: &str, keep_going: bool) -> Result<usize, String> {
    let data = std::fs::read(path).map_err(|e| format!("cannot read {path}: {e}"))?;
    Ok(run_reader(session, path, &data, keep_going))
}

/// Runs standard input (a pipe or `-`).
pub fn run_stdin(session: &mut Session, keep_going: bool) -> usize {
    let mut data = Vec::new();
    let _ = std::io::stdin().lock().read_to_end(&mut data);
    run_reader(session, "<stdin>", &data, keep_going)
}

/// TRUBAL.DIR in the working directory containing BATCH.
pub fn batch_requested() -> bool {
    std::fs::read_to_string("TRUBAL.DIR")
        .map(|s| s.to_ascii_uppercase().contains("BATCH"))
        .unwrap_or(false)
}

/// Completion of command names and their keywords.
pub struct TrubalHelper;

impl Completer for TrubalHelper {
    type Candidate = Pair;
    fn complete(
        &self,
        line: &str,
        pos: usize,
        _ctx: &Context<'_>,
    ) -> rustyline::Result<(usize, Vec<Pair>)> {
        let (start, word, first) = word_at(line, pos);
        Ok((start, completions(&line[..start], word, first)))
    }
}

fn word_at(line: &str, pos: usize) -> (usize, &str, bool) {
    let before = &line[..pos];
    let start = before
        .rfind(|c: char| c.is_whitespace() || ",/()".contains(c))
        .map(|i| i + 1)
        .unwrap_or(0);
    let first = before[..start].trim().is_empty();
    (start, &before[start..], first)
}

/// Candidates for the word being typed: command names at the start of a line, else keywords
/// of the line's command.
pub fn completions(prefix_line: &str, word: &str, first: bool) -> Vec<Pair> {
    let w = word.to_ascii_lowercase();
    let mut out = Vec::new();
    if first {
        for d in COMMANDS {
            if d.name.to_ascii_lowercase().starts_with(&w) {
                out.push(Pair {
                    display: format!("{} {}", d.name, d.syntax),
                    replacement: d.name.to_ascii_lowercase(),
                });
            }
        }
    } else {
        let cmd = prefix_line.split_whitespace().next().unwrap_or("");
        let keys = crate::lang::table::command_keywords();
        if let Ok(i) = crate::lang::keyword::match_keyword(cmd, &keys) {
            for k in COMMANDS[i].keywords {
                if k.to_ascii_lowercase().starts_with(&w) {
                    out.push(Pair {
                        display: k.to_string(),
                        replacement: k.to_ascii_lowercase(),
                    });
                }
            }
        }
    }
    out
}

impl Hinter for TrubalHelper {
    type Hint = String;
}
impl Highlighter for TrubalHelper {}
impl Validator for TrubalHelper {}
impl Helper for TrubalHelper {}

/// Interactive session on a terminal.
pub fn run_interactive(session: &mut Session) -> Result<(), String> {
    let mut rl = rustyline::Editor::<TrubalHelper, rustyline::history::DefaultHistory>::new()
        .map_err(|e| format!("cannot start the line editor: {e}"))?;
    rl.set_helper(Some(TrubalHelper));
    let hist = std::env::var_os("HOME")
        .map(|h| std::path::PathBuf::from(h).join(".trubal_history"))
        .unwrap_or_else(|| ".trubal_history".into());
    let _ = rl.load_history(&hist);
    session.emit("trubal — DEM of spheres. `help` lists the commands, `help NAME` explains one, `stop` ends.");
    let mut n = 0;
    loop {
        match rl.readline("trubal> ") {
            Ok(line) => {
                n += 1;
                if !line.trim().is_empty() {
                    let _ = rl.add_history_entry(line.as_str());
                }
                match session.run_line(&line) {
                    Ok(Flow::Stop) => break,
                    Ok(Flow::Continue) => {}
                    Err(e) => {
                        let src = Source {
                            name: "<terminal>".into(),
                            line: n,
                        };
                        session.emit_err(&format_error(&src, &line, &e));
                    }
                }
                session.flush();
            }
            Err(ReadlineError::Interrupted) => continue,
            Err(ReadlineError::Eof) => break,
            Err(e) => return Err(format!("terminal error: {e}")),
        }
    }
    let _ = rl.save_history(&hist);
    Ok(())
}

/// Reads lines from any BufRead (used by tests).
pub fn lines_of<R: BufRead>(r: R) -> Vec<String> {
    r.lines().map_while(Result::ok).collect()
}
