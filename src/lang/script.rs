//! The words of the programmable language (doc/language.md): variables, conditions, loops,
//! procedures, include, and `Cycle ... UNTIL` / `CALL ... EVery`. Their builders read the
//! expressions into [`Expr`] trees, evaluated when the session runs the command.

use super::args::{Args, ParseError};
use super::command::{Command, StressServo};
use super::expr::{self, Expr};
use super::keyword::{Keyword, kw};

/// One item of `SHow`: a quoted text, or an expression (with its text as written).
#[derive(Clone, Debug, PartialEq)]
pub enum ShowItem {
    Text(String),
    Value(Expr, String),
}

#[derive(Clone, Debug, PartialEq)]
pub enum ScriptCmd {
    Let {
        name: String,
        value: Expr,
    },
    If {
        cond: Expr,
    },
    Else,
    End,
    Loop {
        var: String,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
    },
    While {
        cond: Expr,
    },
    Define {
        name: String,
        params: Vec<String>,
    },
    Call {
        name: String,
        args: Vec<Expr>,
    },
    Return {
        value: Option<Expr>,
    },
    Break,
    Include {
        file: String,
    },
    Show {
        items: Vec<ShowItem>,
    },
    /// `HIStory name EVery k expr` (`every` and `expr` given), `HIStory name OFF` (neither).
    History {
        name: String,
        every: Option<u64>,
        expr: Option<String>,
    },
    /// `HIStory WRIte file`.
    HistoryWrite {
        file: String,
    },
    /// `Cycle n [servo] [CALL name EVery k] [UNTIL cond]`.
    Cycle {
        n: u64,
        servo: Vec<(StressServo, f64)>,
        call: Option<(String, u64)>,
        until: Option<Expr>,
    },
}

impl ScriptCmd {
    /// The command's name in the table (for messages).
    pub fn name(&self) -> &'static str {
        match self {
            ScriptCmd::Let { .. } => "LET",
            ScriptCmd::If { .. } => "IF",
            ScriptCmd::Else => "ELSE",
            ScriptCmd::End => "END",
            ScriptCmd::Loop { .. } => "LOOP",
            ScriptCmd::While { .. } => "WHILE",
            ScriptCmd::Define { .. } => "DEFine",
            ScriptCmd::Call { .. } => "CALL",
            ScriptCmd::Return { .. } => "RETurn",
            ScriptCmd::Break => "BREak",
            ScriptCmd::Include { .. } => "INClude",
            ScriptCmd::Show { .. } => "SHow",
            ScriptCmd::History { .. } | ScriptCmd::HistoryWrite { .. } => "HIStory",
            ScriptCmd::Cycle { .. } => "Cycle",
        }
    }

    /// Whether the command opens a block closed by `END`.
    pub fn opens_block(&self) -> bool {
        matches!(
            self,
            ScriptCmd::If { .. }
                | ScriptCmd::Loop { .. }
                | ScriptCmd::While { .. }
                | ScriptCmd::Define { .. }
        )
    }
}

fn script(c: ScriptCmd) -> Result<Command, ParseError> {
    Ok(Command::Script(c))
}

/// A new name (of a variable, a loop's counter, a procedure or its parameter).
fn new_name(a: &mut Args, what: &str) -> Result<String, ParseError> {
    let t = a.next_tok(&format!("the {what}'s name"))?;
    let n = t.text.to_ascii_lowercase();
    if !expr::is_name(&n) {
        return Err(ParseError::at(
            t,
            format!(
                "`{}` cannot name a {what}: a name is letters, digits and `_`, starting with a letter",
                t.text
            ),
        ));
    }
    if expr::reserved(&n) {
        return Err(ParseError::at(
            t,
            format!(
                "`{n}` is a function or constant of expressions: choose another name for the {what}"
            ),
        ));
    }
    Ok(n)
}

pub fn b_let(a: &mut Args) -> Result<Command, ParseError> {
    let name = new_name(a, "variable")?;
    match a.next_tok("`=`")? {
        t if t.text == "=" => {}
        t if t.text.starts_with('=') => {
            return Err(ParseError::at(
                t,
                "put blanks around `=`: `LET name = value`",
            ));
        }
        t => {
            return Err(ParseError::at(
                t,
                format!("expected `=`, found `{}` (LET name = value)", t.text),
            ));
        }
    }
    let value = a.rest_expr("the value")?;
    script(ScriptCmd::Let { name, value })
}

pub fn b_if(a: &mut Args) -> Result<Command, ParseError> {
    let cond = a.rest_expr("the condition")?;
    script(ScriptCmd::If { cond })
}

