//! `[ga]`, `[smc]`, `[sosmc]`, `[rjmcmc]`, `[islands]` and budgets. A
//! method without a table gets the paper's spaceship presets; a key left out
//! of a table gets the preset's value. The island GA is the experiment's GA
//! split into islands, with the GA's budget unless `[islands]` gives one;
//! the hybrid runs the experiment's GA, then its RJMCMC. Every GA starts
//! challengers after `DEFAULT_CHALLENGE` steps without progress unless its
//! table says `challenge = 0` (the paper's GA): `[ga]` for the GA,
//! `[islands]` and `[hybrid]` for theirs, `[tandem]` for the tandem's.

use std::collections::BTreeMap;

use toml::Spanned;

use super::Ctx;
use crate::experiment::file::{
    BudgetFile, DelayedRejectionFile, EdgeMatchFile, ExperimentFile, FirstPhaseFile, GaFile,
    RjmcmcFile, SmcFile, TopologyFile,
};
use crate::experiment::{ExperimentError, Method, MethodConfig, MethodParams};
use crate::ops::{CrossoverConfig, EdgeMatch, InitLength, MutationSplit};
use crate::optimize::{
    Budget, DEFAULT_CHALLENGE, DelayedRejection, GaParams, HYBRID_PATIENCE_SHARE, HybridParams,
    IslandParams, RjmcmcParams, SmcParams, TANDEM_INTERVAL, TANDEM_MIGRANTS, TandemParams,
    Topology,
};

/// The largest population, particle or chain count (each individual keeps a
/// chromosome; 10⁶ of them is already gigabytes).
const MAX_INDIVIDUALS: usize = 1_000_000;

/// Problems of sizes the optimizers' own checks do not cover.
fn size_problems(count: (&str, usize), init_length: Option<u32>) -> Vec<String> {
    let mut p = Vec::new();
    if count.1 > MAX_INDIVIDUALS {
        p.push(format!(
            "{} must be at most {MAX_INDIVIDUALS}, got {}",
            count.0, count.1
        ));
    }
    if init_length == Some(0) {
        p.push("init_length must be at least 1 (initial lengths are drawn around it)".into());
    }
    p
}

/// SMC and SOSMC particles without a table (the paper's spaceship).
const PAPER_PARTICLES: usize = 500;
/// RJMCMC chains and initial length without a table (the paper's spaceship).
const PAPER_CHAINS: usize = 70;
const PAPER_RJMCMC_LENGTH: u32 = 50;

/// Every method's configuration.
pub(super) fn from_file(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
) -> Result<BTreeMap<Method, MethodConfig>, ExperimentError> {
    // In file order, so the first invalid table is the one reported; the
    // island GA and the hybrid build on the GA's and RJMCMC's settings.
    let ga = ga(ctx, f.ga.as_ref())?;
    let smc_config = smc(ctx, Method::Smc, f.smc.as_ref(), SmcParams::paper)?;
    let sosmc = smc(ctx, Method::Sosmc, f.sosmc.as_ref(), SmcParams::paper_sosmc)?;
    let rjmcmc = rjmcmc(ctx, f.rjmcmc.as_ref())?;
    Ok(BTreeMap::from([
        (Method::Ga, ga),
        (Method::Smc, smc_config),
        (Method::Sosmc, sosmc),
        (Method::Rjmcmc, rjmcmc),
        (Method::Islands, islands(ctx, f, ga)?),
        (
            Method::Hybrid,
            hybrid(ctx, f, ga, rjmcmc, [smc_config, sosmc])?,
        ),
        (
            Method::Tandem,
            tandem(ctx, f, ga, rjmcmc, [smc_config, sosmc])?,
        ),
    ]))
}

