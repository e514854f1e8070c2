//! Formatting of results for people (tables) and machines (JSON, one object per line).

pub mod fields;
pub mod groups;
pub mod print;
pub mod vtk;
