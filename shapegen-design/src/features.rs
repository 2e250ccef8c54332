//! Φ(m): a model's feature vector, read off its derivation tree (thesis §4.4.1).
//!
//! Three kinds of features, all from the chromosome alone (no geometry):
//!
//! - **Parameters**: for every numeric parameter component of every node, the
//!   mean value over the genes of that node at each *recursion level* (how
//!   many ancestors are of the same node), levels beyond
//!   [`FeatureOptions::recursion_levels`] merged into the last; scaled to
//!   `[0, 1]` by the parameter's support (0 where no such gene exists).
//! - **Counts**: the number of genes of each node, and the number of genes
//!   of each node that took each option of each of its choices (in a
//!   grammar: how often each rule was applied).
//! - **Paths**: the number of occurrences of each path down the derivation
//!   tree, of *effective length* 1..=k. A path is a chain of genes linked by
//!   slots, where each gene is either bare (its node) or annotated with the
//!   option of one of its choices. Its effective length counts the
//!   stochastic steps: each annotation (a choice with more than one
//!   possible option) and each slot with `0 < p < 1`; slots of `p = 1` cost
//!   nothing (the thesis's non-informative rules), though they still tell
//!   where a path starts (`Stack.bottom>…` against `Stack.top>…`). A path
//!   ends on a stochastic step; one ending in a free step would only repeat
//!   the count of the path before it.
//!   So with `k = 1`, "the bottom mass is brown" and "a branch grows on the
//!   trunk's first slot" are features; with `k = 2`, "the bottom mass is a
//!   brown box".
//!
//! The path vocabulary is that of the models a [`FeatureSpace`] is fitted on
//! (paths never seen there are not features). Every feature is divided by its
//! largest magnitude over those models, so all lie in about `[0, 1]`.

use crate::DesignError;
use std::collections::HashMap;

use serde::{Deserialize, Serialize};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::{Dist, Graph, IntDist, NodeId, ParamDist};

/// How features are read from a derivation tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FeatureOptions {
    /// The longest effective path length `k` (at least 1).
    pub path_length: u32,
    /// Recursion levels kept apart for parameter features (at least 1).
    pub recursion_levels: u32,
}

impl Default for FeatureOptions {
    /// `k = 1` (the thesis starts there) and three recursion levels.
    fn default() -> Self {
        Self {
            path_length: 1,
            recursion_levels: 3,
        }
    }
}

/// What one feature measures.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeatureKey {
    /// Mean of a parameter component over the node's genes at one recursion level.
    Param {
        /// The node.
        node: NodeId,
        /// The parameter's index in the node.
        param: u16,
        /// The component (0 for scalars).
        component: u8,
        /// The recursion level.
        level: u8,
    },
    /// Number of genes of a node.
    Count {
        /// The node.
        node: NodeId,
    },
    /// Number of genes of a node whose choice parameter `param` took `value`.
    Choice {
        /// The node.
        node: NodeId,
        /// The choice parameter's index in the node.
        param: u16,
        /// The option.
        value: u32,
    },
    /// Number of occurrences of a path: genes (each `[node, param, value]`,
    /// `param = u32::MAX` for a bare gene) separated by slot indices,
    /// `[gene₀ (3), slot₀, gene₁ (3), slot₁, …, geneₖ (3)]`.
    Path(Vec<u32>),
}

impl FeatureKey {
    /// The nodes this feature is about (for choosing which nodes to split).
    #[must_use]
    pub fn nodes(&self) -> Vec<NodeId> {
        match self {
            Self::Param { node, .. } | Self::Count { node } => vec![*node],
            Self::Choice { node, .. } => vec![*node],
            Self::Path(p) => p.chunks(4).map(|c| c[0] as NodeId).collect(),
        }
    }

