//! Parses one line into typed commands, using the command table.

use super::args::{Args, ParseError};
use super::command::Command;
use super::keyword::{match_keyword, minimal};
use super::lexer::tokenize;
use super::table::{COMMANDS, command_keywords};

/// A parsed command and the byte span of its words in the line.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    pub command: Command,
    pub start: usize,
    pub end: usize,
}

/// Parses a line: zero or more complete commands (`plot save cycle 200 plot bou rdisp`).
/// Either every command of the line parses or the line is refused with the first error.
/// Expressions may hold numbers, constants and functions only ([`parse_line_in`] with a
/// scope knows variables and the scene).
pub fn parse_line(line: &str) -> Result<Vec<Parsed>, ParseError> {
    parse_line_in(line, &super::expr::NoScope)
}

/// [`parse_line`] with the names of `scope`: the expressions in numbers' places are
/// evaluated as the line is read, before its first command runs.
pub fn parse_line_in(
    line: &str,
    scope: &dyn super::expr::Scope,
) -> Result<Vec<Parsed>, ParseError> {
    let toks = tokenize(line);
    let keywords = command_keywords();
    let mut out = Vec::new();
    let mut pos = 0;
    while pos < toks.len() {
        let t = &toks[pos];
        let def = match super::table::find_command(&t.text, keywords) {
            Ok(i) => &COMMANDS[i],
            Err(e) => {
                let mut msg = e.describe(&t.text, "command", keywords);
                if !out.is_empty() {
                    // (Invariant: checked non-empty just above.)
                    let prev: &Parsed = out.last().expect("non-empty");
                    let name = command_name(&prev.command);
                    msg = format!("unexpected `{}` after {name}: {msg}", t.text);
                }
                return Err(ParseError::at(t, msg));
            }
        };
        let mut args = Args::new(
            &toks,
            pos + 1,
            line.trim_end().len(),
            def.name,
            def.syntax,
            line,
            scope,
        );
        let command = (def.build)(&mut args)?;
        let end = toks[args.pos - 1].end;
        out.push(Parsed {
            command,
            start: t.start,
            end,
        });
        pos = args.pos;
        if let Some(next) = toks.get(pos)
            && match_keyword(&next.text, keywords).is_err()
        {
            // A slash separates words (TRUBAL's syntax), so a path must be quoted.
            let between = line.get(toks[pos - 1].end..next.start).unwrap_or("");
            let takes_path = def.syntax.contains("file") || def.name == "SET";
            let hint = if between.contains('/') && takes_path {
                ": a file or directory name with `/` must be quoted, e.g. \"dir/name\""
            } else {
                ""
            };
            return Err(ParseError::at(
                next,
                format!(
                    "unexpected `{}`: {} takes `{} {}`{hint}",
                    next.text,
                    def.name,
                    minimal(def.name).to_lowercase(),
                    def.syntax
                ),
            ));
        }
    }
    Ok(out)
}

/// The table name of a command variant (for messages).
pub fn command_name(c: &Command) -> &'static str {
    use Command::*;
    match c {
        Agglomerate { .. } => "AGGlomerate",
        Agenerate { .. } => "AGEnerate",
        Awall { .. } => "AWAll",
        Cgravity { .. } => "CGRavity",
        Cohesion { .. } => "COHesion",
        Create { .. } => "CReate",
        Cycle { .. } => "Cycle",
        Damping(_) => "DAmping",
        Density { .. } => "Density",
        Dwall(_) => "DWAll",
        Fix { .. } => "Fix",
        Fmm { .. } => "FMM",
        Fro => "FRO",
        Fraction { .. } => "FRAction",
        Friction { .. } => "FRiction",
        Gain { .. } => "GAIN",
        Gravity { .. } => "GRAvity",
        Grid { .. } => "GRID",
        Help { .. } => "HELP",
        Iset => "Iset",
        Liquid { .. } => "LIQuid",
        Log { .. } => "Log",
        Mode { .. } => "Mode",
        New => "New",
        Plot { .. } => "PLot",
        Pra { .. } => "PRA",
        Print { .. } => "PRint",
        Probe { .. } => "PRObe",
        Radius { .. } => "RAdius",
        Move { .. } => "MOVe",
        Delete { .. } => "DELete",
        Relax { .. } => "RELax",
        Reset => "RESEt",
        Restart { .. } => "RESTart",
        Rgenerate { .. } | RgenerateSeed { .. } => "RGEnerate",
        Rset => "RSet",
        Save { .. } => "SAve",
        Set(_) => "SET",
        Start { .. } => "STArt",
        Stop => "STOp",
        Velocity { .. } => "VELocity",
        Vmu { .. } => "VMU",
        Window { .. } => "Window",
        Ymd { .. } => "YMD",
        Zero { .. } => "Zero",
        TwoD => "2-D",
        Vtk { .. } => "VTk",
        Field { .. } => "FIEld",
        Group { .. } => "GROup",
        Property { .. } => "PROPerty",
        DeleteRange { .. } => "DELete",
        Script(s) => s.name(),
    }
}
