//! [`MethodParams`]: any of the methods, chosen at run time.

use super::{
    Fitness, Ga, GaParams, Hybrid, HybridParams, IslandGa, IslandParams, OptimizeError, Optimizer,
    Rjmcmc, RjmcmcParams, Run, RunResult, Smc, SmcParams, Tandem, TandemParams,
};

/// The parameters of one of the methods, chosen at run time (an experiment
/// file's `method = "..."`); runs as that method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MethodParams {
    /// GA parameters.
    Ga(GaParams),
    /// SMC or SOSMC parameters (the slot order tells which).
    Smc(SmcParams),
    /// RJMCMC parameters.
    Rjmcmc(RjmcmcParams),
    /// Island GA parameters.
    Islands(IslandParams),
    /// GA-then-RJMCMC parameters.
    Hybrid(HybridParams),
    /// GA-beside-RJMCMC parameters.
    Tandem(TandemParams),
}

impl MethodParams {
    /// Whether the method regrows whole subtrees from the generator's own
    /// distribution (RJMCMC's jumps, in the chains or as the GA's local
    /// search): without a `max_len`, a generator whose uncontrolled models
    /// can be huge then proposes models of thousands of genes.
    #[must_use]
    pub fn regrows_subtrees(&self) -> bool {
        match *self {
            Self::Ga(p) => p.local_search > 0,
            Self::Islands(p) => p.ga.local_search > 0,
            Self::Smc(_) => false,
            Self::Rjmcmc(_) | Self::Hybrid(_) | Self::Tandem(_) => true,
        }
    }
}

impl Optimizer for MethodParams {
    fn name(&self) -> &'static str {
        match *self {
            Self::Ga(p) => Ga::new(p).name(),
            Self::Smc(p) => Smc::new(p).name(),
            Self::Rjmcmc(p) => Rjmcmc::new(p).name(),
            Self::Islands(p) => IslandGa::new(p).name(),
            Self::Hybrid(p) => Hybrid::new(p).name(),
            Self::Tandem(p) => Tandem::new(p).name(),
        }
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        match *self {
            Self::Ga(p) => Ga::new(p).run_from(run),
            Self::Smc(p) => Smc::new(p).run_from(run),
            Self::Rjmcmc(p) => Rjmcmc::new(p).run_from(run),
            Self::Islands(p) => IslandGa::new(p).run_from(run),
            Self::Hybrid(p) => Hybrid::new(p).run_from(run),
            Self::Tandem(p) => Tandem::new(p).run_from(run),
        }
    }
}
