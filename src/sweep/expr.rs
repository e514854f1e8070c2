//! The arithmetic of `--let`: a value computed from a run's other values, e.g. the velocity
//! components of an oblique collision `v1x = v/2*cos(theta*pi/180)`.
//!
//! Numbers, names, `+ - * / ^` (right-associative power), parentheses, `pi`, and the
//! functions sin cos tan asin acos atan sqrt exp ln log10 abs round floor ceil (one argument)
//! and min max (two).

use crate::lang::lexer::parse_real;

#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Num(f64),
    Name(String),
    Neg(Box<Expr>),
    Bin(char, Box<Expr>, Box<Expr>),
    Call(String, Vec<Expr>),
}

const FUNCTIONS: &[(&str, usize)] = &[
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("asin", 1),
    ("acos", 1),
    ("atan", 1),
    ("sqrt", 1),
    ("exp", 1),
    ("ln", 1),
    ("log10", 1),
    ("abs", 1),
    ("round", 1),
    ("floor", 1),
    ("ceil", 1),
    ("min", 2),
    ("max", 2),
];

struct Parser<'a> {
    s: &'a [u8],
    text: &'a str,
    i: usize,
}

impl Parser<'_> {
    fn skip(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip();
        self.s.get(self.i).copied()
    }

    fn err<T>(&self, what: &str) -> Result<T, String> {
        Err(format!(
            "{what} at character {} of `{}`",
            self.i + 1,
            self.text
        ))
    }

    fn expr(&mut self) -> Result<Expr, String> {
        let mut e = self.term()?;
        while let Some(c @ (b'+' | b'-')) = self.peek() {
            self.i += 1;
            e = Expr::Bin(c as char, Box::new(e), Box::new(self.term()?));
        }
        Ok(e)
    }

    fn term(&mut self) -> Result<Expr, String> {
        let mut e = self.unary()?;
        while let Some(c @ (b'*' | b'/')) = self.peek() {
            self.i += 1;
            e = Expr::Bin(c as char, Box::new(e), Box::new(self.unary()?));
        }
        Ok(e)
    }

    fn unary(&mut self) -> Result<Expr, String> {
        match self.peek() {
            Some(b'-') => {
                self.i += 1;
                Ok(Expr::Neg(Box::new(self.unary()?)))
            }
            Some(b'+') => {
                self.i += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Expr, String> {
        let base = self.atom()?;
        if self.peek() == Some(b'^') {
            self.i += 1;
            return Ok(Expr::Bin('^', Box::new(base), Box::new(self.unary()?)));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<Expr, String> {
        match self.peek() {
            Some(b'(') => {
                self.i += 1;
                let e = self.expr()?;
                if self.peek() != Some(b')') {
                    return self.err("`)` expected");
                }
                self.i += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                let start = self.i;
                while self.i < self.s.len() {
                    let c = self.s[self.i];
                    let exp_sign = matches!(c, b'+' | b'-')
                        && matches!(self.s[self.i - 1], b'e' | b'E' | b'd' | b'D');
                    if c.is_ascii_digit()
                        || matches!(c, b'.' | b'e' | b'E' | b'd' | b'D')
                        || exp_sign
                    {
                        self.i += 1;
                    } else {
                        break;
                    }
                }
                match parse_real(&self.text[start..self.i]) {
                    Some(v) => Ok(Expr::Num(v)),
                    None => {
                        self.i = start;
                        self.err("not a number")
                    }
                }
            }
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let start = self.i;
                while self.i < self.s.len()
                    && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
                {
                    self.i += 1;
                }
                let name = self.text[start..self.i].to_string();
                if self.peek() != Some(b'(') {
                    return Ok(Expr::Name(name));
                }
                let Some(&(_, arity)) = FUNCTIONS.iter().find(|(f, _)| *f == name) else {
                    self.i = start;
                    return self.err(&format!("unknown function `{name}`"));
                };
                self.i += 1;
                let mut args = vec![self.expr()?];
                while self.peek() == Some(b',') {
                    self.i += 1;
                    args.push(self.expr()?);
                }
                if self.peek() != Some(b')') {
                    return self.err("`)` expected");
                }
                self.i += 1;
                if args.len() != arity {
                    return Err(format!(
                        "`{name}` takes {arity} argument{} in `{}`",
                        if arity == 1 { "" } else { "s" },
                        self.text
                    ));
                }
                Ok(Expr::Call(name, args))
            }
            Some(_) => self.err("unexpected character"),
            None => self.err("unexpected end"),
        }
    }
}

/// Parses an expression.
pub fn parse(text: &str) -> Result<Expr, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        text,
        i: 0,
    };
    let e = p.expr()?;
    if p.peek().is_some() {
        return p.err("unexpected character");
    }
    Ok(e)
}

impl Expr {
    /// The names it reads (besides `pi`), in order of first use.
    pub fn names(&self) -> Vec<String> {
        fn walk(e: &Expr, out: &mut Vec<String>) {
            match e {
                Expr::Num(_) => {}
                Expr::Name(n) => {
                    if n != "pi" && !out.contains(n) {
                        out.push(n.clone());
                    }
                }
                Expr::Neg(a) => walk(a, out),
                Expr::Bin(_, a, b) => {
                    walk(a, out);
                    walk(b, out);
                }
                Expr::Call(_, args) => args.iter().for_each(|a| walk(a, out)),
            }
        }
        let mut out = Vec::new();
        walk(self, &mut out);
        out
    }

    /// The value, with `value(name)` giving the names' values.
    pub fn eval(&self, value: &dyn Fn(&str) -> Result<f64, String>) -> Result<f64, String> {
        Ok(match self {
            Expr::Num(v) => *v,
            Expr::Name(n) if n == "pi" => std::f64::consts::PI,
            Expr::Name(n) => value(n)?,
            Expr::Neg(a) => -a.eval(value)?,
            Expr::Bin(op, a, b) => {
                let (x, y) = (a.eval(value)?, b.eval(value)?);
                match op {
                    '+' => x + y,
                    '-' => x - y,
                    '*' => x * y,
                    '/' => x / y,
                    _ => x.powf(y),
                }
            }
            Expr::Call(f, args) => {
                let x = args[0].eval(value)?;
                match f.as_str() {
                    "sin" => x.sin(),
                    "cos" => x.cos(),
                    "tan" => x.tan(),
                    "asin" => x.asin(),
                    "acos" => x.acos(),
                    "atan" => x.atan(),
                    "sqrt" => x.sqrt(),
                    "exp" => x.exp(),
                    "ln" => x.ln(),
                    "log10" => x.log10(),
                    "abs" => x.abs(),
                    "round" => x.round(),
                    "floor" => x.floor(),
                    "ceil" => x.ceil(),
                    "min" => x.min(args[1].eval(value)?),
                    _ => x.max(args[1].eval(value)?),
                }
            }
        })
    }
}

/// A computed value as a command-file number: whole numbers without a point, others with the
/// shortest digits that read back to the same float (exponent form below 1e-4 or from 1e15).
pub fn format_number(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else if x.abs() >= 1e-4 && x.abs() < 1e15 {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(text: &str, vars: &[(&str, f64)]) -> f64 {
        parse(text)
            .unwrap()
            .eval(&|n| {
                vars.iter()
                    .find(|(k, _)| *k == n)
                    .map(|(_, v)| *v)
                    .ok_or(format!("no {n}"))
            })
            .unwrap()
    }

    #[test]
    fn arithmetic_follows_the_usual_precedence() {
        assert_eq!(eval("1 + 2 * 3", &[]), 7.0);
        assert_eq!(eval("(1 + 2) * 3", &[]), 9.0);
        assert_eq!(eval("2 ^ 3 ^ 2", &[]), 512.0);
        assert_eq!(eval("-2 ^ 2", &[]), -4.0);
        assert_eq!(eval("8 / 4 / 2", &[]), 1.0);
        assert_eq!(eval("1.5d-3 * 2", &[]), 3e-3);
        assert_eq!(eval("1e-3+1", &[]), 1.001);
        assert_eq!(eval("max(2, v) - min(1, 3)", &[("v", 5.0)]), 4.0);
    }

    #[test]
    fn oblique_velocity_components() {
        // v/2 (cos 60°, sin 60°) = (0.5, 0.866...) for v = 2.
        let vars = [("v", 2.0), ("theta", 60.0)];
        assert!((eval("v/2*cos(theta*pi/180)", &vars) - 0.5).abs() < 1e-15);
        assert!((eval("v/2*sin(theta*pi/180)", &vars) - 3f64.sqrt() / 2.0).abs() < 1e-15);
        assert_eq!(
            eval("round(64e-6 / (frac * 1e-8))", &[("frac", 0.2)]),
            32000.0
        );
    }

    #[test]
    fn bad_expressions_are_refused() {
        for bad in ["1 +", "(1", "sin(1, 2)", "foo(1)", "1 $ 2", "2 3", ""] {
            assert!(parse(bad).is_err(), "{bad}");
        }
        assert_eq!(parse("a*b+a/pi").unwrap().names(), ["a", "b"]);
    }

    #[test]
    fn numbers_read_back_exactly() {
        for x in [1.0, -3.0, 0.5, 0.1 + 0.2, 1e-7, 3.74e-4, 1e20, 12500.0] {
            let s = format_number(x);
            assert_eq!(parse_real(&s), Some(x), "{s}");
        }
        assert_eq!(format_number(12500.0), "12500");
        assert_eq!(format_number(1e-7), "1e-7");
        assert_eq!(format_number(0.25), "0.25");
    }
}
