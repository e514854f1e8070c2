//! The integration tests: one binary (one link, shared helpers in `common`), a module per
//! subject. Run one subject with `cargo test --profile ci --test it NAME::`.

mod common;

mod adhesion;
mod architecture;
mod broken_pipe;
mod cell;
mod chart;
mod checkpoint;
mod cli;
mod continuation;
mod cycle_physics;
mod delete;
mod doc_commands;
mod elastic_gas;
mod experiments;
mod fields;
mod fuzz_commands;
mod fuzz_inputs;
mod golden;
mod groups;
mod hard_cases;
mod hertz_mindlin;
mod indentation;
mod json_output;
mod language;
mod liquid;
mod nguyen_jkr;
mod oblique_impact;
mod pair_values;
mod pasha_laws;
mod plot;
mod procedures;
mod readme;
mod restitution;
mod slurm;
mod sweep;
mod tables;
mod terminal;
mod threads;
mod timestep_study;
mod touching;
mod trust;
mod vtk;
