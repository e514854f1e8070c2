//! Help text and the command reference (`doc/commands.md`), generated from the command table.

use super::keyword::minimal;
use super::table::{COMMANDS, CommandDef, command_keywords};

/// One-line-per-command list for `help`.
pub fn help_index() -> String {
    let mut s =
        String::from("Commands (type the upper-case part at least; `help NAME` for details):\n");
    for d in COMMANDS {
        s.push_str(&format!("  {:<12} {}\n", d.name, d.syntax));
    }
    s
}

/// Help for one command, found by the same abbreviation rule as the parser.
pub fn help_for(word: &str) -> Result<String, String> {
    let keys = command_keywords();
    match super::table::find_command(word, &keys) {
        Ok(i) => Ok(help_entry(&COMMANDS[i])),
        Err(e) => Err(e.describe(word, "command", &keys)),
    }
}

fn help_entry(d: &CommandDef) -> String {
    let mut s = format!(
        "{} {}\n  shortest form: {}\n  {}\n",
        d.name,
        d.syntax,
        minimal(d.name).to_lowercase(),
        d.help
    );
    if !d.keywords.is_empty() {
        // The items or keywords it takes, wrapped as a terminal shows them.
        s.push_str("  keywords (upper-case part at least):\n");
        let mut line = String::from("   ");
        for k in d.keywords {
            if line.len() + k.len() + 1 > 90 {
                s.push_str(&line);
                s.push('\n');
                line = String::from("   ");
            }
            line.push(' ');
            line.push_str(k);
        }
        s.push_str(&line);
        s.push('\n');
    }
    s
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