/// A `budget` table: at least one limit, seconds finite and positive.
pub(super) fn budget(
    ctx: &Ctx<'_>,
    key: &str,
    b: &Spanned<BudgetFile>,
) -> Result<Budget, ExperimentError> {
    let f = b.get_ref();
    let mut out = Budget::default();
    if let Some(s) = f.seconds {
        let Some(t) = Budget::seconds(s) else {
            return Err(ctx.err(
                key,
                b,
                format!(
                    "seconds must be > 0 and at most {:.0} (a century), got {s}",
                    Budget::MAX_SECONDS
                ),
            ));
        };
        out.wall_time = Some(t);
    }
    if f.generations == Some(0) {
        return Err(ctx.err(key, b, "generations must be at least 1"));
    }
    out.evaluations = f.evaluations;
    out.generations = f.generations;
    if out.is_unbounded() {
        return Err(ctx.err(key, b, "give seconds, evaluations or generations"));
    }
    Ok(out)
}

/// A method's parameters after its own checks, with its budget.
fn config(
    ctx: &Ctx<'_>,
    method: Method,
    table: &Spanned<impl Sized>,
    params: MethodParams,
    problems: Vec<String>,
    own_budget: Option<&Spanned<BudgetFile>>,
) -> Result<MethodConfig, ExperimentError> {
    if !problems.is_empty() {
        return Err(ctx.err(method.name(), table, problems.join("; ")));
    }
    let key = format!("{method}.budget");
    Ok(MethodConfig {
        params,
        budget: own_budget.map(|b| budget(ctx, &key, b)).transpose()?,
    })
}

fn ga(ctx: &Ctx<'_>, table: Option<&Spanned<GaFile>>) -> Result<MethodConfig, ExperimentError> {
    let preset = GaParams {
        challenge: DEFAULT_CHALLENGE,
        ..GaParams::paper_spaceship()
    };
    let Some(t) = table else {
        return Ok(MethodConfig {
            params: MethodParams::Ga(preset),
            budget: None,
        });
    };
    let g = t.get_ref();
    let params = GaParams {
        population: g.population,
        elites: g.elites,
        init: InitLength::Around { l0: g.init_length },
        mutation_rate: g.mutation_rate,
        mutation_split: MutationSplit::new(g.split.grow, g.split.cut, g.split.alter),
        tournament: g.tournament.unwrap_or(preset.tournament),
        crossover: CrossoverConfig {
            max_retries: g.max_retries.unwrap_or(preset.crossover.max_retries),
            edge_match: match g.crossover {
                None => preset.crossover.edge_match,
                Some(EdgeMatchFile::Strict) => EdgeMatch::Strict,
                Some(EdgeMatchFile::ChildType) => EdgeMatch::ChildType,
            },
        },
        elite_dedup: g.elite_dedup.unwrap_or(preset.elite_dedup),
        local_search: g.local_search.unwrap_or(preset.local_search),
        adaptive_split: g.adaptive_split.unwrap_or(preset.adaptive_split),
        challenge: g.challenge.unwrap_or(preset.challenge),
        ..preset
    };
    let mut problems = params.problems();
    problems.extend(size_problems(
        ("population", g.population),
        Some(g.init_length),
    ));
    if params.tournament > params.population {
        problems.push(format!(
            "tournament ({}) must not exceed the population ({})",
            params.tournament, params.population
        ));
    }
    config(
        ctx,
        Method::Ga,
        t,
        MethodParams::Ga(params),
        problems,
        g.budget.as_ref(),
    )
}

fn smc(
    ctx: &Ctx<'_>,
    method: Method,
    table: Option<&Spanned<SmcFile>>,
    preset: fn(usize) -> SmcParams,
) -> Result<MethodConfig, ExperimentError> {
    let Some(t) = table else {
        return Ok(MethodConfig {
            params: MethodParams::Smc(preset(PAPER_PARTICLES)),
            budget: None,
        });
    };
    let s = t.get_ref();
    let params = preset(s.particles);
    let mut problems = params.problems();
    problems.extend(size_problems(("particles", s.particles), None));
    config(
        ctx,
        method,
        t,
        MethodParams::Smc(params),
        problems,
        s.budget.as_ref(),
    )
}

