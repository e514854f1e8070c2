//! Keyword matching with TRUBAL's abbreviation rule.
//!
//! A keyword is written with its minimal abbreviation in upper case (`PRint`, `RAdius`). A word
//! matches it when the word is a case-insensitive prefix of the full name and at least as long
//! as the upper-case part (Lian 1994, Appendix B.1). A word equal to a full name always matches
//! that name. Two or more matches, or a word that is only a too-short prefix, is an error that
//! names the candidates and their shortest spellings.

/// A keyword: its name with the minimal abbreviation in upper case, and the value it stands for.
#[derive(Clone, Copy, Debug)]
pub struct Keyword<K> {
    pub name: &'static str,
    pub value: K,
}

/// Shorthand constructor used by the tables.
pub const fn kw<K>(name: &'static str, value: K) -> Keyword<K> {
    Keyword { name, value }
}

/// The minimal abbreviation: the leading upper-case letters, digits and dashes.
pub fn minimal(name: &str) -> &str {
    let n = name
        .char_indices()
        .find(|(_, c)| c.is_ascii_lowercase())
        .map(|(i, _)| i)
        .unwrap_or(name.len());
    &name[..n.max(1)]
}

#[derive(Debug, PartialEq)]
pub enum MatchError {
    /// Several keywords match: their indices.
    Ambiguous(Vec<usize>),
    /// The word is a prefix of these keywords but shorter than their minimal abbreviations.
    TooShort(Vec<usize>),
    /// Nothing matches; the closest keyword, if any is close.
    Unknown(Option<usize>),
}

impl MatchError {
    /// A sentence for the user: what matched or what was expected.
    pub fn describe<K>(&self, word: &str, what: &str, set: &[Keyword<K>]) -> String {
        let list = |ix: &[usize]| {
            let names: Vec<String> = ix
                .iter()
                .map(|&i| format!("{} ({})", set[i].name, minimal(set[i].name).to_lowercase()))
                .collect();
            names.join(" or ")
        };
        match self {
            MatchError::Ambiguous(ix) => format!("`{word}` is ambiguous: {}?", list(ix)),
            MatchError::TooShort(ix) => {
                format!("`{word}` is too short to choose: {}?", list(ix))
            }
            MatchError::Unknown(close) => {
                let mut s = format!("unknown {what} `{word}`");
                let lower = word.to_ascii_lowercase();
                if what == "command" && ["quit", "exit", "bye", "q"].contains(&lower.as_str()) {
                    s.push_str("; STOp ends the session (or the end of the file, Ctrl-D)");
                } else if let Some(i) = close {
                    s.push_str(&format!("; did you mean {}?", set[*i].name));
                } else if set.len() <= 16 {
                    let names: Vec<&str> = set.iter().map(|k| k.name).collect();
                    s.push_str(&format!("; expected one of {}", names.join(", ")));
                }
                s
            }
        }
    }
}

/// Finds the keyword a word stands for.
pub fn match_keyword<K: Copy>(word: &str, set: &[Keyword<K>]) -> Result<K, MatchError> {
    if let Some(k) = set.iter().find(|k| k.name.eq_ignore_ascii_case(word)) {
        return Ok(k.value);
    }
    // The one keyword the word abbreviates, found without allocating; anything else (no
    // match, several, too short) is sorted out below.
    let mut only = None;
    for k in set {
        if abbreviates(word, k.name) && word.len() >= minimal(k.name).len() {
            if only.is_some() {
                only = None;
                break;
            }
            only = Some(k.value);
        }
    }
    if let Some(v) = only {
        return Ok(v);
    }
    let w = word.to_ascii_lowercase();
    let mut full = Vec::new();
    let mut short = Vec::new();
    for (i, k) in set.iter().enumerate() {
        if abbreviates(&w, k.name) {
            if w.len() >= minimal(k.name).len() {
                full.push(i);
            } else {
                short.push(i);
            }
        }
    }
    match full.len() {
        1 => Ok(set[full[0]].value),
        0 if !short.is_empty() => Err(MatchError::TooShort(short)),
        0 => Err(MatchError::Unknown(closest(&w, set))),
        _ => Err(MatchError::Ambiguous(full)),
    }
}

/// Whether `word` is a case-insensitive prefix of `name` (ASCII case folding, byte by byte:
/// the same as comparing the two lower-cased strings).
fn abbreviates(word: &str, name: &str) -> bool {
    name.as_bytes()
        .get(..word.len())
        .is_some_and(|head| head.eq_ignore_ascii_case(word.as_bytes()))
}

