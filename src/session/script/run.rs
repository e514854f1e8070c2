//! Running statements: conditions, loops, procedure calls, INClude, LET and SHow.

use super::block::{self, Stmt};
use super::{MAX_CALLS, MAX_INCLUDES, MAX_PASSES, Proc, Signal, SrcLine, query};
use crate::lang::expr::{self, Expr};
use crate::lang::script::{ScriptCmd, ShowItem};
use crate::session::{Flow, LineError, Session, interrupt};

/// A number as text that reads back to the same bits (`$name`, SHow).
pub fn number_text(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

fn located(e: crate::lang::ParseError) -> LineError {
    LineError {
        start: e.start,
        end: e.end,
        message: e.message,
    }
}

impl Session {
    /// Runs statements over `lines`; stops at the first error, at STOp, at Ctrl-C, or when
    /// BREak or RETurn was given (the signal is left for the loop or call to answer).
    pub(super) fn exec(&mut self, lines: &[SrcLine], stmts: &[Stmt]) -> Result<Flow, String> {
        for s in stmts {
            let at = match s {
                Stmt::Line(i) | Stmt::If { at: i, .. } | Stmt::Loop { at: i, .. } => *i,
                Stmt::Define { at, .. } => *at,
            };
            if interrupt::requested() {
                interrupt::clear();
                self.emit_err(&format!(
                    "interrupted: stopped before {}:{} (Ctrl-C)",
                    lines[at].file, lines[at].line
                ));
                return Ok(Flow::Interrupted);
            }
            let flow = match s {
                Stmt::Line(i) => self.run_one(&lines[*i])?,
                Stmt::If {
                    at,
                    then,
                    otherwise,
                } => {
                    // (Invariant: the block was built from this line's first word, IF; a
                    // `$name` can only add to that word, which then fails to parse, `opener`.)
                    let ScriptCmd::If { cond } = self.opener(&lines[*at])? else {
                        unreachable!("an IF line parses to IF")
                    };
                    if self.truth(&lines[*at], &cond)? {
                        self.exec(lines, then)?
                    } else if let Some((_, o)) = otherwise {
                        self.exec(lines, o)?
                    } else {
                        Flow::Continue
                    }
                }
                Stmt::Loop { at, body } => {
                    self.script.loops += 1;
                    let r = self.exec_loop(lines, *at, body);
                    self.script.loops -= 1;
                    r?
                }
                Stmt::Define { at, end } => {
                    let ScriptCmd::Define { name, params } = self.opener(&lines[*at])? else {
                        unreachable!("a DEFine line parses to DEFine")
                    };
                    let body = lines[at + 1..*end].to_vec();
                    self.script.state.procs.insert(name, Proc { params, body });
                    Flow::Continue
                }
            };
            if flow != Flow::Continue || self.script.signal.is_some() {
                return Ok(flow);
            }
        }
        Ok(Flow::Continue)
    }

    /// The command of a block's opening line, parsed when it is reached.
    fn opener(&self, l: &SrcLine) -> Result<ScriptCmd, String> {
        let text = self.substituted(&l.text).map_err(|e| l.error(&e))?;
        let parsed =
            crate::lang::parse_line_in(&text, &self.names()).map_err(|e| l.error(&located(e)))?;
        match parsed.into_iter().next().map(|p| p.command) {
            Some(crate::lang::Command::Script(c)) => Ok(c),
            _ => unreachable!("an opening line parses to its script command"),
        }
    }

    fn value(&self, l: &SrcLine, e: &Expr) -> Result<f64, String> {
        expr::eval(e, &self.names()).map_err(|e| l.error(&located(e)))
    }

    fn truth(&self, l: &SrcLine, e: &Expr) -> Result<bool, String> {
        Ok(self.value(l, e)? != 0.0)
    }

    fn exec_loop(&mut self, lines: &[SrcLine], at: usize, body: &[Stmt]) -> Result<Flow, String> {
        let l = &lines[at];
        let cmd = self.opener(l)?;
        let mut pass = 0u64;
        let counted = match &cmd {
            ScriptCmd::Loop {
                var,
                from,
                to,
                step,
            } => {
                let (a, b) = (self.value(l, from)?, self.value(l, to)?);
                let s = match step {
                    Some(e) => self.value(l, e)?,
                    None => 1.0,
                };
                let span = |e: &Expr, m: String| {
                    l.error(&LineError {
                        start: e.start,
                        end: e.end,
                        message: m,
                    })
                };
                if s == 0.0 {
                    // (Invariant: without a step it is 1, so a 0 was given.)
                    return Err(span(
                        step.as_ref().expect("0 is given"),
                        "the step of a LOOP must not be 0".into(),
                    ));
                }
                let n = ((b - a) / s).floor() + 1.0;
                if n > MAX_PASSES as f64 {
                    return Err(span(
                        to,
                        format!(
                            "this LOOP would make {n} passes, more than the {MAX_PASSES} a loop may (a runaway loop?)"
                        ),
                    ));
                }
                Some((var.clone(), a, s, n.max(0.0) as u64))
            }
            _ => None,
        };
        loop {
            let go = match &counted {
                Some((var, a, s, n)) => {
                    if pass < *n {
                        self.script
                            .state
                            .vars
                            .insert(var.clone(), a + pass as f64 * s);
                    }
                    pass < *n
                }
                None => {
                    let ScriptCmd::While { cond } = &cmd else {
                        unreachable!("LOOP or WHILE")
                    };
                    let go = self.truth(l, cond)?;
                    if go && pass >= MAX_PASSES {
                        let e = LineError {
                            start: cond.start,
                            end: cond.end,
                            message: format!(
                                "the condition is still true after {MAX_PASSES} passes: a runaway loop (stopped; the state is that after the last pass)"
                            ),
                        };
                        return Err(l.error(&e));
                    }
                    go
                }
            };
            if !go {
                return Ok(Flow::Continue);
            }
            pass += 1;
            if interrupt::requested() {
                interrupt::clear();
                self.emit_err(&format!(
                    "interrupted: the loop of {}:{} stopped in its pass {pass} (Ctrl-C)",
                    l.file, l.line
                ));
                return Ok(Flow::Interrupted);
            }
            let flow = self.exec(lines, body)?;
            match self.script.signal {
                Some(Signal::Break) => {
                    self.script.signal = None;
                    return Ok(flow);
                }
                Some(Signal::Return) => return Ok(flow),
                None => {}
            }
            if flow != Flow::Continue {
                return Ok(flow);
            }
        }
    }

    /// A command of the language given on a line.
    pub(super) fn script_cmd(&mut self, c: &ScriptCmd) -> Result<Flow, String> {
        // An expression's error is located in the line (`run_line` takes it from `span`).
        let eval = |s: &Self, e: &Expr| {
            expr::eval(e, &s.names()).map_err(|e| {
                let m = e.message.clone();
                s.script.span.set(Some(located(e)));
                m
            })
        };
        match c {
            ScriptCmd::Let { name, value } => {
                if query::is_query(name) {
                    return Err(format!(
                        "`{name}` is a query of the scene: a variable needs another name"
                    ));
                }
                let v = eval(self, value)?;
                self.script.state.vars.insert(name.clone(), v);
            }
            ScriptCmd::Call { name, args } => {
                let mut v = Vec::with_capacity(args.len());
                for a in args {
                    v.push(eval(self, a)?);
                }
                return self.call(name, &v);
            }
            ScriptCmd::Return { value } => {
                let Some(p) = self.script.calls.last().cloned() else {
                    return Err(
                        "RETurn outside a procedure (it ends the procedure being CALLed)".into(),
                    );
                };
                if let Some(e) = value {
                    let v = eval(self, e)?;
                    self.script.state.vars.insert(p, v);
                }
                self.script.signal = Some(Signal::Return);
            }
            ScriptCmd::Break => {
                if self.script.loops == 0 {
                    return Err("BREak outside a LOOP or WHILE (of this procedure)".into());
                }
                self.script.signal = Some(Signal::Break);
            }
            ScriptCmd::Include { file } => return self.include(file),
            ScriptCmd::Show { items } => {
                let mut text = Vec::new();
                let mut json = Vec::new();
                for it in items {
                    match it {
                        ShowItem::Text(t) => {
                            text.push(t.clone());
                            json.push(serde_json::Value::from(t.clone()));
                        }
                        ShowItem::Value(e, _) => {
                            let v = eval(self, e)?;
                            text.push(number_text(v));
                            json.push(serde_json::Value::from(v));
                        }
                    }
                }
                let out = if self.json {
                    serde_json::json!({ "show": json }).to_string()
                } else {
                    text.join(" ")
                };
                self.emit(&out);
                // Out now: a loop's lines appear as it runs.
                self.flush();
            }
            ScriptCmd::History { name, every, expr } => {
                return self.history_define(name, *every, expr.as_deref());
            }
            ScriptCmd::HistoryWrite { file } => return self.history_write(file),
            ScriptCmd::Cycle {
                n,
                servo,
                call,
                until,
            } => {
                return self.cycle_scripted(*n, servo, call.as_ref(), until.as_ref());
            }
            ScriptCmd::If { .. }
            | ScriptCmd::Loop { .. }
            | ScriptCmd::While { .. }
            | ScriptCmd::Define { .. } => {
                return Err(format!(
                    "{} opens a block: it must be the first word of its line, and END closes it",
                    c.name()
                ));
            }
            ScriptCmd::Else | ScriptCmd::End => {
                return Err(format!("{} must be alone on its line", c.name()));
            }
        }
        Ok(Flow::Continue)
    }

    /// `CALL name args`: the parameters are set for the call and put back after it.
    pub(super) fn call(&mut self, name: &str, args: &[f64]) -> Result<Flow, String> {
        let Some(p) = self.script.state.procs.get(name).cloned() else {
            return Err(format!("no procedure `{name}`: DEFine it first"));
        };
        if p.params.len() != args.len() {
            return Err(format!(
                "{name} takes {} argument{} ({}), got {}",
                p.params.len(),
                if p.params.len() == 1 { "" } else { "s" },
                p.params.join(" "),
                args.len()
            ));
        }
        if self.script.calls.len() >= MAX_CALLS {
            return Err(format!(
                "procedures nested more than {MAX_CALLS} deep (a procedure that calls itself without end?)"
            ));
        }
        let vars = &mut self.script.state.vars;
        let saved: Vec<Option<f64>> = p.params.iter().map(|q| vars.get(q).copied()).collect();
        for (q, v) in p.params.iter().zip(args) {
            vars.insert(q.clone(), *v);
        }
        self.script.calls.push(name.to_string());
        let loops = std::mem::take(&mut self.script.loops);
        let r = self.run_nested(&p.body);
        self.script.loops = loops;
        self.script.calls.pop();
        if self.script.signal == Some(Signal::Return) {
            self.script.signal = None;
        }
        let vars = &mut self.script.state.vars;
        for (q, old) in p.params.iter().zip(saved) {
            match old {
                Some(v) => vars.insert(q.clone(), v),
                None => vars.remove(q),
            };
        }
        r
    }

    /// Lines run inside a command (a procedure, an included file): their errors come
    /// formatted with their own lines, kept for the line that led here.
    fn run_nested(&mut self, lines: &[SrcLine]) -> Result<Flow, String> {
        let r = block::build(lines)
            .map_err(|(i, e)| lines[i].error(&e))
            .and_then(|stmts| self.exec(lines, &stmts));
        r.map_err(|msg| {
            self.script.nested = Some(msg);
            "(see above)".to_string()
        })
    }

    fn include(&mut self, file: &str) -> Result<Flow, String> {
        if self.script.includes >= MAX_INCLUDES {
            return Err(format!(
                "INClude nested more than {MAX_INCLUDES} deep (a file that includes itself?)"
            ));
        }
        let path = super::super::join(&self.dir, file);
        let data = std::fs::read(&path).map_err(|e| format!("cannot read {file}: {e}"))?;
        let text = String::from_utf8_lossy(&data);
        let lines: Vec<SrcLine> = text
            .lines()
            .enumerate()
            .map(|(i, t)| SrcLine {
                file: file.to_string(),
                line: i + 1,
                text: t.strip_suffix('\r').unwrap_or(t).to_string(),
            })
            .collect();
        self.script.includes += 1;
        let loops = std::mem::take(&mut self.script.loops);
        let r = self.run_nested(&lines);
        self.script.loops = loops;
        self.script.includes -= 1;
        r
    }
}
