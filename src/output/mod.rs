//! Formatting of results for people (tables) and machines (JSON, one object per line).

pub mod print;
pub mod vtk;
