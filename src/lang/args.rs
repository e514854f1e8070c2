//! A cursor over the tokens of one command, with typed readers that produce located errors.

use super::expr::{self, Expr, Kind, Scope};
use super::keyword::{Keyword, MatchError, match_keyword};
use super::lexer::{Token, parse_real};

/// A parse error located in the line: byte span plus what was expected.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    pub start: usize,
    pub end: usize,
    pub message: String,
}

impl ParseError {
    pub fn at(tok: &Token, message: impl Into<String>) -> Self {
        ParseError {
            start: tok.start,
            end: tok.end,
            message: message.into(),
        }
    }
}

/// The largest integer a parameter may have (integers are read as reals first: every whole
/// number up to this is exact).
pub const INT_LIMIT: i64 = 9_000_000_000_000_000;

/// Tokens of the current line and the reading position.
pub struct Args<'a> {
    pub toks: &'a [Token],
    pub pos: usize,
    /// Span of the command word (for "missing parameter" errors at the end of a line).
    pub line_end: usize,
    pub command: &'static str,
    pub syntax: &'static str,
    /// The line (expressions that run to its end are read from it).
    pub line: &'a str,
    /// What the names of an expression in a number's place mean (variables, queries).
    pub scope: &'a dyn Scope,
}

impl<'a> Args<'a> {
    pub fn new(
        toks: &'a [Token],
        pos: usize,
        line_end: usize,
        command: &'static str,
        syntax: &'static str,
        line: &'a str,
        scope: &'a dyn Scope,
    ) -> Self {
        Args {
            toks,
            pos,
            line_end,
            command,
            syntax,
            line,
            scope,
        }
    }

