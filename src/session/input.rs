//! Where lines come from: a command file, standard input, TRUBAL.DIR/TRUBAL.DAT batch mode,
//! or an interactive terminal (rustyline: line editing, history file, completion, help).

use std::io::{BufRead, Read};

use rustyline::completion::{Completer, Pair};
use rustyline::error::ReadlineError;
use rustyline::{Context, Helper, highlight::Highlighter, hint::Hinter, validate::Validator};

use super::{Flow, Session, Source};
use crate::lang::table::COMMANDS;

/// The longest command line read (a command file's lines are short; a longer one is a
/// binary or generated file by mistake, refused before it is parsed).
pub const MAX_LINE: usize = 1 << 20;

/// How a command file or standard input ended.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct RunEnd {
    /// Lines that failed.
    pub errors: usize,
    /// Ctrl-C stopped the run (exit code 130).
    pub interrupted: bool,
}

/// Runs the lines of a command file or a pipe, in order, each as it is read. With
/// `keep_going` false the first error stops the run; Ctrl-C stops it after the current line
/// (a `Cycle` at the end of its current step).
struct Runner<'a> {
    session: &'a mut Session,
    name: &'a str,
    keep_going: bool,
    line: usize,
    end: RunEnd,
}

impl Runner<'_> {
    /// Runs one line (raw bytes, without its newline; `len` is its length, more than
    /// `raw` holds when a too-long line was not kept); false when the run stops here.
    fn feed(&mut self, raw: &[u8], len: usize) -> bool {
        let go = self.feed_line(raw, len);
        if !go {
            // A block being read is dropped with the rest of the input.
            self.session.end_of_input();
        }
        go
    }

    /// At the end of the input: a block left open is an error.
    fn finish(&mut self) {
        if let Some(msg) = self.session.end_of_input() {
            self.end.errors += 1;
            self.session.emit_err(&msg);
        }
    }

    fn feed_line(&mut self, raw: &[u8], len: usize) -> bool {
        self.line += 1;
        let mut raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        if self.line == 1 {
            // A UTF-16 file (an editor's "Unicode") is named as such instead of read as
            // garbage; a UTF-8 byte-order mark is dropped.
            if raw.starts_with(&[0xff, 0xfe]) || raw.starts_with(&[0xfe, 0xff]) {
                self.session.emit_err(&format!(
                    "{}: the file is encoded as UTF-16 ({}); save it as UTF-8 or plain ASCII",
                    self.name,
                    if raw[0] == 0xff {
                        "little-endian"
                    } else {
                        "big-endian"
                    }
                ));
                self.end.errors += 1;
                return false;
            }
            raw = raw.strip_prefix(&[0xef, 0xbb, 0xbf]).unwrap_or(raw);
        }
        if let Some(why) = binary_line(raw) {
            // Not a command file: one error, and the rest of it is not read.
            self.session.emit_err(&format!(
                "{}:{}: error: this looks like a binary file ({why}), not a command file; nothing more of it is read",
                self.name, self.line
            ));
            self.end.errors += 1;
            return false;
        }
        let src = Source {
            name: self.name.to_string(),
            line: self.line,
        };
        let flow = if len > MAX_LINE {
            Err(too_long(&src, len, raw))
        } else {
            let line = String::from_utf8_lossy(raw);
            self.session.feed(&src, &line)
        };
        // What this line printed is out before the next one runs.
        self.session.flush();
        match flow {
            Ok(Flow::Continue) => {}
            Ok(Flow::Stop) => return false,
            Ok(Flow::Interrupted) => {
                self.end.interrupted = true;
            }
            Err(msg) => {
                self.end.errors += 1;
                self.session.emit_err(&msg);
                if !self.keep_going {
                    return false;
                }
            }
        }
        if self.end.interrupted || super::interrupt::requested() {
            self.end.interrupted = true;
            self.session.emit_err(&format!(
                "{}:{}: interrupted (Ctrl-C): the run stops here; the output so far is complete",
                self.name, self.line
            ));
            return false;
        }
        true
    }
}

