//! Help text and the command reference (`doc/commands.md`), generated from the command table.

use super::keyword::{Keyword, kw, match_keyword, minimal};
use super::table::{COMMANDS, CommandDef, command_keywords};

/// One-line-per-command list for `help`.
pub fn help_index() -> String {
    let mut s = String::from(
        "Commands (type the upper-case part at least; `help NAME` for details, `help NAME ITEM` for one item):\n",
    );
    for d in COMMANDS {
        s.push_str(&format!("  {:<12} {}\n", d.name, d.syntax));
    }
    s
}

/// Help for one command, found by the same abbreviation rule as the parser; with an item
/// (`help set outdir`, `help print energy`), the part of the help about that item.
pub fn help_for(word: &str, item: Option<&str>) -> Result<String, String> {
    let keys = command_keywords();
    let d = match super::table::find_command(word, keys) {
        Ok(i) => &COMMANDS[i],
        Err(e) => return Err(e.describe(word, "command", keys)),
    };
    let Some(item) = item else {
        return Ok(help_entry(d));
    };
    let items: Vec<Keyword<usize>> = d
        .keywords
        .iter()
        .enumerate()
        .map(|(i, k)| kw(k, i))
        .collect();
    if items.is_empty() {
        return Err(format!("{} takes no items or keywords", d.name));
    }
    let name = match match_keyword(item, &items) {
        Ok(i) => d.keywords[i],
        Err(e) => return Err(e.describe(item, &format!("{} item", d.name), &items)),
    };
    let parts = item_help(d.help, name);
    let mut s = format!("{} {name}\n", d.name);
    if parts.is_empty() {
        // No text of its own: the command's help says what its items do.
        s.push_str(&format!("  {}\n", d.help));
    } else {
        for p in parts {
            s.push_str(&format!("  {p}\n"));
        }
    }
    Ok(s)
}

fn help_entry(d: &CommandDef) -> String {
    let mut s = format!(
        "{} {}\n  shortest form: {}\n",
        d.name,
        d.syntax,
        minimal(d.name).to_lowercase(),
    );
    if let Some(items) = d.help.strip_prefix("Settings: ") {
        // SET: one paragraph per item.
        s.push_str("  Settings (`help set NAME` for one):\n");
        for p in split_parts(items) {
            s.push_str(&format!("  - {p}\n"));
        }
    } else {
        s.push_str(&format!("  {}\n", d.help));
    }
    if !d.keywords.is_empty() {
        // The items or keywords it takes (`help NAME ITEM` for one); `wrap` folds the line.
        s.push_str("  keywords (upper-case part at least):\n   ");
        for k in d.keywords {
            s.push(' ');
            s.push_str(k);
        }
        s.push('\n');
    }
    s
}

/// The parts of a help text (split at `; ` outside brackets) that are about `name`: those that
/// begin with it, or name it as an alternative (`TOL d | XRES d | SMIN s`).
fn item_help<'a>(help: &'a str, name: &str) -> Vec<&'a str> {
    let upper = name.to_ascii_uppercase();
    split_parts(help)
        .into_iter()
        .map(|p| p.strip_prefix("Settings: ").unwrap_or(p))
        .filter(|p| {
            let head = p.split_whitespace().next().unwrap_or("");
            head.eq_ignore_ascii_case(&upper) || p.contains(&format!("| {name} "))
        })
        .collect()
}

/// A help text split at `; ` outside brackets, without the final full stop.
fn split_parts(help: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    let bytes = help.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            b';' if depth == 0 && bytes.get(i + 1) == Some(&b' ') => {
                parts.push(help[start..i].trim());
                start = i + 2;
            }
            _ => {}
        }
    }
    parts.push(help[start..].trim().trim_end_matches('.'));
    parts
}

/// Wraps every line of `text` to `width` columns at blanks; a continuation keeps the line's
/// indentation and two more blanks.
pub fn wrap(text: &str, width: usize) -> String {
    let width = width.max(40);
    let mut out = String::new();
    for line in text.lines() {
        let indent = line.len() - line.trim_start().len();
        let cont = " ".repeat(indent + 2);
        let mut cur = line[..indent].to_string();
        let mut cur_len = indent;
        let mut first = true;
        for w in line.split_whitespace() {
            let wl = w.chars().count();
            if !first && cur_len + 1 + wl > width {
                out.push_str(&cur);
                out.push('\n');
                cur = cont.clone();
                cur_len = cont.len();
                first = true;
            }
            if !first {
                cur.push(' ');
                cur_len += 1;
            }
            cur.push_str(w);
            cur_len += wl;
            first = false;
        }
        out.push_str(&cur);
        out.push('\n');
    }
    out
}

/// The Markdown command reference.
pub fn reference_markdown() -> String {
    let mut s = String::new();
    s.push_str("# Command reference\n\n");
    s.push_str("Generated from the command table in `src/lang/table.rs` (a test fails when this file is out of date;\n");
    s.push_str("regenerate with `TRUBAL_BLESS=1 cargo test --profile ci doc_commands`).\n\n");
    s.push_str("Type a command or keyword in full or abbreviated to at least its upper-case letters, in any case.\n");
    s.push_str("Separators: blanks, tabs, commas, slashes, round brackets. Comments start with `;` or `#`.\n");
    s.push_str("A word in double quotes is taken as it is, e.g. a file name with a directory: `save \"runs/a.sav\"`.\n");
    s.push_str(
        "Several complete commands may share a line (`plot save cycle 200 plot bou rdisp`).\n",
    );
    s.push_str("`$name` or `${name}` is replaced by a value given as `--set name=value` on the command line.\n\n");
    s.push_str("Historical clashes are settled by the abbreviation rule: `STArt`/`STOp` (`s`, `st` are too short),\n");
    s.push_str(
        "`RESTart`/`RESEt`/`RSet` (`r`, `res` too short), `PLot`/`PRint` (`pl`, `pr`; `p` alone is `PRint`, as in Appendix B.1's `p c`),\n",
    );
    s.push_str("`PRint ENErgy`/`ENTries` (`e`, `en` too short). A too-short or ambiguous word is an error that names the candidates.\n\n");
    s.push_str(
        "| command | shortest | parameters | Appendix B | description |\n|---|---|---|---|---|\n",
    );
    for d in COMMANDS {
        s.push_str(&format!(
            "| `{}` | `{}` | `{}` | {} | {} |\n",
            d.name,
            minimal(d.name).to_lowercase(),
            d.syntax.replace('|', "\\|"),
            if d.appendix_b { "yes" } else { "added" },
            d.help.replace('|', "\\|")
        ));
    }
    s.push_str("\n## Keywords by command\n\n");
    for d in COMMANDS.iter().filter(|d| !d.keywords.is_empty()) {
        s.push_str(&format!(
            "- `{}`: {}\n",
            d.name,
            d.keywords
                .iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    s
}
