//! Expressions of the command language (doc/language.md): numbers, names, operators, the
//! usual functions, and the queries of the scene a [`Scope`] answers. Parsed once into an
//! [`Expr`] whose every node keeps its byte span in the line (errors point at the column);
//! evaluated in f64 with IEEE operations only, so the same input gives the same bits.
//!
//! Grammar (lowest precedence first):
//!
//! ```text
//! expr    = or
//! or      = and { "or" and }
//! and     = not { "and" not }
//! not     = "not" not | compare
//! compare = sum [ ("<" | "<=" | ">" | ">=" | "==" | "!=") sum ]
//! sum     = product { ("+" | "-") product }
//! product = unary { ("*" | "/" | "%") unary }
//! unary   = "-" unary | "+" unary | power
//! power   = atom [ "^" unary ]
//! atom    = number | name [ "(" [ expr { "," expr } ] ")" ] | "(" expr ")"
//! ```
//!
//! A number is TRUBAL's (`1e-3`, `1.d-3`); a name is letters, digits, `_` and `.`, starting
//! with a letter or `_`, case-insensitive. True is 1, false is 0; a condition is true when
//! it is not 0.

use nom::{
    IResult, Parser,
    bytes::complete::{take_while, take_while1},
    combinator::recognize,
    sequence::pair,
};

use super::args::ParseError;
use super::lexer::parse_real;

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Pow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

/// One node of an expression and its byte span in the line.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: Kind,
    pub start: usize,
    pub end: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    Num(f64),
    /// A variable, a constant or a query without arguments (lower case).
    Name(String),
    Neg(Box<Expr>),
    Not(Box<Expr>),
    Bin(Op, Box<Expr>, Box<Expr>),
    /// A function: built in, or a query of the scene (lower case).
    Call(String, Vec<Expr>),
}

/// What an expression's names mean beyond the built-in functions: variables and the queries
/// of the scene. `None`: the name is not known here.
pub trait Scope {
    /// A variable, or a query of the scene without arguments (`time`, `energy.kinetic`).
    fn value(&self, name: &str) -> Option<Result<f64, String>>;
    /// A query of the scene with arguments (`ball_vz(3)`).
    fn call(&self, name: &str, args: &[f64]) -> Option<Result<f64, String>>;
    /// `sum`/`avg` of a particle quantity over a range: every particle when `range` is
    /// `None` (a later range or group names its particles here).
    fn reduce(&self, op: Reduce, field: &str, range: Option<&str>) -> Option<Result<f64, String>>;
}

/// A reduction over the particles of a range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reduce {
    Sum,
    Avg,
}

/// A scope without variables or a scene: constants and functions only.
pub struct NoScope;

impl Scope for NoScope {
    fn value(&self, _: &str) -> Option<Result<f64, String>> {
        None
    }
    fn call(&self, _: &str, _: &[f64]) -> Option<Result<f64, String>> {
        None
    }
    fn reduce(&self, _: Reduce, _: &str, _: Option<&str>) -> Option<Result<f64, String>> {
        None
    }
}

/// The built-in functions: name, number of arguments (`None`: one or more).
pub const FUNCTIONS: &[(&str, Option<usize>)] = &[
    ("sqrt", Some(1)),
    ("exp", Some(1)),
    ("log", Some(1)),
    ("log10", Some(1)),
    ("sin", Some(1)),
    ("cos", Some(1)),
    ("tan", Some(1)),
    ("asin", Some(1)),
    ("acos", Some(1)),
    ("atan", Some(1)),
    ("atan2", Some(2)),
    ("abs", Some(1)),
    ("floor", Some(1)),
    ("ceil", Some(1)),
    ("round", Some(1)),
    ("min", None),
    ("max", None),
];

/// The built-in constants.
pub const CONSTANTS: &[(&str, f64)] = &[("pi", std::f64::consts::PI)];

