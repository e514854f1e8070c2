//! `$name` and `${name}` in command lines: where they are, and their replacement by the values
//! given with `--set`. The session substitutes them line by line; `trubal sweep` reads the same
//! places to check a sweep's parameters against its command file before anything runs.

use std::collections::HashMap;

use super::LineError;

/// One `$name` or `${name}` in a line: its byte span and the name.
#[derive(Clone, Debug, PartialEq)]
pub struct Placeholder {
    pub start: usize,
    pub end: usize,
    pub name: String,
}

/// The placeholders of a line, in order. A comment (from `;` or `#`) has none: its `$` are
/// words. An unclosed `${` is an error; a lone `$` is a placeholder with an empty name.
pub fn placeholders(line: &str) -> Result<Vec<Placeholder>, LineError> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b';' || b[i] == b'#' {
            break;
        }
        if b[i] != b'$' {
            i += 1;
            continue;
        }
        let (name_start, braced) = if b.get(i + 1) == Some(&b'{') {
            (i + 2, true)
        } else {
            (i + 1, false)
        };
        let mut j = name_start;
        while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
            j += 1;
        }
        let end = if braced {
            if b.get(j) != Some(&b'}') {
                return Err(LineError {
                    start: i,
                    end: j,
                    message: "unclosed `${`".into(),
                });
            }
            j + 1
        } else {
            j
        };
        out.push(Placeholder {
            start: i,
            end,
            name: line[name_start..j].to_string(),
        });
        i = end;
    }
    Ok(out)
}

/// The line with every placeholder replaced by its value; a placeholder without one (or a
/// lone `$`) is an error located on it.
pub fn substitute(line: &str, vars: &HashMap<String, String>) -> Result<String, LineError> {
    let mut out = String::with_capacity(line.len());
    let mut last = 0;
    for p in placeholders(line)? {
        match vars.get(&p.name) {
            Some(v) if !p.name.is_empty() => {
                out.push_str(&line[last..p.start]);
                out.push_str(v);
                last = p.end;
            }
            _ => {
                return Err(LineError {
                    start: p.start,
                    end: p.end,
                    message: format!(
                        "`${}` has no value: give it on the command line with --set {}=VALUE",
                        p.name, p.name
                    ),
                });
            }
        }
    }
    out.push_str(&line[last..]);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vars(kv: &[(&str, &str)]) -> HashMap<String, String> {
        kv.iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    #[test]
    fn finds_plain_and_braced_names_outside_comments() {
        let p = placeholders("velocity 0 0 -$v ${n}x ; $not # $either").unwrap();
        let names: Vec<&str> = p.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["v", "n"]);
        assert_eq!((p[0].start, p[0].end), (14, 16));
        assert_eq!((p[1].start, p[1].end), (17, 21));
    }

    #[test]
    fn substitutes_and_locates_missing_values() {
        let v = vars(&[("v", "2"), ("n", "10")]);
        assert_eq!(
            substitute("velocity 0 0 -$v ${n}0 ; $x", &v).unwrap(),
            "velocity 0 0 -2 100 ; $x"
        );
        let e = substitute("cycle $m", &v).unwrap_err();
        assert_eq!((e.start, e.end), (6, 8));
        assert!(e.message.contains("`$m` has no value"), "{}", e.message);
        assert!(substitute("cycle ${n", &v).is_err());
        assert!(substitute("cycle $ 1", &v).is_err());
    }
}
