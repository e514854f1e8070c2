//! The command language: lexer, keyword matching, the command table and the parser.
//! Data flows one way: text → [`parse::parse_line`] → [`command::Command`].

pub mod args;
pub mod command;
pub mod doc;
pub mod expr;
pub mod keyword;
pub mod lexer;
pub mod parse;
pub mod range;
pub mod script;
pub mod table;

pub use args::ParseError;
pub use command::Command;
pub use parse::{Parsed, parse_line, parse_line_in};

#[cfg(test)]
mod tests;