/// Deepest nesting of brackets and unary operators (deeper input is refused, not a stack
/// overflow).
pub const MAX_DEPTH: usize = 64;

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Sym(&'static str),
}

/// A number at the start of `i`: digits with an optional fraction (`12`, `12.`, `12.75`,
/// `.5`), then an optional exponent (`e`, `E`, `d` or `D`, a sign, digits); the rest and the
/// number's text. Written by hand: nom 8's `recognize` of the same sequence gave `12.` for
/// `12.75` at the end of the input (the fraction's digits lost).
fn number(i: &str) -> Option<(&str, &str)> {
    let b = i.as_bytes();
    let digits = |k: usize| b[k..].iter().take_while(|c| c.is_ascii_digit()).count();
    let whole = digits(0);
    let mut k = whole;
    let mut frac = 0;
    if b.get(k) == Some(&b'.') {
        frac = digits(k + 1);
        k += 1 + frac;
    }
    if whole == 0 && frac == 0 {
        return None;
    }
    if let Some(c) = b.get(k)
        && matches!(c, b'e' | b'E' | b'd' | b'D')
    {
        let sign = usize::from(matches!(b.get(k + 1), Some(b'+' | b'-')));
        let e = digits(k + 1 + sign);
        if e > 0 {
            k += 1 + sign + e;
        }
    }
    Some((&i[k..], &i[..k]))
}

fn name(i: &str) -> IResult<&str, &str> {
    recognize(pair(
        take_while1(|c: char| c.is_ascii_alphabetic() || c == '_'),
        take_while(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.'),
    ))
    .parse(i)
}

const SYMBOLS: &[&str] = &[
    "<=", ">=", "==", "!=", "+", "-", "*", "/", "%", "^", "(", ")", ",", "<", ">",
];

/// The tokens of `text` with their spans (offset by `base`).
fn tokens(text: &str, base: usize) -> Result<Vec<(Tok, usize, usize)>, ParseError> {
    let mut out = Vec::new();
    let mut rest = text;
    loop {
        rest = rest.trim_start();
        if rest.is_empty() {
            return Ok(out);
        }
        let at = base + text.len() - rest.len();
        if let Some((after, n)) = number(rest) {
            let v = parse_real(n)
                .ok_or_else(|| err(at, at + n.len(), format!("`{n}` is not a finite number")))?;
            if after.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
                let (_, w) = name(after).unwrap_or((after, ""));
                return Err(err(
                    at,
                    at + n.len() + w.len(),
                    format!(
                        "`{n}{w}` is neither a number nor a name (a name starts with a letter)"
                    ),
                ));
            }
            out.push((Tok::Num(v), at, at + n.len()));
            rest = after;
        } else if let Ok((after, n)) = name(rest) {
            out.push((Tok::Name(n.to_ascii_lowercase()), at, at + n.len()));
            rest = after;
        } else if let Some(s) = SYMBOLS.iter().find(|s| rest.starts_with(**s)) {
            out.push((Tok::Sym(s), at, at + s.len()));
            rest = &rest[s.len()..];
        } else {
            let c = rest.chars().next().unwrap_or(' ');
            let hint = match c {
                '=' => ": compare with `==`; a variable is set with `LET name = value`",
                '&' | '|' => ": write `and`, `or`",
                '!' => ": write `not`",
                '[' | ']' => {
                    ": square brackets hold a whole expression and do not nest; group with ( )"
                }
                _ => "",
            };
            return Err(err(
                at,
                at + c.len_utf8(),
                format!("unexpected `{c}` in an expression{hint}"),
            ));
        }
    }
}

fn err(start: usize, end: usize, message: String) -> ParseError {
    ParseError {
        start,
        end,
        message,
    }
}

