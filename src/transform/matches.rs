//! Semantic matches between two generators' nodes (thesis §5.4.1) and the
//! timeline of each (§5.5.2).

use std::collections::HashMap;

use crate::graph::{Graph, NodeId};

use super::TransformError;

/// When a match's blend happens on the global timeline `t ∈ [0, 1]`.
///
/// Its weight is `clamp((t − start) / (end − start), 0, 1)`; `start = end`
/// is a rule switch at `start`. Discrete decisions (which design's asset a
/// blended shape shows, and in the thesis's mode which unpaired shapes
/// exist) change at `threshold`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Timeline {
    /// When the blend starts (default 0).
    pub start: f32,
    /// When it ends (default 1).
    pub end: f32,
    /// When discrete decisions switch from the first design to the second (default ½).
    pub threshold: f32,
}

impl Default for Timeline {
    fn default() -> Self {
        Self {
            start: 0.0,
            end: 1.0,
            threshold: 0.5,
        }
    }
}

impl Timeline {
    /// The blend weight at time `t`: 0 is the first design, 1 the second.
    #[must_use]
    pub fn weight(&self, t: f32) -> f32 {
        if self.end <= self.start {
            if t >= self.start { 1.0 } else { 0.0 }
        } else {
            ((t - self.start) / (self.end - self.start)).clamp(0.0, 1.0)
        }
    }

    /// Whether discrete decisions follow the second design at time `t`.
    #[must_use]
    pub fn switched(&self, t: f32) -> bool {
        t >= self.threshold
    }

    /// [`problem`](Self::problem) as the error of the match of `a` with `b`.
    fn check(&self, a: &str, b: &str) -> Result<(), TransformError> {
        match self.problem() {
            None => Ok(()),
            Some(reason) => Err(TransformError::Timeline {
                a: a.to_string(),
                b: b.to_string(),
                reason,
            }),
        }
    }

    /// Why the times are not usable, if they are not: each in `[0, 1]`, `start ≤ end`.
    #[must_use]
    pub fn problem(&self) -> Option<&'static str> {
        let times = [self.start, self.end, self.threshold];
        if times.iter().any(|t| !(0.0..=1.0).contains(t)) {
            Some("start, end and threshold are times in [0, 1]")
        } else if self.start > self.end {
            Some("start comes after end")
        } else {
            None
        }
    }
}

/// The semantic matches of two designs: pairs of nodes (one of the first
/// generator, one of the second) that correspond, each with its timeline.
///
/// Built from tags ([`Matches::from_tags`]): nodes sharing a tag match, and
/// the two start nodes always match. One node may match several.
#[derive(Clone, Debug, PartialEq)]
pub struct Matches {
    pairs: Vec<(NodeId, NodeId)>,
    timelines: Vec<Timeline>,
    index: HashMap<(NodeId, NodeId), usize>,
    matched_a: Vec<bool>,
    matched_b: Vec<bool>,
}

impl Matches {
    /// The start nodes, then every pair of nodes that share a tag (in node order).
    #[must_use]
    pub fn from_tags(a: &Graph, b: &Graph) -> Self {
        let mut m = Self {
            pairs: Vec::new(),
            timelines: Vec::new(),
            index: HashMap::new(),
            matched_a: vec![false; a.node_count()],
            matched_b: vec![false; b.node_count()],
        };
        m.insert(a.start(), b.start());
        for i in 0..a.node_count() as NodeId {
            for j in 0..b.node_count() as NodeId {
                let shared = a
                    .node(i)
                    .tags
                    .iter()
                    .any(|t| b.node(j).tags.iter().any(|u| u == t));
                if shared {
                    m.insert(i, j);
                }
            }
        }
        m
    }

    fn insert(&mut self, a: NodeId, b: NodeId) {
        if self.index.contains_key(&(a, b)) {
            return;
        }
        self.index.insert((a, b), self.pairs.len());
        self.pairs.push((a, b));
        self.timelines.push(Timeline::default());
        self.matched_a[a as usize] = true;
        self.matched_b[b as usize] = true;
    }