fn rjmcmc(
    ctx: &Ctx<'_>,
    table: Option<&Spanned<RjmcmcFile>>,
) -> Result<MethodConfig, ExperimentError> {
    let Some(t) = table else {
        let init = InitLength::Around {
            l0: PAPER_RJMCMC_LENGTH,
        };
        return Ok(MethodConfig {
            params: MethodParams::Rjmcmc(RjmcmcParams::paper(PAPER_CHAINS, init)),
            budget: None,
        });
    };
    let r = t.get_ref();
    let mut params = RjmcmcParams::paper(r.chains, InitLength::Around { l0: r.init_length });
    if let Some(p) = r.jump_probability {
        params.jump_probability = p;
    }
    if let Some(a) = r.annealing {
        params.annealing = (a != 1.0).then_some(a);
    }
    if let Some(d) = r.delayed_rejection {
        params.delayed_rejection = match d {
            DelayedRejectionFile::Off => DelayedRejection::Off,
            DelayedRejectionFile::Exact => DelayedRejection::Exact,
            DelayedRejectionFile::ApproxAlter => DelayedRejection::ApproxAlter,
        };
    }
    let mut problems = params.problems();
    problems.extend(size_problems(("chains", r.chains), Some(r.init_length)));
    config(
        ctx,
        Method::Rjmcmc,
        t,
        MethodParams::Rjmcmc(params),
        problems,
        r.budget.as_ref(),
    )
}

/// The island GA: the `[ga]` population (`ga`) split across `islands` (default 4).
fn islands(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    ga: MethodConfig,
) -> Result<MethodConfig, ExperimentError> {
    let MethodParams::Ga(ga_params) = ga.params else {
        unreachable!("the GA's configuration holds GA parameters")
    };
    // Islands start challengers whatever the GA does (the paper's
    // experiments turn the GA's off): a quarter of the population
    // collapses where the whole does not.
    let challenge = f
        .islands
        .as_ref()
        .and_then(|t| t.get_ref().challenge)
        .unwrap_or(DEFAULT_CHALLENGE);
    let ga_params = GaParams {
        challenge,
        ..ga_params
    };
    let preset = IslandParams::split(ga_params);
    let Some(t) = f.islands.as_ref() else {
        return Ok(MethodConfig {
            params: MethodParams::Islands(preset),
            budget: ga.budget,
        });
    };
    let i = t.get_ref();
    let count = i.islands.unwrap_or(preset.islands);
    let mut params = IslandParams::split_into(ga_params, count);
    params.interval = i.interval.unwrap_or(preset.interval);
    params.migrants = i.migrants.unwrap_or(preset.migrants);
    params.topology = match i.topology {
        None => preset.topology,
        Some(TopologyFile::Ring) => Topology::Ring,
        Some(TopologyFile::Random) => Topology::Random,
    };
    let mut problems = params.problems();
    if count == 0 {
        problems.push("islands must be at least 1".into());
    } else if ga_params.population / count < 2 {
        problems.push(format!(
            "{count} islands leave fewer than 2 of the GA's {} individuals per island",
            ga_params.population
        ));
    }
    let mut config = config(
        ctx,
        Method::Islands,
        t,
        MethodParams::Islands(params),
        problems,
        i.budget.as_ref(),
    )?;
    config.budget = config.budget.or(ga.budget);
    Ok(config)
}

/// Generations without a gain before the hybrid switches, without `[hybrid]`.
const HYBRID_PATIENCE: u64 = 100;