/// Parses the expression `text`, which starts at byte `base` of its line.
pub fn parse(text: &str, base: usize) -> Result<Expr, ParseError> {
    let toks = tokens(text, base)?;
    let end = base + text.trim_end().len();
    if toks.is_empty() {
        return Err(err(
            base,
            end.max(base + 1),
            "an expression is missing here".into(),
        ));
    }
    let mut p = Parser_ {
        toks: &toks,
        pos: 0,
        end,
        depth: 0,
    };
    let e = p.or()?;
    if let Some((t, s, e2)) = toks.get(p.pos) {
        let what = match t {
            Tok::Sym(")") => "a `)` without its `(`".to_string(),
            _ => format!(
                "`{}` after a complete expression: an operator is missing",
                &text[s - base..e2 - base]
            ),
        };
        return Err(err(*s, *e2, what));
    }
    Ok(e)
}

struct Parser_<'a> {
    toks: &'a [(Tok, usize, usize)],
    pos: usize,
    end: usize,
    depth: usize,
}

impl Parser_<'_> {
    fn sym(&self) -> Option<&'static str> {
        match self.toks.get(self.pos) {
            Some((Tok::Sym(s), _, _)) => Some(s),
            _ => None,
        }
    }
    fn word(&self, w: &str) -> bool {
        matches!(self.toks.get(self.pos), Some((Tok::Name(n), _, _)) if n == w)
    }
    fn bin(
        &mut self,
        op: Op,
        l: Expr,
        next: fn(&mut Self) -> Result<Expr, ParseError>,
    ) -> Result<Expr, ParseError> {
        self.pos += 1;
        let r = next(self)?;
        Ok(Expr {
            start: l.start,
            end: r.end,
            kind: Kind::Bin(op, Box::new(l), Box::new(r)),
        })
    }
    fn or(&mut self) -> Result<Expr, ParseError> {
        let mut l = self.and()?;
        while self.word("or") {
            l = self.bin(Op::Or, l, Self::and)?;
        }
        Ok(l)
    }
    fn and(&mut self) -> Result<Expr, ParseError> {
        let mut l = self.not()?;
        while self.word("and") {
            l = self.bin(Op::And, l, Self::not)?;
        }
        Ok(l)
    }
    fn deeper(&mut self, at: usize) -> Result<(), ParseError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(err(
                at,
                at + 1,
                format!("the expression is nested more than {MAX_DEPTH} deep"),
            ));
        }
        Ok(())
    }
    fn not(&mut self) -> Result<Expr, ParseError> {
        if self.word("not") {
            let start = self.toks[self.pos].1;
            self.deeper(start)?;
            self.pos += 1;
            let e = self.not()?;
            self.depth -= 1;
            return Ok(Expr {
                start,
                end: e.end,
                kind: Kind::Not(Box::new(e)),
            });
        }
        self.compare()
    }
    fn compare(&mut self) -> Result<Expr, ParseError> {
        let l = self.sum()?;
        let op = match self.sym() {
            Some("<") => Op::Lt,
            Some("<=") => Op::Le,
            Some(">") => Op::Gt,
            Some(">=") => Op::Ge,
            Some("==") => Op::Eq,
            Some("!=") => Op::Ne,
            _ => return Ok(l),
        };
        self.bin(op, l, Self::sum)
    }
    fn sum(&mut self) -> Result<Expr, ParseError> {
        let mut l = self.product()?;
        loop {
            let op = match self.sym() {
                Some("+") => Op::Add,
                Some("-") => Op::Sub,
                _ => return Ok(l),
            };
            l = self.bin(op, l, Self::product)?;
        }
    }
    fn product(&mut self) -> Result<Expr, ParseError> {
        let mut l = self.unary()?;
        loop {
            let op = match self.sym() {
                Some("*") => Op::Mul,
                Some("/") => Op::Div,
                Some("%") => Op::Rem,
                _ => return Ok(l),
            };
            l = self.bin(op, l, Self::unary)?;
        }
    }
    fn unary(&mut self) -> Result<Expr, ParseError> {
        if let Some(s @ ("-" | "+")) = self.sym() {
            let start = self.toks[self.pos].1;
            self.deeper(start)?;
            self.pos += 1;
            let e = self.unary()?;
            self.depth -= 1;
            if s == "+" {
                return Ok(e);
            }
            return Ok(Expr {
                start,
                end: e.end,
                kind: Kind::Neg(Box::new(e)),
            });
        }
        self.power()
    }
    fn power(&mut self) -> Result<Expr, ParseError> {
        let l = self.atom()?;
        if self.sym() == Some("^") {
            return self.bin(Op::Pow, l, Self::unary);
        }
        Ok(l)
    }
    fn missing(&self) -> ParseError {
        match self.toks.get(self.pos) {
            Some((t, s, e)) => err(
                *s,
                *e,
                format!("expected a number, a name or `(`, found {}", describe(t)),
            ),
            None => err(
                self.end,
                self.end + 1,
                "the expression ends too soon: a number, a name or `(` is missing".into(),
            ),
        }
    }
    fn close(&mut self, open: usize) -> Result<usize, ParseError> {
        match self.toks.get(self.pos) {
            Some((Tok::Sym(")"), _, e)) => {
                self.pos += 1;
                Ok(*e)
            }
            Some((t, s, e)) => Err(err(
                *s,
                *e,
                format!(
                    "expected `)` to close the `(` at {open}, found {}",
                    describe(t)
                ),
            )),
            None => Err(err(open, open + 1, "this `(` is not closed".into())),
        }
    }
    fn atom(&mut self) -> Result<Expr, ParseError> {
        let Some((t, s, e)) = self.toks.get(self.pos).cloned() else {
            return Err(self.missing());
        };
        match t {
            Tok::Num(v) => {
                self.pos += 1;
                Ok(Expr {
                    kind: Kind::Num(v),
                    start: s,
                    end: e,
                })
            }
            Tok::Sym("(") => {
                self.deeper(s)?;
                self.pos += 1;
                let inner = self.or()?;
                let end = self.close(s)?;
                self.depth -= 1;
                Ok(Expr {
                    start: s,
                    end,
                    ..inner
                })
            }
            Tok::Name(n) if !matches!(n.as_str(), "and" | "or" | "not") => {
                self.pos += 1;
                if self.sym() != Some("(") {
                    return Ok(Expr {
                        kind: Kind::Name(n),
                        start: s,
                        end: e,
                    });
                }
                let open = self.toks[self.pos].1;
                self.deeper(open)?;
                self.pos += 1;
                let mut args = Vec::new();
                if self.sym() != Some(")") {
                    args.push(self.or()?);
                    while self.sym() == Some(",") {
                        self.pos += 1;
                        args.push(self.or()?);
                    }
                }
                let end = self.close(open)?;
                self.depth -= 1;
                Ok(Expr {
                    kind: Kind::Call(n, args),
                    start: s,
                    end,
                })
            }
            _ => Err(self.missing()),
        }
    }
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("the number {v}"),
        Tok::Name(n) => format!("`{n}`"),
        Tok::Sym(s) => format!("`{s}`"),
    }
}

