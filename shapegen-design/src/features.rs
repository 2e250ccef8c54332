//! Φ(m): a model's feature vector, read off its derivation tree (thesis §4.4.1).
//!
//! Three kinds of features, all from the chromosome alone (no geometry):
//!
//! - **Parameters**: for every numeric parameter component of every node, the
//!   mean value over the genes of that node at each *recursion level* (how
//!   many ancestors are of the same node), levels beyond
//!   [`FeatureOptions::recursion_levels`] merged into the last; scaled to
//!   `[0, 1]` by the parameter's support (0 where no such gene exists).
//! - **Counts**: the number of genes of each node, and of each *label*
//!   (a node together with the values of its choice parameters: in a
//!   grammar, which rule was applied) of nodes that have choices.
//! - **Paths**: the number of occurrences of each path of (label, slot) edges
//!   from a gene down to a descendant, of *effective length* 1..=k: an edge
//!   counts toward the length only if it carries a stochastic choice (its slot
//!   has `0 < p < 1`, or the child's node has a choice with more than one
//!   possible option). A path begins and ends on such an edge; the ones that
//!   do not would only repeat a shorter path's count.
//!
//! The path vocabulary is that of the models a [`FeatureSpace`] is fitted on
//! (paths never seen there are not features). Every feature is divided by its
//! largest magnitude over those models, so all lie in about `[0, 1]`.

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
    /// Number of genes with this label (node, then its choice values).
    Label(Vec<u32>),
    /// Number of occurrences of a path: labels separated by slot indices,
    /// `[label₀…, slot₀, label₁…, slot₁, …, labelₖ…]`.
    Path(Vec<u32>),
}

impl FeatureKey {
    /// The nodes this feature is about (for choosing which nodes to split).
    #[must_use]
    pub fn nodes(&self, graph: &Graph) -> Vec<NodeId> {
        match self {
            Self::Param { node, .. } | Self::Count { node } => vec![*node],
            Self::Label(l) => vec![l[0] as NodeId],
            Self::Path(p) => {
                let mut nodes = Vec::new();
                let mut i = 0;
                while i < p.len() {
                    let node = p[i] as NodeId;
                    nodes.push(node);
                    i += 1 + choice_params(graph, node).len() + 1;
                }
                nodes
            }
        }
    }

    /// A readable name, e.g. `Mass.h[0]`, `#Mass`, `Root.bottom>Mass(shape=1,colour=2)`.
    #[must_use]
    pub fn describe(&self, graph: &Graph) -> String {
        let label = |l: &[u32]| -> (String, usize) {
            let node = l[0] as NodeId;
            let choices = choice_params(graph, node);
            let spec = graph.node(node);
            let mut s = spec.name.to_string();
            if !choices.is_empty() {
                let parts: Vec<String> = choices
                    .iter()
                    .zip(&l[1..])
                    .map(|(&k, v)| format!("{}={v}", spec.params[k].name))
                    .collect();
                s += &format!("({})", parts.join(","));
            }
            (s, 1 + choices.len())
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
                    ParamDist::Vec2(_) | ParamDist::Vec3(_) => format!(".{}", ["x", "y", "z"][*component as usize]),
                    _ => String::new(),
                };
                format!("{}.{name}{comp}[{level}]", spec.name)
            }
            Self::Count { node } => format!("#{}", graph.node(*node).name),
            Self::Label(l) => format!("#{}", label(l).0),
            Self::Path(p) => {
                let mut out = String::new();
                let mut i = 0;
                while i < p.len() {
                    let (s, used) = label(&p[i..]);
                    let node = p[i] as NodeId;
                    i += used;
                    out += &s;
                    if i < p.len() {
                        out += &format!(".{}>", graph.node(node).slots[p[i] as usize].name);
                        i += 1;
                    }
                }
                out
            }
        }
    }
}

/// The indices of a node's choice parameters.
pub(crate) fn choice_params(graph: &Graph, node: NodeId) -> Vec<usize> {
    graph
        .node(node)
        .params
        .iter()
        .enumerate()
        .filter(|(_, p)| matches!(p.dist, ParamDist::Choice(_)))
        .map(|(i, _)| i)
        .collect()
}

/// Whether a node has a choice with more than one possible option.
fn has_stochastic_choice(graph: &Graph, node: NodeId) -> bool {
    graph.node(node).params.iter().any(|p| match &p.dist {
        ParamDist::Choice(w) => w.iter().filter(|&&x| x > 0.0).count() > 1,
        _ => false,
    })
}

/// A fitted feature map: the vocabulary and scales learned from a set of models.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(from = "StoredSpace", into = "StoredSpace")]
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