pub fn b_while(a: &mut Args) -> Result<Command, ParseError> {
    let cond = a.rest_expr("the condition")?;
    script(ScriptCmd::While { cond })
}

pub fn b_loop(a: &mut Args) -> Result<Command, ParseError> {
    let var = new_name(a, "loop counter")?;
    let from = a.expr("from")?;
    let to = a.expr("to")?;
    let step = if a.at_end() {
        None
    } else {
        Some(a.expr("step")?)
    };
    script(ScriptCmd::Loop {
        var,
        from,
        to,
        step,
    })
}

pub fn b_define(a: &mut Args) -> Result<Command, ParseError> {
    let name = new_name(a, "procedure")?;
    let mut params: Vec<String> = Vec::new();
    while !a.at_end() {
        // (Invariant: the loop runs while a token is left.)
        let t = a.peek().expect("not at end");
        let p = new_name(a, "parameter")?;
        if p == name || params.contains(&p) {
            return Err(ParseError::at(t, format!("`{p}` is named twice")));
        }
        params.push(p);
    }
    script(ScriptCmd::Define { name, params })
}

pub fn b_call(a: &mut Args) -> Result<Command, ParseError> {
    let name = a.word("name")?.to_ascii_lowercase();
    let mut args = Vec::new();
    while !a.at_end() {
        args.push(a.expr("argument")?);
    }
    script(ScriptCmd::Call { name, args })
}

pub fn b_return(a: &mut Args) -> Result<Command, ParseError> {
    let value = if a.at_end() {
        None
    } else {
        Some(a.rest_expr("the value")?)
    };
    script(ScriptCmd::Return { value })
}

pub fn b_include(a: &mut Args) -> Result<Command, ParseError> {
    let file = a.word("file")?;
    script(ScriptCmd::Include { file })
}

pub fn b_show(a: &mut Args) -> Result<Command, ParseError> {
    let mut items = Vec::new();
    while let Some(t) = a.peek() {
        if a.line[t.start..].starts_with('"') {
            a.pos += 1;
            items.push(ShowItem::Text(t.text.clone()));
        } else {
            let e = a.expr("value")?;
            items.push(ShowItem::Value(e, t.text.clone()));
        }
    }
    if items.is_empty() {
        return Err(ParseError {
            start: a.line_end,
            end: a.line_end + 1,
            message: "SHow needs something to show: an expression or a \"text\"".into(),
        });
    }
    script(ScriptCmd::Show { items })
}

pub fn b_history(a: &mut Args) -> Result<Command, ParseError> {
    const WRITE: &[Keyword<()>] = &[kw("WRIte", ())];
    const WHAT: &[Keyword<bool>] = &[kw("EVery", true), kw("OFF", false)];
    if a.try_keyword(WRITE)?.is_some() {
        let file = a.word("file")?;
        return script(ScriptCmd::HistoryWrite { file });
    }
    let name = new_name(a, "history")?;
    if !a.keyword(WHAT, "EVery k expr, or OFF")? {
        return script(ScriptCmd::History {
            name,
            every: None,
            expr: None,
        });
    }
    let every = a.int_in("k", 1, i64::MAX / 2)? as u64;
    let e = a.rest_expr("the expression")?;
    let text = a.line[e.start..e.end].to_string();
    script(ScriptCmd::History {
        name,
        every: Some(every),
        expr: Some(text),
    })
}

/// The scripted options of `Cycle`, after its servo keywords: `CALL name EVery k`, `UNTIL
/// cond` (the rest of the line). `None` when there are none (a plain Cycle).
pub fn cycle_options(
    a: &mut Args,
    n: u64,
    servo: &[(StressServo, f64)],
) -> Result<Option<Command>, ParseError> {
    #[derive(Clone, Copy)]
    enum K {
        Call,
        Until,
    }
    const KWS: &[Keyword<K>] = &[kw("CALL", K::Call), kw("UNTIL", K::Until)];
    const EVERY: &[Keyword<()>] = &[kw("EVery", ())];
    let (mut call, mut until) = (None, None);
    while let Some(k) = a.try_keyword(KWS)? {
        match k {
            K::Call => {
                let name = a.word("procedure")?.to_ascii_lowercase();
                a.keyword(EVERY, "EVery (CALL name EVery k)")?;
                let k = a.int_in("k", 1, i64::MAX / 2)? as u64;
                call = Some((name, k));
            }
            K::Until => until = Some(a.rest_expr("the condition")?),
        }
    }
    if call.is_none() && until.is_none() {
        return Ok(None);
    }
    Ok(Some(Command::Script(ScriptCmd::Cycle {
        n,
        servo: servo.to_vec(),
        call,
        until,
    })))
}