/// Evaluates an expression; an error is located on the node that failed.
pub fn eval(e: &Expr, scope: &dyn Scope) -> Result<f64, ParseError> {
    let at = |m: String| err(e.start, e.end, m);
    let v = match &e.kind {
        Kind::Num(v) => return Ok(*v),
        Kind::Name(n) => return name_value(n, scope).map_err(at),
        Kind::Neg(x) => -eval(x, scope)?,
        Kind::Not(x) => truth(eval(x, scope)? == 0.0),
        Kind::Bin(Op::And, a, b) => truth(eval(a, scope)? != 0.0 && eval(b, scope)? != 0.0),
        Kind::Bin(Op::Or, a, b) => truth(eval(a, scope)? != 0.0 || eval(b, scope)? != 0.0),
        Kind::Bin(op, a, b) => {
            let (x, y) = (eval(a, scope)?, eval(b, scope)?);
            match op {
                Op::Add => x + y,
                Op::Sub => x - y,
                Op::Mul => x * y,
                Op::Div if y == 0.0 => return Err(at("division by zero".into())),
                Op::Div => x / y,
                Op::Rem if y == 0.0 => return Err(at("`%` by zero".into())),
                Op::Rem => x % y,
                Op::Pow => x.powf(y),
                Op::Lt => truth(x < y),
                Op::Le => truth(x <= y),
                Op::Gt => truth(x > y),
                Op::Ge => truth(x >= y),
                Op::Eq => truth(x == y),
                Op::Ne => truth(x != y),
                Op::And | Op::Or => unreachable!("handled above"),
            }
        }
        Kind::Call(f, args) => call(f, args, scope).map_err(|m| m.unwrap_or_else(&at))?,
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(at(format!("the value is not a finite number ({v})")))
    }
}

fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

fn name_value(n: &str, scope: &dyn Scope) -> Result<f64, String> {
    if let Some(r) = scope.value(n) {
        return r;
    }
    if let Some((_, v)) = CONSTANTS.iter().find(|(c, _)| *c == n) {
        return Ok(*v);
    }
    if FUNCTIONS.iter().any(|(f, _)| *f == n) || matches!(n, "sum" | "avg") {
        return Err(format!(
            "`{n}` is a function: give its arguments, `{n}(...)`"
        ));
    }
    Err(format!(
        "unknown name `{n}`: not a variable (LET {n} = ...) nor a query of the scene (`help LET` lists them)"
    ))
}

/// A function call: `Err(Ok(e))` a located error from an argument, `Err(Err(m))` an error of
/// the call itself.
fn call(f: &str, args: &[Expr], scope: &dyn Scope) -> Result<f64, Result<ParseError, String>> {
    if let Some(op) = match f {
        "sum" => Some(Reduce::Sum),
        "avg" => Some(Reduce::Avg),
        _ => None,
    } {
        let (field, range) = match args {
            [
                Expr {
                    kind: Kind::Name(q),
                    ..
                },
            ] => (q, None),
            [
                Expr {
                    kind: Kind::Name(q),
                    ..
                },
                Expr {
                    kind: Kind::Name(r),
                    ..
                },
            ] => (q, Some(r.as_str())),
            _ => {
                return Err(Err(format!(
                    "{f} takes a particle quantity and optionally a range: `{f}(vz)`"
                )));
            }
        };
        return scope
            .reduce(op, field, range)
            .unwrap_or_else(|| Err(format!("{f}() needs a scene")))
            .map_err(Err);
    }
    let mut v = Vec::with_capacity(args.len());
    for a in args {
        v.push(eval(a, scope).map_err(Ok)?);
    }
    if let Some(&(_, n)) = FUNCTIONS.iter().find(|(g, _)| *g == f) {
        if let Some(n) = n
            && v.len() != n
        {
            return Err(Err(format!(
                "{f} takes {n} argument{}, got {}",
                if n == 1 { "" } else { "s" },
                v.len()
            )));
        }
        if v.is_empty() {
            return Err(Err(format!("{f} takes at least one argument")));
        }
        let x = v[0];
        return Ok(match f {
            "sqrt" if x < 0.0 => return Err(Err(format!("sqrt of a negative number ({x})"))),
            "sqrt" => x.sqrt(),
            "exp" => x.exp(),
            "log" | "log10" if x <= 0.0 => {
                return Err(Err(format!("{f} of a number that is not positive ({x})")));
            }
            "log" => x.ln(),
            "log10" => x.log10(),
            "sin" => x.sin(),
            "cos" => x.cos(),
            "tan" => x.tan(),
            "asin" | "acos" if !(-1.0..=1.0).contains(&x) => {
                return Err(Err(format!("{f} of a number outside [-1, 1] ({x})")));
            }
            "asin" => x.asin(),
            "acos" => x.acos(),
            "atan" => x.atan(),
            "atan2" => x.atan2(v[1]),
            "abs" => x.abs(),
            "floor" => x.floor(),
            "ceil" => x.ceil(),
            "round" => x.round(),
            "min" => v.iter().copied().fold(x, f64::min),
            _ => v.iter().copied().fold(x, f64::max),
        });
    }
    match scope.call(f, &v) {
        Some(r) => r.map_err(Err),
        None => Err(Err(format!(
            "unknown function `{f}` (`help LET` lists the functions and queries)"
        ))),
    }
}

