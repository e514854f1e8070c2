//! Splits one line of the command language into tokens (nom).
//!
//! Lexical rules (doc/commands.md, `doc/spec/commands.md`): separators are runs of
//! blanks, tabs, commas, slashes and round brackets; `;` or `#` start a comment that runs to the
//! end of the line. A word in double quotes is taken as it is (`save "runs/a.sav"`); an
//! expression in square brackets is one word with its brackets (`rad [r/2] 1`). Every
//! token keeps its column span so that errors can point at it.

use nom::{
    IResult, Parser,
    bytes::complete::{take_till1, take_while},
    character::complete::anychar,
    combinator::{recognize, rest},
    sequence::preceded,
};

/// One word or number of a command line, with its byte span in the line.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub text: String,
    /// Byte offset of the first character in the line.
    pub start: usize,
    /// Byte offset one past the last character.
    pub end: usize,
}

fn is_sep(c: char) -> bool {
    c.is_whitespace() || matches!(c, ',' | '/' | '(' | ')')
}

fn is_comment(c: char) -> bool {
    c == ';' || c == '#'
}

fn separators(input: &str) -> IResult<&str, &str> {
    take_while(is_sep)(input)
}

fn word(input: &str) -> IResult<&str, &str> {
    take_till1(|c| is_sep(c) || is_comment(c))(input)
}

fn comment(input: &str) -> IResult<&str, &str> {
    recognize(preceded(anychar, rest)).parse(input)
}

/// Tokenises one line; a comment ends the line. Never fails: every character is either a
/// separator, part of a word, or part of a comment.
pub fn tokenize(line: &str) -> Vec<Token> {
    let mut out = Vec::new();
    let mut input = line;
    while let Some((t, after)) = next_token(line, input) {
        out.push(t);
        input = after;
    }
    out
}

/// The first token of a line (what [`tokenize`] gives first), without reading the rest.
pub fn first_token(line: &str) -> Option<Token> {
    next_token(line, line).map(|(t, _)| t)
}

/// The token that starts `input` (the rest of `line`) after its separators, and what
/// follows it; `None` at the end of the line or at a comment.
fn next_token<'a>(line: &str, input: &'a str) -> Option<(Token, &'a str)> {
    let (input, _) = separators(input).ok()?;
    if input.is_empty() {
        return None;
    }
    if input.starts_with(is_comment) {
        let _ = comment(input);
        return None;
    }
    let start = line.len() - input.len();
    if input.starts_with('[') {
        // An expression in square brackets is one word, separators and all
        // (`rad [r/2] 1`); an unclosed one runs to the end of the line (or its comment).
        let len = match input.find(']') {
            Some(k) => k + 1,
            None => input.find(is_comment).unwrap_or(input.len()),
        };
        let t = Token {
            text: input[..len].to_string(),
            start,
            end: start + len,
        };
        return Some((t, &input[len..]));
    }
    if let Some(rest) = input.strip_prefix('"') {
        // A quoted word: everything up to the closing quote (file names with `/`).
        let (text, after) = match rest.find('"') {
            Some(k) => (&rest[..k], &rest[k + 1..]),
            None => (rest, ""),
        };
        let t = Token {
            text: text.to_string(),
            start,
            end: line.len() - after.len(),
        };
        return Some((t, after));
    }
    let (after, w) = word(input).ok()?;
    let t = Token {
        text: w.to_string(),
        start,
        end: start + w.len(),
    };
    Some((t, after))
}

/// Parses a real number in Rust or Fortran style (`1`, `-2e-7`, `1.2E+3`, `1.d-3`).
/// Returns `None` for anything else (including `inf` and `nan`, which a user never means).
pub fn parse_real(text: &str) -> Option<f64> {
    // Fortran's exponent letter `d` is read as `e` (a copy only when there is one).
    let t: std::borrow::Cow<str> = if text.contains(['d', 'D']) {
        text.chars()
            .map(|c| if c == 'd' || c == 'D' { 'e' } else { c })
            .collect::<String>()
            .into()
    } else {
        text.into()
    };
    let first = t.chars().next()?;
    if !(first.is_ascii_digit() || first == '.' || first == '-' || first == '+') {
        return None;
    }
    if !t
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'))
    {
        return None;
    }
    let v: f64 = t.parse().ok()?;
    v.is_finite().then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(line: &str) -> Vec<String> {
        tokenize(line).into_iter().map(|t| t.text).collect()
    }

    #[test]
    fn separators_and_comments() {
        assert_eq!(
            texts("start 0.1,0.1 (0.1) 1000/2000 2 log"),
            ["start", "0.1", "0.1", "0.1", "1000", "2000", "2", "log"]
        );
        assert_eq!(texts("  cycle 10 ; a comment"), ["cycle", "10"]);
        assert_eq!(texts("# whole line"), Vec::<String>::new());
        assert_eq!(texts(""), Vec::<String>::new());
        assert_eq!(texts("pr c#comment"), ["pr", "c"]);
    }

    #[test]
    fn quoted_words_keep_slashes() {
        assert_eq!(texts("save \"runs/a b.sav\" ; x"), ["save", "runs/a b.sav"]);
        assert_eq!(texts("save \"unclosed/x"), ["save", "unclosed/x"]);
    }

    #[test]
    fn bracketed_expressions_are_one_word() {
        assert_eq!(texts("rad [r / 2, 1] 1"), ["rad", "[r / 2, 1]", "1"]);
        assert_eq!(texts("rad [r/2 ; x"), ["rad", "[r/2 "]);
    }

    #[test]
    fn spans_point_into_the_line() {
        let line = "  rad  30e-6 1";
        for t in tokenize(line) {
            assert_eq!(&line[t.start..t.end], t.text);
        }
    }

    #[test]
    fn first_token_is_the_first_of_the_line() {
        for line in [
            "",
            "   ",
            "; comment",
            "  cr 1 2 3",
            ",(/ if x > 1",
            "[r/2] 1",
            "\"a/b c\" d",
            "end# c",
            "\"unclosed",
        ] {
            assert_eq!(
                first_token(line),
                tokenize(line).into_iter().next(),
                "{line:?}"
            );
        }
        assert_eq!(
            first_token("  cr 1").map(|t| (t.start, t.end)),
            Some((2, 4))
        );
    }

    #[test]
    fn numbers() {
        assert_eq!(parse_real("1"), Some(1.0));
        assert_eq!(parse_real("-2e-7"), Some(-2e-7));
        assert_eq!(parse_real("1.2E+3"), Some(1200.0));
        assert_eq!(parse_real("1.d-3"), Some(1e-3));
        assert_eq!(parse_real(".5"), Some(0.5));
        assert_eq!(parse_real("abc"), None);
        assert_eq!(parse_real("inf"), None);
        assert_eq!(parse_real("1e999"), None);
        assert_eq!(parse_real("1..2"), None);
        assert_eq!(parse_real("2D+2"), Some(200.0));
        assert_eq!(parse_real("d"), None);
    }

    #[test]
    fn garbage_does_not_panic() {
        let s = "\u{0}\u{1}\u{7f}é∑ ,,(( ;";
        let _ = tokenize(s);
    }
}