/// The keyword a mistyped word most likely meant: among the keywords whose shortest form the
/// word starts with (`energies` → ENErgy, not ENTries), else among those that share its first
/// letter (`e` suggests nothing rather than CReate), the one at the smallest edit distance.
fn closest<K>(w: &str, set: &[Keyword<K>]) -> Option<usize> {
    let starts: Vec<usize> = (0..set.len())
        .filter(|&i| w.starts_with(&minimal(set[i].name).to_ascii_lowercase()))
        .collect();
    let first = w.chars().next();
    let pool: Vec<usize> = if starts.is_empty() {
        (0..set.len())
            .filter(|&i| set[i].name.chars().next().map(|c| c.to_ascii_lowercase()) == first)
            .collect()
    } else {
        starts
    };
    let mut best = None;
    let mut best_d = usize::MAX;
    for i in pool {
        let k = &set[i];
        let name = k.name.to_ascii_lowercase();
        // Compare with the prefix of the same length (abbreviations are prefixes).
        let wl = w.chars().count().max(minimal(k.name).len());
        let d = (wl.saturating_sub(1)..=wl + 1)
            .map(|l| edit_distance(w, &name.chars().take(l).collect::<String>()))
            .min()
            .unwrap_or(usize::MAX);
        if d < best_d {
            best_d = d;
            best = Some(i);
        }
    }
    (best_d <= 1 + w.len() / 4).then_some(best).flatten()
}

fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut cur = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    const SET: &[Keyword<u8>] = &[
        kw("PLot", 0),
        kw("PRint", 1),
        kw("PRA", 2),
        kw("Cycle", 3),
        kw("COHesion", 4),
        kw("2-D", 5),
    ];

    #[test]
    fn abbreviation_rule() {
        assert_eq!(minimal("PRint"), "PR");
        assert_eq!(minimal("2-D"), "2-D");
        assert_eq!(match_keyword("pri", SET), Ok(1));
        assert_eq!(match_keyword("PRINT", SET), Ok(1));
        assert_eq!(match_keyword("pl", SET), Ok(0));
        assert_eq!(match_keyword("c", SET), Ok(3));
        assert_eq!(match_keyword("coh", SET), Ok(4));
        assert_eq!(match_keyword("2-d", SET), Ok(5));
        // `pra` is PRA exactly even though it is also a prefix of nothing else.
        assert_eq!(match_keyword("pra", SET), Ok(2));
    }

    #[test]
    fn ambiguity_and_short_words() {
        assert_eq!(
            match_keyword("p", SET),
            Err(MatchError::TooShort(vec![0, 1, 2]))
        );
        assert_eq!(match_keyword("pr", SET), Ok(1));
        assert_eq!(match_keyword("co", SET), Err(MatchError::TooShort(vec![4])));
        let e = match_keyword("p", SET)
            .unwrap_err()
            .describe("p", "command", SET);
        assert!(e.contains("PLot (pl) or PRint (pr) or PRA (pra)"), "{e}");
        const TWO: &[Keyword<u8>] = &[kw("ENErgy", 0), kw("ENTries", 1), kw("ENd", 2)];
        assert_eq!(match_keyword("ene", TWO), Ok(0));
        assert_eq!(match_keyword("en", TWO), Ok(2));
        assert_eq!(
            match_keyword("e", TWO),
            Err(MatchError::TooShort(vec![0, 1, 2]))
        );
        const AMB: &[Keyword<u8>] = &[kw("Xa", 0), kw("Xb", 1)];
        assert_eq!(
            match_keyword("x", AMB),
            Err(MatchError::Ambiguous(vec![0, 1]))
        );
    }

    /// The rule of Lian 1994 Appendix B.1 written out plainly (lower-cased copies, every
    /// keyword looked at): the allocation-free matcher must give what it gives for every
    /// prefix, in three cases, of every command word, and for words that match nothing.
    #[test]
    fn matcher_agrees_with_the_rule_on_the_command_table() {
        fn rule(word: &str, set: &[Keyword<usize>]) -> Option<usize> {
            let w = word.to_lowercase();
            if let Some(k) = set.iter().find(|k| k.name.to_lowercase() == w) {
                return Some(k.value);
            }
            let full: Vec<usize> = set
                .iter()
                .filter(|k| {
                    let n = k.name.to_lowercase();
                    let upper = k.name.chars().take_while(|c| !c.is_lowercase()).count();
                    n.starts_with(&w) && w.chars().count() >= upper.max(1)
                })
                .map(|k| k.value)
                .collect();
            (full.len() == 1).then(|| full[0])
        }
        let set = crate::lang::table::command_keywords();
        let mut words = vec!["".to_string(), "zz".into(), "é".into(), "cré".into()];
        for k in set {
            for n in 1..=k.name.len() {
                let p = &k.name[..n];
                words.extend([p.to_string(), p.to_lowercase(), p.to_uppercase()]);
            }
            words.push(format!("{}x", k.name));
        }
        for w in &words {
            assert_eq!(match_keyword(w, set).ok(), rule(w, set), "`{w}`");
        }
    }

    #[test]
    fn suggestions() {
        match match_keyword("prnt", SET) {
            Err(MatchError::Unknown(Some(1))) => {}
            other => panic!("{other:?}"),
        }
        assert_eq!(match_keyword("zzzzzz", SET), Err(MatchError::Unknown(None)));
        const EN: &[Keyword<u8>] = &[kw("ENErgy", 0), kw("ENTries", 1), kw("CReate", 2)];
        assert_eq!(
            match_keyword("energies", EN),
            Err(MatchError::Unknown(Some(0)))
        );
        assert_eq!(
            match_keyword("e", EN),
            Err(MatchError::TooShort(vec![0, 1]))
        );
        assert_eq!(match_keyword("x", EN), Err(MatchError::Unknown(None)));
    }
}