/// The hybrid: the `[ga]` settings (`ga`), then the `[rjmcmc]` ones (`rjmcmc`).
fn hybrid(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    ga: MethodConfig,
    rjmcmc: MethodConfig,
    smc_configs: [MethodConfig; 2],
) -> Result<MethodConfig, ExperimentError> {
    let (MethodParams::Ga(ga_params), MethodParams::Rjmcmc(rjmcmc)) = (ga.params, rjmcmc.params)
    else {
        unreachable!("the GA's and RJMCMC's configurations hold their parameters")
    };
    let challenge = f
        .hybrid
        .as_ref()
        .and_then(|t| t.get_ref().challenge)
        .unwrap_or(DEFAULT_CHALLENGE);
    let mut params = HybridParams {
        ga: GaParams {
            challenge,
            ..ga_params
        },
        rjmcmc,
        patience: HYBRID_PATIENCE,
        patience_share: HYBRID_PATIENCE_SHARE,
        first_phase: None,
    };
    let Some(t) = f.hybrid.as_ref() else {
        return Ok(MethodConfig {
            params: MethodParams::Hybrid(params),
            budget: ga.budget,
        });
    };
    let h = t.get_ref();
    params.patience = h.patience.unwrap_or(HYBRID_PATIENCE);
    params.patience_share = h.patience_share.unwrap_or(HYBRID_PATIENCE_SHARE);
    params.first_phase = first_phase(h.first_phase, smc_configs);
    let problems = params.problems();
    let mut config = config(
        ctx,
        Method::Hybrid,
        t,
        MethodParams::Hybrid(params),
        problems,
        h.budget.as_ref(),
    )?;
    config.budget = config.budget.or(ga.budget);
    Ok(config)
}

/// The tandem: the experiment's GA and RJMCMC side by side, as
/// [`TandemParams::recommended`] sets them (the GA with local search and
/// elite deduplication) unless `[tandem]` says otherwise; the GA's budget
/// unless `[tandem]` has its own.
fn tandem(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    ga: MethodConfig,
    rjmcmc: MethodConfig,
    smc_configs: [MethodConfig; 2],
) -> Result<MethodConfig, ExperimentError> {
    let (MethodParams::Ga(ga_params), MethodParams::Rjmcmc(rjmcmc)) = (ga.params, rjmcmc.params)
    else {
        unreachable!("the GA's and RJMCMC's configurations hold their parameters")
    };
    let mut params = TandemParams::recommended(ga_params, rjmcmc);
    let Some(t) = f.tandem.as_ref() else {
        return Ok(MethodConfig {
            params: MethodParams::Tandem(params),
            budget: ga.budget,
        });
    };
    let table = t.get_ref();
    params.interval = table.interval.unwrap_or(TANDEM_INTERVAL);
    params.migrants = table.migrants.unwrap_or(TANDEM_MIGRANTS);
    params.ga.local_search = table.local_search.unwrap_or(params.ga.local_search);
    params.ga.elite_dedup = table.elite_dedup.unwrap_or(params.ga.elite_dedup);
    params.ga.adaptive_split = table.adaptive_split.unwrap_or(params.ga.adaptive_split);
    params.first_phase = first_phase(table.first_phase, smc_configs);
    params.balance = table.balance.unwrap_or(params.balance);
    params.to_chains = table.to_chains.unwrap_or(params.to_chains);
    params.challenge = table.challenge.unwrap_or(params.challenge);
    let problems = params.problems();
    let mut config = config(
        ctx,
        Method::Tandem,
        t,
        MethodParams::Tandem(params),
        problems,
        table.budget.as_ref(),
    )?;
    config.budget = config.budget.or(ga.budget);
    Ok(config)
}

/// The first phase `[hybrid]` or `[tandem]` asks for: the `[smc]` or
/// `[sosmc]` settings of `smc_configs` (in that order), or none.
fn first_phase(
    choice: Option<FirstPhaseFile>,
    smc_configs: [MethodConfig; 2],
) -> Option<SmcParams> {
    let [smc, sosmc] = smc_configs.map(|c| match c.params {
        MethodParams::Smc(p) => p,
        _ => unreachable!("the SMC and SOSMC configurations hold their parameters"),
    });
    match choice {
        None | Some(FirstPhaseFile::None) => None,
        Some(FirstPhaseFile::Smc) => Some(smc),
        Some(FirstPhaseFile::Sosmc) => Some(sosmc),
    }
}
