//! Checking every invariant of a chromosome against its graph.

use super::Chromosome;
use super::word;
use crate::graph::Graph;

/// A broken invariant in a chromosome: it could not have been derived by its graph.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum GenomeError {
    /// The buffer holds no gene.
    #[error("the chromosome is empty (it must hold at least the root gene)")]
    Empty,
    /// A gene names a node the graph does not have.
    #[error("gene at word {pos} names node {node}, but the graph has {nodes} nodes")]
    UnknownNode {
        /// Gene position.
        pos: usize,
        /// The node id found.
        node: u16,
        /// Number of nodes in the graph.
        nodes: usize,
    },
    /// The buffer ends inside a gene.
    #[error("gene at word {pos} needs {needed} words but only {available} remain")]
    Truncated {
        /// Gene position.
        pos: usize,
        /// Words the gene needs.
        needed: usize,
        /// Words left in the buffer.
        available: usize,
    },
    /// A gene has flag bits set.
    #[error("gene at word {pos} has reserved flag bits set")]
    Flags {
        /// Gene position.
        pos: usize,
    },
    /// The first gene is not a root of the start node.
    #[error("the first gene must be a root gene of the start node `{start}`")]
    BadRoot {
        /// Name of the start node.
        start: String,
    },
    /// A gene's parent link does not point to an earlier gene.
    #[error("gene at word {pos} has a parent link that does not point to an earlier gene")]
    BadParent {
        /// Gene position.
        pos: usize,
    },
    /// A gene hangs from a slot its parent does not have.
    #[error(
        "gene at word {pos} hangs from slot {slot} of a `{parent}` gene, which has only {slots} slots"
    )]
    BadSlot {
        /// Gene position.
        pos: usize,
        /// The slot index stored in the gene.
        slot: u32,
        /// The parent's node name.
        parent: String,
        /// The parent's slot count.
        slots: usize,
    },
    /// Parent and child links disagree.
    #[error("links between the gene at word {pos} and its parent or children disagree")]
    BrokenLink {
        /// Gene position.
        pos: usize,
    },
    /// A child's node is not its slot's target.
    #[error("gene at word {pos} is a `{found}` but slot `{slot}` of `{parent}` takes `{expected}`")]
    WrongChild {
        /// Gene position.
        pos: usize,
        /// The node found.
        found: String,
        /// The parent node.
        parent: String,
        /// The slot name.
        slot: String,
        /// The slot's target node.
        expected: String,
    },
    /// A parameter value lies outside its distribution's support.
    #[error("parameter `{param}` of the `{node}` gene at word {pos} lies outside its support")]
    ParamOutOfSupport {
        /// Gene position.
        pos: usize,
        /// Node name.
        node: String,
        /// Parameter name.
        param: String,
    },
    /// The gene count breaks the graph's length limits.
    #[error("the chromosome has {len} genes; the graph allows {min} <= L < {max}")]
    Length {
        /// Gene count.
        len: usize,
        /// `L_min`.
        min: u32,
        /// `L_max` (`inf` when unbounded).
        max: String,
    },
    /// A gene is deeper than the graph allows.
    #[error("gene at word {pos} has depth {depth}; the graph allows at most {max}")]
    Depth {
        /// Gene position.
        pos: usize,
        /// Its depth.
        depth: u32,
        /// The limit.
        max: u32,
    },
    /// The cached gene count disagrees with the buffer.
    #[error("the stored gene count {stored} disagrees with the {actual} genes in the buffer")]
    Count {
        /// Stored count.
        stored: usize,
        /// Counted genes.
        actual: usize,
    },
    /// The chromosome was saved for another generator graph.
    #[error(
        "the chromosome was made for graph `{found}` (fingerprint {found_fp}), not `{expected}` (fingerprint {expected_fp})"
    )]
    ForeignGraph {
        /// Graph name in the file.
        found: String,
        /// Fingerprint in the file.
        found_fp: String,
        /// Graph name expected.
        expected: String,
        /// Fingerprint expected.
        expected_fp: String,
    },
    /// The saved data has a format version this library does not read.
    #[error("unsupported chromosome format version {0}")]
    Version(u32),
}

impl Chromosome {
    /// Checks every invariant: node ids exist, genes fit the buffer, the root
    /// is one gene of the start node, every parent precedes its children,
    /// parent and child links agree, each child's node is its slot's target,
    /// parameters lie in their support and the graph's limits hold.
    ///
    /// Because every non-root gene's parent precedes it and links are mutual,
    /// the genes form one tree rooted at position 0: no cycles, nothing unreachable.
    pub fn validate(&self, graph: &Graph) -> Result<(), GenomeError> {
        let starts = validate_words(graph, &self.words, false)?;
        if starts != self.index {
            return Err(GenomeError::Count {
                stored: self.len(),
                actual: starts.len(),
            });
        }
        Ok(())
    }
}

