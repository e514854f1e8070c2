//! trubal: a discrete element simulator for spherical particles driven by TRUBAL's mnemonic
//! command language. See ARCHITECTURE.md for the map of the modules.

pub mod analysis;
pub mod chart;
pub mod checkpoint;
pub mod lang;
pub mod output;
pub mod physics;
pub mod plot;
#[cfg(feature = "python")]
mod python;
pub mod session;
pub mod sim;
pub mod sweep;