/// Why a line is not text, if it is not: it holds NUL bytes (a binary, or UTF-16 without a
/// byte-order mark), or mostly bytes that are neither printable nor blanks (compressed data).
fn binary_line(raw: &[u8]) -> Option<String> {
    let nul = raw.iter().filter(|&&b| b == 0).count();
    if nul > 0 {
        let odd_nul = raw.iter().skip(1).step_by(2).filter(|&&b| b == 0).count();
        let even_nul = raw.iter().step_by(2).filter(|&&b| b == 0).count();
        let half = raw.len() / 2;
        if raw.len() >= 4 && (odd_nul >= half || even_nul >= half) {
            return Some("NUL bytes between the characters: UTF-16 without a byte-order mark? save it as UTF-8".into());
        }
        return Some(format!("{nul} NUL bytes in line of {} bytes", raw.len()));
    }
    let text = String::from_utf8_lossy(raw);
    let (mut bad, mut all) = (0usize, 0usize);
    for c in text.chars() {
        all += 1;
        if c == '\u{fffd}' || (c.is_control() && c != '\t' && c != '\x0c') {
            bad += 1;
        }
    }
    (bad >= 2 && 3 * bad >= all).then(|| format!("{bad} of its {all} characters are not text"))
}

/// The error of a line longer than [`MAX_LINE`] (`len` bytes), quoting its first 60 bytes.
fn too_long(src: &Source, len: usize, raw: &[u8]) -> String {
    let head = String::from_utf8_lossy(&raw[..raw.len().min(60)]);
    format!(
        "{}:{}: error: the line is {len} bytes long, more than the {MAX_LINE} a command line may have (a binary or generated file?): `{}...`",
        src.name,
        src.line,
        head.escape_debug()
    )
}

/// Runs lines from a reader. With `keep_going` false the first error stops the run.
pub fn run_reader(session: &mut Session, name: &str, text: &[u8], keep_going: bool) -> RunEnd {
    let mut r = Runner {
        session,
        name,
        keep_going,
        line: 0,
        end: RunEnd::default(),
    };
    let text = text.strip_suffix(b"\n").unwrap_or(text);
    let mut complete = true;
    if !text.is_empty() {
        for raw in text.split(|&b| b == b'\n') {
            if !r.feed(raw, raw.len()) {
                complete = false;
                break;
            }
        }
    }
    if complete {
        r.finish();
    }
    r.session.flush();
    r.end
}

/// Runs a command file.
pub fn run_file(session: &mut Session, path: &str, keep_going: bool) -> Result<RunEnd, String> {
    let data = std::fs::read(path).map_err(|e| format!("cannot read {path}: {e}"))?;
    Ok(run_reader(session, path, &data, keep_going))
}