/// Validates a raw buffer; on success it returns the gene positions. A
/// `partial` chromosome (still being built) may be shorter than `L_min`.
pub(crate) fn validate_words(
    graph: &Graph,
    words: &[u32],
    partial: bool,
) -> Result<Vec<u32>, GenomeError> {
    if words.is_empty() {
        return Err(GenomeError::Empty);
    }
    // Pass 1: gene boundaries, node ids and flags.
    const NOT_A_GENE: u32 = u32::MAX;
    let mut depth_at = vec![NOT_A_GENE; words.len()];
    let mut starts = Vec::new();
    let mut pos = 0;
    while pos < words.len() {
        let w0 = words[pos];
        let node = word::node(w0);
        if node as usize >= graph.node_count() {
            return Err(GenomeError::UnknownNode {
                pos,
                node,
                nodes: graph.node_count(),
            });
        }
        if w0 & word::FLAGS != 0 {
            return Err(GenomeError::Flags { pos });
        }
        let size = graph.layout(node).gene_words as usize;
        if pos + size > words.len() {
            return Err(GenomeError::Truncated {
                pos,
                needed: size,
                available: words.len() - pos,
            });
        }
        depth_at[pos] = 0;
        starts.push(pos as u32);
        pos += size;
    }
    let limits = graph.limits();
    // Pass 2: links, nodes, parameters, depth.
    for &pos in &starts {
        let pos = pos as usize;
        let w0 = words[pos];
        let node = word::node(w0);
        let layout = graph.layout(node);
        let spec = graph.node(node);
        if pos == 0 {
            if node != graph.start() || words[word::PARENT] != 0 || word::slot(w0) != 0 {
                return Err(GenomeError::BadRoot {
                    start: graph.node(graph.start()).name.to_string(),
                });
            }
        } else {
            let link = words[pos + word::PARENT] as i32;
            let parent = pos as i64 + link as i64;
            if link >= 0 || parent < 0 || depth_at[parent as usize] == NOT_A_GENE {
                return Err(GenomeError::BadParent { pos });
            }
            let parent = parent as usize;
            let pnode = word::node(words[parent]);
            let pspec = graph.node(pnode);
            let slot = word::slot(w0);
            if slot as usize >= pspec.slots.len() {
                return Err(GenomeError::BadSlot {
                    pos,
                    slot,
                    parent: pspec.name.to_string(),
                    slots: pspec.slots.len(),
                });
            }
            if words[parent + word::SLOTS + slot as usize] != word::link(parent, pos) {
                return Err(GenomeError::BrokenLink { pos });
            }
            let edge = graph.edge(pnode, slot);
            if edge.to != node {
                let s = &pspec.slots[slot as usize];
                return Err(GenomeError::WrongChild {
                    pos,
                    found: spec.name.to_string(),
                    parent: pspec.name.to_string(),
                    slot: s.name.to_string(),
                    expected: s.target.to_string(),
                });
            }
            let depth = depth_at[parent] + 1;
            if !limits.allows_depth(depth) {
                return Err(GenomeError::Depth {
                    pos,
                    depth,
                    max: limits.max_depth.unwrap_or(0),
                });
            }
            depth_at[pos] = depth;
        }
        for j in 0..layout.slots as usize {
            let l = words[pos + word::SLOTS + j];
            if l == 0 {
                continue;
            }
            let child = pos as i64 + l as i32 as i64;
            let ok = child > pos as i64
                && (child as usize) < words.len()
                && depth_at[child as usize] != NOT_A_GENE
                && words[child as usize + word::PARENT] == word::link(child as usize, pos)
                && word::slot(words[child as usize]) == j as u32;
            if !ok {
                return Err(GenomeError::BrokenLink { pos });
            }
        }
        let params_at = pos + word::SLOTS + layout.slots as usize;
        for (p, &off) in spec.params.iter().zip(&layout.param_offsets) {
            let start = params_at + off as usize;
            if !p
                .dist
                .contains(&words[start..start + p.dist.kind().words()])
            {
                return Err(GenomeError::ParamOutOfSupport {
                    pos,
                    node: spec.name.to_string(),
                    param: p.name.to_string(),
                });
            }
        }
    }
    let len = starts.len() as u32;
    let allowed = if partial {
        limits.max_len.is_none_or(|m| len < m)
    } else {
        limits.allows_len(len)
    };
    if !allowed {
        return Err(GenomeError::Length {
            len: starts.len(),
            min: limits.min_len,
            max: limits
                .max_len
                .map_or_else(|| "inf".to_string(), |m| m.to_string()),
        });
    }
    Ok(starts)
}