    /// Whether the key can name features of `graph`: its nodes, parameters,
    /// components and slots exist (a key read from a file is checked so
    /// before [`describe`](Self::describe) or a model meets it).
    pub fn check(&self, graph: &Graph) -> Result<(), String> {
        let spec = |node: u32| {
            if (node as usize) < graph.node_count() {
                Ok(graph.node(node as NodeId))
            } else {
                Err(format!(
                    "feature {self:?} names node {node}; the generator has {}",
                    graph.node_count()
                ))
            }
        };
        let param = |node: u32, param: u32| -> Result<&ParamDist, String> {
            spec(node)?
                .params
                .get(param as usize)
                .map(|p| &p.dist)
                .ok_or_else(|| {
                    format!("feature {self:?} names a parameter node {node} does not have")
                })
        };
        match self {
            Self::Count { node } => spec(u32::from(*node)).map(|_| ()),
            Self::Param {
                node,
                param: p,
                component,
                ..
            } => {
                let dims = match param(u32::from(*node), u32::from(*p))? {
                    ParamDist::Vec2(_) => 2,
                    ParamDist::Vec3(_) => 3,
                    _ => 1,
                };
                if *component >= dims {
                    return Err(format!(
                        "feature {self:?} names component {component} of a parameter of {dims}"
                    ));
                }
                Ok(())
            }
            Self::Choice { node, param: p, .. } => match param(u32::from(*node), u32::from(*p))? {
                ParamDist::Choice(_) => Ok(()),
                _ => Err(format!(
                    "feature {self:?} counts options of a parameter that is no choice"
                )),
            },
            Self::Path(path) => {
                if path.len() % 4 != 3 {
                    return Err(format!(
                        "feature {self:?}: a path is genes of 3 numbers joined by slots"
                    ));
                }
                for c in path.chunks(4) {
                    let node = spec(c[0])?;
                    if c[1] != u32::MAX {
                        param(c[0], c[1])?;
                    }
                    if let Some(&slot) = c.get(3)
                        && slot as usize >= node.slots.len()
                    {
                        return Err(format!(
                            "feature {self:?} names slot {slot} of `{}`, which has {}",
                            node.name,
                            node.slots.len()
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// A readable name, e.g. `Mass.h[0]`, `#Mass`, `#Mass(colour=0)`,
    /// `Stack.bottom>Mass(colour=0)`.
    #[must_use]
    pub fn describe(&self, graph: &Graph) -> String {
        let gene = |node: u32, param: u32, value: u32| -> String {
            let spec = graph.node(node as NodeId);
            match spec.params.get(param as usize) {
                Some(p) => format!("{}({}={value})", spec.name, p.name),
                None => spec.name.to_string(),
            }
        };
        match self {
            Self::Param {
                node,
                param,
                component,
                level,
            } => {
                let spec = graph.node(*node);
                let name = &spec.params[*param as usize].name;
                let comp = match spec.params[*param as usize].dist {
                    ParamDist::Vec2(_) | ParamDist::Vec3(_) => {
                        format!(".{}", ["x", "y", "z"][*component as usize])
                    }
                    _ => String::new(),
                };
                format!("{}.{name}{comp}[{level}]", spec.name)
            }
            Self::Count { node } => format!("#{}", graph.node(*node).name),
            Self::Choice { node, param, value } => {
                format!("#{}", gene(u32::from(*node), u32::from(*param), *value))
            }
            Self::Path(p) => {
                let mut out = String::new();
                for (i, c) in p.chunks(4).enumerate() {
                    if i > 0 {
                        out += ">";
                    }
                    out += &gene(c[0], c[1], c[2]);
                    if let Some(&slot) = c.get(3) {
                        out +=
                            &format!(".{}", graph.node(c[0] as NodeId).slots[slot as usize].name);
                    }
                }
                out
            }
        }
    }
}

/// Whether parameter `param` of `node` is a choice with more than one possible option.
fn stochastic_choice(graph: &Graph, node: NodeId, param: usize) -> bool {
    match &graph.node(node).params[param].dist {
        ParamDist::Choice(w) => w.iter().filter(|&&x| x > 0.0).count() > 1,
        _ => false,
    }
}

/// A fitted feature map: the vocabulary and scales learned from a set of models.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(try_from = "StoredSpace", into = "StoredSpace")]
pub struct FeatureSpace {
    options: FeatureOptions,
    keys: Vec<FeatureKey>,
    scale: Vec<f64>,
    index: HashMap<FeatureKey, usize>,
}

/// A [`FeatureSpace`] as stored: without its lookup index.
#[derive(Clone, Serialize, Deserialize)]
struct StoredSpace {
    options: FeatureOptions,
    keys: Vec<FeatureKey>,
    scale: Vec<f64>,
}

impl TryFrom<StoredSpace> for FeatureSpace {
    type Error = DesignError;

    /// Refuses a (hand-edited) space whose scales are not one positive
    /// number per key, or whose keys repeat.
    fn try_from(s: StoredSpace) -> Result<Self, DesignError> {
        if s.keys.len() != s.scale.len() {
            return Err(DesignError::Mismatch {
                what: "a feature space's keys and scales",
                left: s.keys.len(),
                right: s.scale.len(),
            });
        }
        if let Some(bad) = s.scale.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return Err(DesignError::Invalid(format!(
                "a feature's scale is {bad}, not a positive number"
            )));
        }
        let index = index_of(&s.keys);
        if index.len() != s.keys.len() {
            return Err(DesignError::Invalid(
                "a feature space names a feature twice".into(),
            ));
        }
        Ok(Self {
            index,
            options: s.options,
            keys: s.keys,
            scale: s.scale,
        })
    }
}

/// Each key's position.
fn index_of(keys: &[FeatureKey]) -> HashMap<FeatureKey, usize> {
    keys.iter()
        .cloned()
        .enumerate()
        .map(|(i, k)| (k, i))
        .collect()
}

impl From<FeatureSpace> for StoredSpace {
    fn from(s: FeatureSpace) -> Self {
        Self {
            options: s.options,
            keys: s.keys,
            scale: s.scale,
        }
    }
}

impl FeatureSpace {
    /// The features of `models` (all of `graph`): every parameter and count
    /// feature of the graph, and every path seen in them.
    #[must_use]
    pub fn fit(graph: &Graph, models: &[Chromosome], options: FeatureOptions) -> Self {
        let raw: Vec<HashMap<FeatureKey, f64>> = models
            .iter()
            .map(|m| raw_features(graph, m, options))
            .collect();
        let mut keys: Vec<FeatureKey> = Vec::new();
        // Parameter and count features: fixed by the graph, in node order.
        for node in 0..graph.node_count() as NodeId {
            keys.push(FeatureKey::Count { node });
            for (param, p) in graph.node(node).params.iter().enumerate() {
                let components = match p.dist {
                    ParamDist::F32(d) => usize::from(is_random(&d)),
                    ParamDist::Vec2(d) => d.iter().filter(|d| is_random(d)).count().min(1) * 2,
                    ParamDist::Vec3(d) => d.iter().filter(|d| is_random(d)).count().min(1) * 3,
                    ParamDist::Int(IntDist::Uniform { lo, hi }) if lo < hi => 1,
                    _ => 0,
                };
                for component in 0..components {
                    for level in 0..options.recursion_levels.max(1) {
                        keys.push(FeatureKey::Param {
                            node,
                            param: param as u16,
                            component: component as u8,
                            level: level as u8,
                        });
                    }
                }
            }
        }
        let mut seen: Vec<FeatureKey> = raw
            .iter()
            .flat_map(|r| r.keys())
            .filter(|k| matches!(k, FeatureKey::Choice { .. } | FeatureKey::Path(_)))
            .cloned()
            .collect();
        seen.sort_by(|a, b| format!("{a:?}").cmp(&format!("{b:?}")));
        seen.dedup();
        keys.extend(seen);
        let index = index_of(&keys);
        let mut scale = vec![0.0f64; keys.len()];
        for r in &raw {
            for (k, v) in r {
                if let Some(&i) = index.get(k) {
                    scale[i] = scale[i].max(v.abs());
                }
            }
        }
        // Features that are 0 on every model (a recursion level never
        // reached, a node never derived) cannot tell models apart: dropped.
        let kept: Vec<usize> = (0..keys.len()).filter(|&i| scale[i] > 0.0).collect();
        let keys: Vec<FeatureKey> = kept.iter().map(|&i| keys[i].clone()).collect();
        Self {
            index: index_of(&keys),
            options,
            keys,
            scale: kept.iter().map(|&i| scale[i]).collect(),
        }
    }

    /// The options it was fitted with.
    #[must_use]
    pub fn options(&self) -> FeatureOptions {
        self.options
    }

    /// The features, in vector order.
    #[must_use]
    pub fn keys(&self) -> &[FeatureKey] {
        &self.keys
    }

    /// Number of features `D`.
    #[must_use]
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Whether there are no features.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Φ(m), scaled.
    #[must_use]
    pub fn features(&self, graph: &Graph, model: &Chromosome) -> Vec<f64> {
        let mut x = vec![0.0; self.keys.len()];
        for (k, v) in raw_features(graph, model, self.options) {
            if let Some(&i) = self.index.get(&k) {
                x[i] = v / self.scale[i];
            }
        }
        x
    }
}

fn is_random(d: &Dist) -> bool {
    match *d {
        Dist::Constant { .. } => false,
        Dist::Uniform { lo, hi } => lo < hi,
        _ => true,
    }
}

/// A numeric parameter component's value mapped to about `[0, 1]` by its support.
fn unit(d: &Dist, x: f32) -> f64 {
    let x = f64::from(x);
    match *d {
        Dist::Uniform { lo, hi } | Dist::TruncatedNormal { lo, hi, .. } if lo < hi => {
            (x - f64::from(lo)) / (f64::from(hi) - f64::from(lo))
        }
        Dist::Normal { mean, std } => 0.5 + (x - f64::from(mean)) / (4.0 * f64::from(std)),
        _ => 0.0,
    }
}

/// The unscaled features of one model (only non-zero ones).
fn raw_features(
    graph: &Graph,
    m: &Chromosome,
    options: FeatureOptions,
) -> HashMap<FeatureKey, f64> {
    let mut out: HashMap<FeatureKey, f64> = HashMap::new();
    let n = m.len();
    let positions = m.positions();
    let at = |pos: u32| positions.partition_point(|&x| x < pos);
    let mut node_of: Vec<NodeId> = Vec::with_capacity(n);
    let mut parent: Vec<Option<usize>> = Vec::with_capacity(n);
    let mut slot: Vec<u32> = Vec::with_capacity(n);
    let mut level: Vec<u32> = Vec::with_capacity(n);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    // Per gene, its variants: bare, then one per stochastic choice ([node, param, value]).
    let mut variants: Vec<Vec<[u32; 3]>> = Vec::with_capacity(n);
    // Sums and counts of parameter components.
    let mut sums: HashMap<FeatureKey, (f64, f64)> = HashMap::new();
    let levels = options.recursion_levels.max(1);
    for (i, g) in m.genes(graph).enumerate() {
        let node = g.node();
        let spec = graph.node(node);
        let p = g.parent().map(at);
        // Recursion level: one more than the nearest ancestor of the same node's.
        let mut lv = 0;
        let mut up = p;
        while let Some(a) = up {
            if node_of[a] == node {
                lv = level[a] + 1;
                break;
            }
            up = parent[a];
        }
        if let Some(a) = p {
            children[a].push(i);
        }
        *out.entry(FeatureKey::Count { node }).or_default() += 1.0;
        let mut vs = vec![[u32::from(node), u32::MAX, 0]];
        let lvl = lv.min(levels - 1) as u8;
        for (k, ps) in spec.params.iter().enumerate() {
            let comps: Vec<(u8, f64)> = match &ps.dist {
                ParamDist::F32(d) => vec![(0, unit(d, g.param_f32(k)))],
                ParamDist::Vec2(d) => {
                    let v = g.param_vec2(k);
                    (0..2).map(|c| (c as u8, unit(&d[c], v[c]))).collect()
                }
                ParamDist::Vec3(d) => {
                    let v = g.param_vec3(k);
                    (0..3).map(|c| (c as u8, unit(&d[c], v[c]))).collect()
                }
                ParamDist::Int(IntDist::Uniform { lo, hi }) if lo < hi => vec![(
                    0,
                    (f64::from(g.param_int(k)) - f64::from(*lo))
                        / (f64::from(*hi) - f64::from(*lo)),
                )],
                ParamDist::Choice(_) => {
                    if stochastic_choice(graph, node, k) {
                        let value = g.param_choice(k);
                        *out.entry(FeatureKey::Choice {
                            node,
                            param: k as u16,
                            value,
                        })
                        .or_default() += 1.0;
                        vs.push([u32::from(node), k as u32, value]);
                    }
                    vec![]
                }
                ParamDist::Int(_) => vec![],
            };
            for (c, v) in comps {
                let e = sums
                    .entry(FeatureKey::Param {
                        node,
                        param: k as u16,
                        component: c,
                        level: lvl,
                    })
                    .or_default();
                e.0 += v;
                e.1 += 1.0;
            }
        }
        node_of.push(node);
        parent.push(p);
        slot.push(g.slot_in_parent());
        level.push(lv);
        variants.push(vs);
    }
    for (k, (s, c)) in sums {
        out.insert(k, s / c);
    }
    // Paths. A slot step is stochastic if 0 < p < 1; an annotated gene is one step.
    let slot_cost = |child: usize| -> u32 {
        let a = parent[child].expect("a child has a parent");
        let p = graph.node(node_of[a]).slots[slot[child] as usize].p;
        u32::from(p > 0.0 && p < 1.0)
    };
    let annotated = |v: &[u32; 3]| u32::from(v[1] != u32::MAX);
    let k = options.path_length.max(1);
    // Raw length cap: chains of free steps cannot make paths unbounded.
    let max_raw = 4 * k as usize + 4;
    // (gene, path so far, effective length, genes on the path).
    let mut stack: Vec<(usize, Vec<u32>, u32, usize)> = Vec::new();
    for start in 0..n {
        for v in &variants[start] {
            stack.push((start, v.to_vec(), annotated(v), 1));
        }
        while let Some((g, path, eff, genes)) = stack.pop() {
            if genes >= max_raw {
                continue;
            }
            for &c in &children[g] {
                let step = slot_cost(c);
                for v in &variants[c] {
                    let e = eff + step + annotated(v);
                    if e > k {
                        continue;
                    }
                    let mut p = path.clone();
                    p.push(slot[c]);
                    p.extend_from_slice(v);
                    // A path ending in a free step to a bare gene only
                    // repeats the count of the path before that step.
                    if annotated(v) == 1 || step == 1 {
                        *out.entry(FeatureKey::Path(p.clone())).or_default() += 1.0;
                    }
                    stack.push((c, p, e, genes + 1));
                }
            }
        }
    }
    out
}
