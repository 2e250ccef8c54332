//! The core crate's integration tests, in one binary (far less linking than
//! one binary per file): one module per area.

/// Random generator graphs and a naive tree model of chromosomes.
mod common;

/// SMC, SOSMC, RJMCMC and the GA against random search on the blocks problem.
mod baselines;
/// Checkpoint and resume, bit-identical, for every optimizer.
mod checkpoint;
/// The GA: reaches the optimum, beats random search, deterministic.
mod ga;
/// The packed genome and its operators over random graphs.
mod genome_props;
/// The hybrid (GA, then RJMCMC): switches, valid, deterministic, beats random search.
mod hybrid;
/// An interrupt flag stops a run mid-generation at the last complete one.
mod interrupt;
/// The island GA: valid, deterministic, beats random search.
mod islands;
/// Grow's and cut's choice frequencies (chi-square).
mod operator_stats;
/// RJMCMC samples the posterior; chains stay valid.
mod rjmcmc;
/// SMC and SOSMC reproduce the prior; particles stay valid.
mod smc;
/// The tandem (GA beside RJMCMC): both run, valid, deterministic, beats random search.
mod tandem;
