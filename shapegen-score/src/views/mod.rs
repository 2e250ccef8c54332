//! View attributes and best views (Lienhard's thesis, §3.3 and §3.4.1):
//! what a render of a model shows, as eight numbers in `[0, 1]`, and the
//! viewpoint that shows a model best.
//!
//! - [`ViewAttributes`]: a1–a8 of one [`GBuffer`](crate::GBuffer), in the
//!   best-view and the clustering variants;
//! - [`AttributeWeights`]: the thesis's weights (Tab. 3.2) or a user's;
//! - [`best_view`]: renders from a [`ViewSampling`]'s viewpoints and keeps
//!   the best-scoring one.

mod attributes;
mod best;

pub use attributes::{ATTRIBUTE_NAMES, AttributeWeights, ViewAttributes, normalize_columns};
pub use best::{BestView, ViewSampling, Viewpoint, best_view, best_view_around};