/// Runs standard input (a pipe or `-`) line by line as it arrives, so that a program that
/// writes commands and reads the answers can drive the session.
pub fn run_stdin(session: &mut Session, keep_going: bool) -> RunEnd {
    let mut r = Runner {
        session,
        name: "<stdin>",
        keep_going,
        line: 0,
        end: RunEnd::default(),
    };
    let stdin = std::io::stdin();
    let mut input = stdin.lock();
    let mut buf = Vec::new();
    loop {
        buf.clear();
        // At most one byte more than a line may have is kept: a longer line is refused
        // without holding it in memory (the rest of it is skipped).
        let n = match (&mut input)
            .take(MAX_LINE as u64 + 1)
            .read_until(b'\n', &mut buf)
        {
            Ok(n) => n,
            Err(_) => break,
        };
        if n == 0 {
            break;
        }
        let mut len = buf.len();
        if buf.last() == Some(&b'\n') {
            buf.pop();
            len -= 1;
        } else if buf.len() > MAX_LINE {
            let mut rest = Vec::new();
            while let Ok(k) = (&mut input).take(1 << 16).read_until(b'\n', &mut rest) {
                if k == 0 {
                    break;
                }
                len += k;
                if rest.last() == Some(&b'\n') {
                    len -= 1;
                    break;
                }
                rest.clear();
            }
        }
        if !r.feed(&buf, len) {
            break;
        }
    }
    r.finish();
    r.session.flush();
    r.end
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
        if let Ok(i) = crate::lang::keyword::match_keyword(cmd, keys) {
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

/// Interactive session on a terminal: the banner, then lines as they are typed or pasted
/// (several pasted lines run one after the other; lines typed during a long command wait
/// in the line editor's buffer). Ctrl-C at the prompt clears the line; during a command it
/// stops the command (a `Cycle` at the end of its current step) and returns here. The
/// history file is written after every line, so no exit loses it.
pub fn run_interactive(session: &mut Session) -> Result<(), String> {
    let _keep = KeepTypedAhead::on();
    session.emit(BANNER);
    session.flush();
    let mut rl = rustyline::Editor::<TrubalHelper, rustyline::history::DefaultHistory>::new()
        .map_err(|e| format!("cannot start the line editor: {e}"))?;
    rl.set_helper(Some(TrubalHelper));
    let hist = std::env::var_os("HOME")
        .map(|h| std::path::PathBuf::from(h).join(".trubal_history"))
        .unwrap_or_else(|| ".trubal_history".into());
    let _ = rl.load_history(&hist);
    let mut n = 0;
    'session: loop {
        // Inside a block (IF, LOOP, WHILE, DEFine) the prompt says so until its END.
        let prompt = if session.in_block() {
            "   ...> "
        } else {
            "trubal> "
        };
        match rl.readline(prompt) {
            Ok(text) => {
                // A paste of several lines arrives as one text (bracketed paste).
                for line in text.split('\n') {
                    let line = line.strip_suffix('\r').unwrap_or(line);
                    n += 1;
                    if !line.trim().is_empty() {
                        let _ = rl.add_history_entry(line);
                        let _ = rl.save_history(&hist);
                    }
                    let src = Source {
                        name: "<terminal>".into(),
                        line: n,
                    };
                    let flow = if line.len() > MAX_LINE {
                        Err(too_long(&src, line.len(), line.as_bytes()))
                    } else {
                        session.feed(&src, line)
                    };
                    session.flush();
                    // A Ctrl-C answered (or pressed after the command ended) is forgotten
                    // at the prompt.
                    super::interrupt::clear();
                    match flow {
                        Ok(Flow::Stop) => break 'session,
                        Ok(Flow::Continue) => {}
                        // The rest of a pasted text is dropped with the command it stopped.
                        Ok(Flow::Interrupted) => break,
                        Err(msg) => session.emit_err(&msg),
                    }
                }
            }
            Err(ReadlineError::Interrupted) => continue,
            Err(ReadlineError::Eof) => break,
            Err(e) => return Err(format!("terminal error: {e}")),
        }
    }
    let _ = rl.save_history(&hist);
    Ok(())
}

/// Lines typed while a command runs wait in the terminal's input queue, which the terminal
/// empties when Ctrl-C is pressed (POSIX: unless NOFLSH is set). Set for the session (the line
/// editor keeps it: it restores the mode it found after every line), so that lines typed
/// during a Cycle run after its Ctrl-C as after its normal end; the mode found is restored
/// at the end of the session.
struct KeepTypedAhead(Option<libc::termios>);

impl KeepTypedAhead {
    fn on() -> Self {
        // SAFETY: tcgetattr/tcsetattr read and write one `termios` of standard input.
        unsafe {
            let mut t: libc::termios = std::mem::zeroed();
            if libc::tcgetattr(libc::STDIN_FILENO, &mut t) != 0 {
                return KeepTypedAhead(None);
            }
            let old = t;
            t.c_lflag |= libc::NOFLSH;
            libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, &t);
            KeepTypedAhead(Some(old))
        }
    }
}

impl Drop for KeepTypedAhead {
    fn drop(&mut self) {
        if let Some(old) = &self.0 {
            // SAFETY: as above; the mode found at the start, NOFLSH as it was.
            unsafe {
                let mut t: libc::termios = std::mem::zeroed();
                if libc::tcgetattr(libc::STDIN_FILENO, &mut t) == 0 {
                    t.c_lflag = (t.c_lflag & !libc::NOFLSH) | (old.c_lflag & libc::NOFLSH);
                    libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, &t);
                }
            }
        }
    }
}

/// The first line of a terminal session.
pub const BANNER: &str = "trubal — DEM of spheres. `help` lists the commands, `help NAME` explains one, `stop` (or Ctrl-D) ends; Ctrl-C stops a running Cycle.";

/// Reads lines from any BufRead (used by tests).
pub fn lines_of<R: BufRead>(r: R) -> Vec<String> {
    r.lines().map_while(Result::ok).collect()
}
