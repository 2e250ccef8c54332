//! The [`Generator`] trait: a graph plus the code that turns a chromosome into geometry.

use crate::genome::Chromosome;
use crate::graph::Graph;

use super::pending::Pending;
use super::sink::ModelSink;

/// A procedural generator: a checked graph, the shapes it emits, and how
/// each gene's operation transforms the state and emits geometry.
///
/// Implemented by the `generator!` macro (one monomorphic function per node)
/// and by [`Interpreter`](super::Interpreter) (rules given at run time).
pub trait Generator: Sync {
    /// The shape state passed along edges (the paper's scope by default).
    type State: Clone;

    /// The checked generator graph.
    fn graph(&self) -> &Graph;

    /// Names of the shapes the generator emits; a [`ShapeId`](super::ShapeId) indexes this list.
    fn shapes(&self) -> &[std::borrow::Cow<'static, str>];

    /// The state the root gene starts from.
    fn axiom(&self) -> Self::State;

    /// Expresses `chromosome` (which must be valid for [`graph`](Self::graph)),
    /// emitting its instances into `sink`. Genes are expressed depth first,
    /// children in the order their parent schedules them. `pending` is
    /// working memory, reused between calls.
    fn express_with<S: ModelSink>(
        &self,
        chromosome: &Chromosome,
        sink: &mut S,
        pending: &mut Pending<Self::State>,
    );

    /// One derivation step: expresses the single gene at `pos` of
    /// `chromosome` from `state`, emitting its instances into `sink` and
    /// pushing the children it schedules onto `children` (their positions
    /// and states), in the order the gene schedules them. Children are not
    /// expressed. Starting from position 0 and [`axiom`](Self::axiom) and
    /// stepping every scheduled child gives the instances of
    /// [`express_with`](Self::express_with); a caller may instead change a
    /// child's state first or stop anywhere (design transformations do both).
    ///
    /// # Panics
    /// If `pos` is not the position of a gene of `chromosome` (positions come
    /// from 0, the root, and from `children`).
    fn express_gene<S: ModelSink>(
        &self,
        chromosome: &Chromosome,
        pos: u32,
        state: Self::State,
        sink: &mut S,
        children: &mut Pending<Self::State>,
    );

    /// Expresses the subtree of the gene at `pos` from `state`: that gene,
    /// then every gene below it, depth first, children in the order their
    /// parent schedules them, one [`express_gene`](Self::express_gene) each.
    /// From position 0 and the [`axiom`](Self::axiom) it is the whole
    /// chromosome, as [`express_with`](Self::express_with) expresses it.
    /// `pending` is working memory, cleared first.
    ///
    /// # Panics
    /// As [`express_gene`](Self::express_gene), if `pos` is not a gene's position.
    #[inline]
    fn express_from<S: ModelSink>(
        &self,
        chromosome: &Chromosome,
        pos: u32,
        state: Self::State,
        sink: &mut S,
        pending: &mut Pending<Self::State>,
    ) {
        pending.clear();
        pending.push(pos, state);
        while let Some(state) = pending.pop_state() {
            let pos = pending.pop_position();
            let start = pending.len();
            self.express_gene(chromosome, pos, state, sink, pending);
            pending.reverse_from(start);
        }
    }

    /// [`express_with`](Self::express_with) with fresh working memory.
    fn express<S: ModelSink>(&self, chromosome: &Chromosome, sink: &mut S) {
        self.express_with(chromosome, sink, &mut Pending::new());
    }
}

/// Implements [`Generator`] for a pointer type by delegating to its target.
macro_rules! delegate_generator {
    ($(#[$doc:meta])* $ty:ty, $($bound:tt)+) => {
        $(#[$doc])*
        impl<G: $($bound)+> Generator for $ty {
            type State = G::State;

            #[inline]
            fn graph(&self) -> &Graph {
                (**self).graph()
            }

            #[inline]
            fn shapes(&self) -> &[std::borrow::Cow<'static, str>] {
                (**self).shapes()
            }

            #[inline]
            fn axiom(&self) -> Self::State {
                (**self).axiom()
            }

            #[inline]
            fn express_with<S: ModelSink>(
                &self,
                chromosome: &Chromosome,
                sink: &mut S,
                pending: &mut Pending<Self::State>,
            ) {
                (**self).express_with(chromosome, sink, pending);
            }

            #[inline]
            fn express_gene<S: ModelSink>(
                &self,
                chromosome: &Chromosome,
                pos: u32,
                state: Self::State,
                sink: &mut S,
                children: &mut Pending<Self::State>,
            ) {
                (**self).express_gene(chromosome, pos, state, sink, children);
            }

            #[inline]
            fn express_from<S: ModelSink>(
                &self,
                chromosome: &Chromosome,
                pos: u32,
                state: Self::State,
                sink: &mut S,
                pending: &mut Pending<Self::State>,
            ) {
                (**self).express_from(chromosome, pos, state, sink, pending);
            }
        }
    };
}

delegate_generator!(
    /// A generator shared by reference is the same generator (e.g. one
    /// [`Interpreter`](super::Interpreter) both scored and written out).
    &G,
    Generator + ?Sized
);

delegate_generator!(
    /// A generator shared between owners (e.g. a registry and the
    /// experiments it builds) is the same generator.
    std::sync::Arc<G>,
    Generator + Send + ?Sized
);