/// Whether a name may be given to a variable: not a function, constant or operator word.
pub fn reserved(n: &str) -> bool {
    matches!(n, "and" | "or" | "not" | "sum" | "avg")
        || FUNCTIONS.iter().any(|(f, _)| *f == n)
        || CONSTANTS.iter().any(|(c, _)| *c == n)
}

/// Whether `w` is a plain name (a variable's name): letters, digits and `_`, first a letter or `_`.
pub fn is_name(w: &str) -> bool {
    w.chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && w.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str) -> Result<f64, ParseError> {
        eval(&parse(s, 0)?, &NoScope)
    }

    #[test]
    fn precedence_and_functions() {
        assert_eq!(ev("1 + 2 * 3").unwrap(), 7.0);
        assert_eq!(ev("(1 + 2) * 3").unwrap(), 9.0);
        assert_eq!(ev("-2 ^ 2").unwrap(), -4.0);
        assert_eq!(ev("2 ^ 3 ^ 2").unwrap(), 512.0);
        assert_eq!(ev("2 ^ -1").unwrap(), 0.5);
        assert_eq!(ev("1e-3*2").unwrap(), 2e-3);
        assert_eq!(ev("1.d-3").unwrap(), 1e-3);
        assert_eq!(ev("7 % 4").unwrap(), 3.0);
        assert_eq!(ev("max(1, 5, 3) + min(2, -1)").unwrap(), 4.0);
        assert_eq!(ev("sqrt(16) + abs(-1) + floor(2.5)").unwrap(), 7.0);
        assert_eq!(ev("cos(pi)").unwrap(), -1.0);
        assert_eq!(ev("1 < 2 and not 2 < 1").unwrap(), 1.0);
        assert_eq!(ev("1 > 2 or 0").unwrap(), 0.0);
        assert_eq!(ev("3 == 3").unwrap(), 1.0);
        assert_eq!(ev("3 != 3").unwrap(), 0.0);
        assert_eq!(ev("atan2(1, 1) * 4").unwrap(), std::f64::consts::PI);
    }

    #[test]
    fn errors_point_into_the_expression() {
        let e = ev("1 + sqrt(-4)").unwrap_err();
        assert_eq!((e.start, e.end), (4, 12));
        assert!(e.message.contains("sqrt of a negative"), "{}", e.message);
        let e = ev("2 * (1 / 0)").unwrap_err();
        assert_eq!((e.start, e.end), (4, 11));
        let e = ev("1 + ").unwrap_err();
        assert!(e.message.contains("ends too soon"), "{}", e.message);
        let e = ev("(1 + 2").unwrap_err();
        assert_eq!(e.start, 0);
        let e = ev("x = 1").unwrap_err();
        assert_eq!(e.start, 2);
        assert!(e.message.contains("=="), "{}", e.message);
        let e = ev("2 r").unwrap_err();
        assert_eq!((e.start, e.end), (2, 3));
        let e = ev("foo + 1").unwrap_err();
        assert_eq!((e.start, e.end), (0, 3));
        let e = ev("10^400").unwrap_err();
        assert!(e.message.contains("not a finite"), "{}", e.message);
        assert!(ev(&"(".repeat(10_000)).is_err());
        assert!(ev(&"-".repeat(10_000)).is_err());
        assert!(ev("2x").is_err());
    }
}