impl From<StoredSpace> for FeatureSpace {
    fn from(s: StoredSpace) -> Self {
        let index = s.keys.iter().cloned().enumerate().map(|(i, k)| (k, i)).collect();
        Self {
            options: s.options,
            keys: s.keys,
            scale: s.scale,
            index,
        }
    }
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
            .filter(|k| matches!(k, FeatureKey::Label(_) | FeatureKey::Path(_)))
            .cloned()
            .collect();
        seen.sort_by(|a, b| format!("{a:?}").cmp(&format!("{b:?}")));
        seen.dedup();
        keys.extend(seen);
        let index: HashMap<FeatureKey, usize> =
            keys.iter().cloned().enumerate().map(|(i, k)| (k, i)).collect();
        let mut scale = vec![0.0f64; keys.len()];
        for r in &raw {
            for (k, v) in r {
                if let Some(&i) = index.get(k) {
                    scale[i] = scale[i].max(v.abs());
                }
            }
        }
        for s in &mut scale {
            if *s <= 0.0 {
                *s = 1.0;
            }
        }
        Self {
            options,
            keys,
            scale,
            index,
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
fn raw_features(graph: &Graph, m: &Chromosome, options: FeatureOptions) -> HashMap<FeatureKey, f64> {
    let mut out: HashMap<FeatureKey, f64> = HashMap::new();
    let n = m.len();
    let positions = m.positions();
    let at = |pos: u32| positions.partition_point(|&x| x < pos);
    // Per gene: its label, parent index, recursion level.
    let mut labels: Vec<Vec<u32>> = Vec::with_capacity(n);
    let mut parent: Vec<Option<usize>> = Vec::with_capacity(n);
    let mut slot: Vec<u32> = Vec::with_capacity(n);
    let mut level: Vec<u32> = Vec::with_capacity(n);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    // Sums and counts of parameter components per (key).
    let mut sums: HashMap<FeatureKey, (f64, f64)> = HashMap::new();
    let levels = options.recursion_levels.max(1);
    for (i, g) in m.genes(graph).enumerate() {
        let node = g.node();
        let spec = graph.node(node);
        let mut label = vec![u32::from(node)];
        for k in choice_params(graph, node) {
            label.push(g.param_choice(k));
        }
        let p = g.parent().map(at);
        // Recursion level: the parent's level for this node, plus one if the
        // parent is the same node; found by walking up to the nearest gene of
        // this node.
        let mut lv = 0;
        let mut up = p;
        while let Some(a) = up {
            if labels[a][0] == u32::from(node) {
                lv = level[a] + 1;
                break;
            }
            up = parent[a];
        }
        if let Some(a) = p {
            children[a].push(i);
        }
        *out.entry(FeatureKey::Count { node }).or_default() += 1.0;
        if label.len() > 1 {
            *out.entry(FeatureKey::Label(label.clone())).or_default() += 1.0;
        }
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
                    (f64::from(g.param_int(k)) - f64::from(*lo)) / (f64::from(*hi) - f64::from(*lo)),
                )],
                _ => vec![],
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
        labels.push(label);
        parent.push(p);
        slot.push(g.slot_in_parent());
        level.push(lv);
    }
    for (k, (s, c)) in sums {
        out.insert(k, s / c);
    }
    // Paths: from every gene, walk down; an edge is stochastic if its slot is
    // optional or its child has a choice.
    let stochastic = |child: usize| -> bool {
        let a = parent[child].expect("a child has a parent");
        let pn = labels[a][0] as NodeId;
        let p = graph.node(pn).slots[slot[child] as usize].p;
        (p > 0.0 && p < 1.0) || has_stochastic_choice(graph, labels[child][0] as NodeId)
    };
    let k = options.path_length.max(1);
    // Raw length cap: deterministic chains cannot make paths unbounded.
    let max_raw = 4 * k as usize + 4;
    let mut stack: Vec<(usize, Vec<u32>, u32, usize)> = Vec::new();
    for start in 0..n {
        for &c in &children[start] {
            if !stochastic(c) {
                continue;
            }
            let mut path = labels[start].clone();
            path.push(slot[c]);
            path.extend_from_slice(&labels[c]);
            stack.push((c, path, 1, 1));
        }
        while let Some((g, path, eff, raw)) = stack.pop() {
            *out.entry(FeatureKey::Path(path.clone())).or_default() += 1.0;
            if raw >= max_raw {
                continue;
            }
            // Extend through deterministic edges freely, and through
            // stochastic ones while the effective length allows.
            let mut frontier = vec![(g, Vec::<u32>::new(), 0usize)];
            while let Some((h, tail, depth)) = frontier.pop() {
                for &c in &children[h] {
                    let mut t = tail.clone();
                    t.push(slot[c]);
                    t.extend_from_slice(&labels[c]);
                    if stochastic(c) {
                        if eff < k {
                            let mut p = path.clone();
                            p.extend_from_slice(&t);
                            stack.push((c, p, eff + 1, raw + depth + 1));
                        }
                    } else if raw + depth + 1 < max_raw {
                        frontier.push((c, t, depth + 1));
                    }
                }
            }
        }
    }
    out
}
