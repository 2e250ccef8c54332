//! [`Pending`]: the genes waiting to be expressed.

/// Genes waiting to be expressed, each with the state its parent passed it:
/// the working memory of [`Generator::express_with`](super::Generator::express_with),
/// reused from one expression to the next.
///
/// Positions and states are kept in two arrays, so pushing a state writes it
/// whole and aligned (a scope is five 16-byte registers).
#[derive(Clone, Debug)]
pub struct Pending<St> {
    positions: Vec<u32>,
    states: Vec<St>,
}

impl<St> Default for Pending<St> {
    fn default() -> Self {
        Self::new()
    }
}

impl<St> Pending<St> {
    /// Empty working memory.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            positions: Vec::new(),
            states: Vec::new(),
        }
    }

    /// Forgets every pending gene (keeps the allocations).
    pub fn clear(&mut self) {
        self.positions.clear();
        self.states.clear();
    }

    /// Schedules the gene at `pos` with `state`.
    #[inline]
    pub fn push(&mut self, pos: u32, state: St) {
        self.positions.push(pos);
        self.states.push(state);
    }

    /// The most recently scheduled gene: its position and state.
    #[inline]
    pub fn pop(&mut self) -> Option<(u32, St)> {
        let state = self.pop_state()?;
        Some((self.pop_position(), state))
    }

    /// The state of the most recently scheduled gene; call
    /// [`pop_position`](Self::pop_position) next. Hot loops use this pair:
    /// returning the state alone keeps it aligned (no tuple temporaries).
    #[inline]
    pub fn pop_state(&mut self) -> Option<St> {
        self.states.pop()
    }

    /// The position of the gene whose state [`pop_state`](Self::pop_state)
    /// just returned (0 if there is none).
    #[inline]
    pub fn pop_position(&mut self) -> u32 {
        self.positions.pop().unwrap_or(0)
    }

    /// Number of pending genes.
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether nothing is pending.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The pending genes, in the order they were pushed: positions and states.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (u32, &St)> {
        self.positions.iter().copied().zip(&self.states)
    }

    /// Removes the pending genes, in the order they were pushed (keeps the allocations).
    pub fn drain(&mut self) -> impl Iterator<Item = (u32, St)> + '_ {
        self.positions.drain(..).zip(self.states.drain(..))
    }

    /// Reverses the genes scheduled since the length was `start`, so that
    /// they are expressed in the order they were scheduled.
    #[inline]
    pub fn reverse_from(&mut self, start: usize) {
        if self.positions.len() > start + 1 {
            self.positions[start..].reverse();
            self.states[start..].reverse();
        }
    }
}
