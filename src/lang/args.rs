//! A cursor over the tokens of one command, with typed readers that produce located errors.

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
}

impl<'a> Args<'a> {
    pub fn new(
        toks: &'a [Token],
        pos: usize,
        line_end: usize,
        command: &'static str,
        syntax: &'static str,
    ) -> Self {
        Args {
            toks,
            pos,
            line_end,
            command,
            syntax,
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

    /// A real number parameter.
    pub fn real(&mut self, name: &str) -> Result<f64, ParseError> {
        let t = self.next_tok(&format!("a number `{name}`"))?;
        parse_real(&t.text).ok_or_else(|| {
            ParseError::at(
                t,
                format!("expected a number for `{name}`, found `{}`", t.text),
            )
        })
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
        let t = self.next_tok(&format!("an integer `{name}`"))?;
        let v = parse_real(&t.text).ok_or_else(|| {
            ParseError::at(
                t,
                format!("expected an integer for `{name}`, found `{}`", t.text),
            )
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
        self.peek().is_some_and(|t| parse_real(&t.text).is_some())
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
