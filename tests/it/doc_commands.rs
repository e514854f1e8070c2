//! `doc/commands.md` is generated from the command table; this test fails when it is out of
//! date (`TRUBAL_BLESS=1 cargo test --profile ci --test it doc_commands::` rewrites it).

#[test]
fn doc_commands_is_up_to_date() {
    let want = trubal::lang::doc::reference_markdown();
    if std::env::var_os("TRUBAL_BLESS").is_some() {
        std::fs::write("doc/commands.md", &want).unwrap();
    }
    let have = std::fs::read_to_string("doc/commands.md").unwrap_or_default();
    assert!(
        have == want,
        "doc/commands.md is out of date: run TRUBAL_BLESS=1 cargo test --profile ci --test it doc_commands::"
    );
}

#[test]
fn all_appendix_b_commands_are_in_the_table() {
    let names: Vec<&str> = trubal::lang::table::COMMANDS
        .iter()
        .filter(|d| d.appendix_b)
        .map(|d| d.name)
        .collect();
    assert_eq!(names.len(), 40, "{names:?}");
}