    pub fn peek(&self) -> Option<&'a Token> {
        self.toks.get(self.pos)
    }

    pub fn at_end(&self) -> bool {
        self.pos >= self.toks.len()
    }

    fn missing(&self, what: &str) -> ParseError {
        ParseError {
            start: self.line_end,
            end: self.line_end + 1,
            message: format!(
                "{} needs {what} here (syntax: {} {})",
                self.command, self.command, self.syntax
            ),
        }
    }

    /// The next token, or an error naming the missing parameter.
    pub fn next_tok(&mut self, what: &str) -> Result<&'a Token, ParseError> {
        match self.toks.get(self.pos) {
            Some(t) => {
                self.pos += 1;
                Ok(t)
            }
            None => Err(self.missing(what)),
        }
    }

    /// A real number parameter: a number, or an expression (doc/language.md).
    pub fn real(&mut self, name: &str) -> Result<f64, ParseError> {
        let e = self.expr(name)?;
        expr::eval(&e, self.scope)
    }

    /// A number's place read as an expression, not evaluated: a number, a word without
    /// separators (`2*r`, `ball_vz(3)` is not: its brackets separate), or `[...]`.
    pub fn expr(&mut self, name: &str) -> Result<Expr, ParseError> {
        // (The message is formatted only when the number is missing.)
        let Some(t) = self.toks.get(self.pos) else {
            return Err(self.missing(&format!("a number `{name}`")));
        };
        self.pos += 1;
        if let Some(v) = parse_real(&t.text) {
            return Ok(Expr {
                kind: Kind::Num(v),
                start: t.start,
                end: t.end,
            });
        }
        if let Some(inner) = t.text.strip_prefix('[') {
            let Some(inner) = inner.strip_suffix(']') else {
                return Err(ParseError::at(t, "this `[` is not closed by `]`"));
            };
            return expr::parse(inner, t.start + 1);
        }
        // A plain word that names nothing (`abc`, `nan`, `1..2`) is a word where a number
        // should be; a word with operators (`2*r`, `-v`) or a known name is an expression.
        let w = &t.text;
        let known = expr::is_name(w)
            && (self.scope.value(&w.to_ascii_lowercase()).is_some()
                || expr::CONSTANTS
                    .iter()
                    .any(|(c, _)| c.eq_ignore_ascii_case(w)));
        let operators = w.contains(['*', '^', '%', '<', '>', '=', '!', '[', ']'])
            || (w.contains(['+', '-'])
                && w.contains(|c: char| c.is_ascii_alphabetic() || c == '_'));
        let glued_bracket = self.line[t.end..].starts_with('(');
        if !(known || operators || glued_bracket && expr::is_name(w)) {
            return Err(ParseError::at(
                t,
                format!("expected a number for `{name}`, found `{}`", t.text),
            ));
        }
        // Commas, slashes and round brackets separate words: an expression with them must be
        // bracketed, or `r/2` would be read as the two numbers `r` and `2`.
        let before = self.line[..t.start].chars().next_back();
        let after = self.line[t.end..].chars().next();
        if before.is_some_and(|c| ",/()".contains(c)) || after.is_some_and(|c| ",/()".contains(c)) {
            return Err(ParseError::at(
                t,
                format!(
                    "`,`, `/` and round brackets separate words: write an expression that holds them in square brackets, e.g. `[{}]`",
                    self.glued(t)
                ),
            ));
        }
        expr::parse(&t.text, t.start)
    }

    /// The text of a word and the words glued to it by `,`, `/` or brackets.
    fn glued(&self, t: &'a Token) -> &'a str {
        let b = self.line.as_bytes();
        let stop = |c: u8| c.is_ascii_whitespace() || c == b';' || c == b'#';
        let mut s = t.start;
        while s > 0 && !stop(b[s - 1]) {
            s -= 1;
        }
        let mut e = t.end;
        while e < b.len() && !stop(b[e]) {
            e += 1;
        }
        self.line.get(s..e).unwrap_or(&t.text)
    }

    /// The rest of the line (up to a comment) as one expression (`IF`, `WHILE`, `LET`,
    /// `UNTIL`); a whole `[...]` is read as its inside.
    pub fn rest_expr(&mut self, what: &str) -> Result<Expr, ParseError> {
        let Some(t) = self.peek() else {
            return Err(self.missing(what));
        };
        // From the first character after the word before: an opening `(` separates words,
        // so the next token starts after it (`let x = (a + b) / 2`).
        let from = match self.pos {
            0 => 0,
            k => self.toks[k - 1].end,
        };
        let rest = self.line.get(from..).unwrap_or("");
        let start = (from + rest.len() - rest.trim_start().len()).min(t.start);
        let text = &self.line[start..];
        let text = &text[..text.find([';', '#']).unwrap_or(text.len())];
        self.pos = self.toks.len();
        let trimmed = text.trim_end();
        if let Some(inner) = trimmed.strip_prefix('[').and_then(|s| s.strip_suffix(']'))
            && !inner.contains(['[', ']'])
        {
            return expr::parse(inner, start + 1);
        }
        expr::parse(text, start)
    }

    /// A positive real (> 0).
    pub fn positive(&mut self, name: &str) -> Result<f64, ParseError> {
        let t = self.peek();
        let v = self.real(name)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(ParseError::at(
                t.expect("real() consumed a token"),
                format!("`{name}` must be positive, got {v}"),
            ))
        }
    }

    /// A non-negative real (>= 0).
    pub fn non_negative(&mut self, name: &str) -> Result<f64, ParseError> {
        let t = self.peek();
        let v = self.real(name)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(ParseError::at(
                t.expect("real() consumed a token"),
                format!("`{name}` must not be negative, got {v}"),
            ))
        }
    }

    /// Three reals.
    pub fn vec3(&mut self, names: [&str; 3]) -> Result<[f64; 3], ParseError> {
        Ok([
            self.real(names[0])?,
            self.real(names[1])?,
            self.real(names[2])?,
        ])
    }

    /// An integer parameter; fractional input is refused.
    pub fn int(&mut self, name: &str) -> Result<i64, ParseError> {
        let Some(t) = self.peek() else {
            return Err(self.missing(&format!("an integer `{name}`")));
        };
        let v = self.real(name).map_err(|e| {
            if e.message.starts_with("expected a number") {
                ParseError::at(
                    t,
                    format!("expected an integer for `{name}`, found `{}`", t.text),
                )
            } else {
                e
            }
        })?;
        if v.fract() != 0.0 {
            return Err(ParseError::at(
                t,
                format!("`{name}` must be a whole number, found `{}`", t.text),
            ));
        }
        if v.abs() > INT_LIMIT as f64 {
            return Err(ParseError::at(
                t,
                format!(
                    "`{name}` = {} is too large: at most {INT_LIMIT} in magnitude",
                    t.text
                ),
            ));
        }
        Ok(v as i64)
    }

    /// A size type number: 1 to the number of size types.
    pub fn size_type(&mut self, name: &str) -> Result<usize, ParseError> {
        Ok(self.int_in(name, 1, crate::sim::scene::MAX_SIZES as i64)? as usize)
    }

    /// A material type number: 1 to the number of material types.
    pub fn material_type(&mut self, name: &str) -> Result<usize, ParseError> {
        Ok(self.int_in(name, 1, crate::sim::scene::MAX_MATERIALS as i64)? as usize)
    }

    /// An integer in `lo..=hi`.
    pub fn int_in(&mut self, name: &str, lo: i64, hi: i64) -> Result<i64, ParseError> {
        let t = self.peek();
        let v = self.int(name)?;
        if v < lo || v > hi {
            let range = if hi >= INT_LIMIT {
                format!("at least {lo}")
            } else {
                format!("between {lo} and {hi}")
            };
            return Err(ParseError::at(
                t.expect("int() consumed a token"),
                format!("`{name}` must be {range}, got {v}"),
            ));
        }
        Ok(v)
    }

    /// A count (>= 0) that fits in usize.
    pub fn count(&mut self, name: &str) -> Result<usize, ParseError> {
        Ok(self.int_in(name, 0, i64::MAX / 2)? as usize)
    }

    /// A 1-based type/index number (>= 1).
    pub fn index(&mut self, name: &str) -> Result<usize, ParseError> {
        Ok(self.int_in(name, 1, i64::MAX / 2)? as usize)
    }

    /// A 0/1 flag.
    pub fn flag(&mut self, name: &str) -> Result<bool, ParseError> {
        Ok(self.int_in(name, 0, 1)? == 1)
    }

    /// A free word (file name, setting value).
    pub fn word(&mut self, name: &str) -> Result<String, ParseError> {
        Ok(self.next_tok(&format!("`{name}`"))?.text.clone())
    }

    /// The next token if it is a number.
    pub fn peek_is_number(&self) -> bool {
        self.peek().is_some_and(|t| {
            parse_real(&t.text).is_some()
                || t.text.starts_with('[')
                || (expr::is_name(&t.text)
                    && self.scope.value(&t.text.to_ascii_lowercase()).is_some())
                || (!expr::is_name(&t.text)
                    && t.text.contains(char::is_alphabetic)
                    && expr::parse(&t.text, t.start)
                        .is_ok_and(|e| expr::eval(&e, self.scope).is_ok()))
        })
    }

    /// A keyword from `set`, required.
    pub fn keyword<K: Copy>(&mut self, set: &[Keyword<K>], what: &str) -> Result<K, ParseError> {
        let t = self.next_tok(what)?;
        match match_keyword(&t.text, set) {
            Ok(k) => Ok(k),
            Err(e) => Err(ParseError::at(t, e.describe(&t.text, what, set))),
        }
    }

    /// The next token as a keyword of `set` if it is one (consumed), else `None` (not consumed).
    pub fn try_keyword<K: Copy>(&mut self, set: &[Keyword<K>]) -> Result<Option<K>, ParseError> {
        let Some(t) = self.peek() else {
            return Ok(None);
        };
        match match_keyword(&t.text, set) {
            Ok(k) => {
                self.pos += 1;
                Ok(Some(k))
            }
            Err(e @ MatchError::Ambiguous(_)) => {
                Err(ParseError::at(t, e.describe(&t.text, "keyword", set)))
            }
            Err(_) => Ok(None),
        }
    }
}