    fn rebuild(&mut self) {
        self.index = self
            .pairs
            .iter()
            .enumerate()
            .map(|(i, &p)| (p, i))
            .collect();
        self.matched_a.fill(false);
        self.matched_b.fill(false);
        for &(a, b) in &self.pairs {
            self.matched_a[a as usize] = true;
            self.matched_b[b as usize] = true;
        }
    }

    /// Which match the first generator's node `a` and the second's `b` form.
    fn named(&self, ga: &Graph, gb: &Graph, a: &str, b: &str) -> Result<usize, TransformError> {
        let (i, j) = (node(ga, a, "first")?, node(gb, b, "second")?);
        self.of(i, j).ok_or_else(|| TransformError::NotAMatch {
            a: a.to_string(),
            b: b.to_string(),
        })
    }

    /// Adds the match of node `a` (first generator) with node `b` (second).
    pub(crate) fn add(
        &mut self,
        ga: &Graph,
        gb: &Graph,
        a: &str,
        b: &str,
    ) -> Result<(), TransformError> {
        let (i, j) = (node(ga, a, "first")?, node(gb, b, "second")?);
        self.insert(i, j);
        Ok(())
    }

    /// Removes the match of node `a` with node `b` (the start nodes' match stays).
    pub(crate) fn remove(
        &mut self,
        ga: &Graph,
        gb: &Graph,
        a: &str,
        b: &str,
    ) -> Result<(), TransformError> {
        let k = self.named(ga, gb, a, b)?;
        if k == 0 {
            return Err(TransformError::StartMatch);
        }
        self.pairs.remove(k);
        self.timelines.remove(k);
        self.rebuild();
        Ok(())
    }

    /// Sets the timeline of the match of `a` with `b`.
    pub(crate) fn set_timeline(
        &mut self,
        ga: &Graph,
        gb: &Graph,
        a: &str,
        b: &str,
        timeline: Timeline,
    ) -> Result<(), TransformError> {
        timeline.check(a, b)?;
        let k = self.named(ga, gb, a, b)?;
        self.timelines[k] = timeline;
        Ok(())
    }

    /// Sets every match's timeline.
    pub(crate) fn set_all_timelines(&mut self, timeline: Timeline) -> Result<(), TransformError> {
        timeline.check("*", "*")?;
        self.timelines.fill(timeline);
        Ok(())
    }

    /// The matched node pairs, the start nodes' first.
    #[must_use]
    pub fn pairs(&self) -> &[(NodeId, NodeId)] {
        &self.pairs
    }

    /// The timeline of each pair, in [`pairs`](Self::pairs) order.
    #[must_use]
    pub fn timelines(&self) -> &[Timeline] {
        &self.timelines
    }

    /// Which match (an index into [`pairs`](Self::pairs)) `a` and `b` form, if any.
    #[must_use]
    pub fn of(&self, a: NodeId, b: NodeId) -> Option<usize> {
        self.index.get(&(a, b)).copied()
    }

    /// Whether node `a` of the first generator matches any node.
    #[must_use]
    pub fn matched_a(&self, a: NodeId) -> bool {
        self.matched_a[a as usize]
    }

    /// Whether node `b` of the second generator matches any node.
    #[must_use]
    pub fn matched_b(&self, b: NodeId) -> bool {
        self.matched_b[b as usize]
    }
}

fn node(g: &Graph, name: &str, which: &'static str) -> Result<NodeId, TransformError> {
    g.node_id(name).ok_or_else(|| TransformError::UnknownNode {
        which,
        node: name.to_string(),
        known: (0..g.node_count() as NodeId)
            .map(|i| g.node(i).name.to_string())
            .collect::<Vec<_>>()
            .join(", "),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_follow_the_timeline() {
        let t = Timeline {
            start: 0.2,
            end: 0.6,
            threshold: 0.5,
        };
        assert_eq!(t.weight(0.0), 0.0);
        assert!((t.weight(0.4) - 0.5).abs() < 1e-6);
        assert_eq!(t.weight(0.9), 1.0);
        let switch = Timeline {
            start: 0.3,
            end: 0.3,
            threshold: 0.3,
        };
        assert_eq!(switch.weight(0.29), 0.0);
        assert_eq!(switch.weight(0.3), 1.0);
        assert!(
            Timeline {
                start: 0.7,
                end: 0.2,
                threshold: 0.5
            }
            .problem()
            .is_some()
        );
    }
}
