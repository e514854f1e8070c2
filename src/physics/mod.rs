//! Contact laws as pure functions of plain numbers, each with closed-form unit tests.

pub mod bridge;
pub mod dashpot;
pub mod hertz;
pub mod hertz_edge;
pub mod jkr;
pub mod jkr_branch;
pub mod jkr_nguyen;
pub mod mdr;
pub mod modified_jkr;
pub mod pasha_linear;
pub mod restitution;
pub mod rolling;
pub mod tangential;
pub mod thornton_ning;
pub mod walton;
