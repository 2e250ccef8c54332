//! The paper's generators, written with [`generator!`](crate::generator).
//!
//! Each scene re-creates a generator of *ShapeGenetics* (Haubenwallner et
//! al. 2017) with the nodes, parameter ranges, probabilities and placement
//! of the reference notes; angles are declared in degrees (trees) or
//! radians (city building rotation) as in the paper's configurations.
//!
//! | generator | paper | shapes |
//! |---|---|---|
//! | [`Spaceship`] | Fig. 3, 4a | `cube` |
//! | [`TreeV2`] | Fig. 8a, tree sketch | `frustum`, `leaf` |
//! | [`TreeV1`] | Fig. 8a, tree avoid | `frustum`, `leaf` |
//! | [`SpaceFillingCity`] | Fig. 8b, city skylines | `cube` |
//! | [`GridCity`] | city volume scene | `cube` |
//! | [`MonopodialTree`] | thesis Fig. 5.1 (Honda) | `frustum` |
//! | [`SympodialTree`] | thesis Fig. 5.1 (Aono–Kunii) | `frustum` |
//! | [`ClassicFacade`] | thesis Fig. A.2 (split rules) | `wall`, `pillar`, `window`, `ledge` |
//! | [`ModernFacade`] | thesis Fig. A.2 (split rules) | `wall`, `window` |
//! | [`Farm`] | thesis Fig. 5.10 | `cube`, `roof`, `frustum`, `window` |
//! | [`Castle`] | thesis Fig. 5.10 | `cube`, `roof`, `frustum`, `window` |
//! | [`Houses`] | thesis Fig. 5.12 (one-to-many) | `cube`, `roof` |
//! | [`Apartments`] | thesis Fig. 5.12 (one-to-many) | `cube`, `roof` |

mod city;
mod facade;
mod farm;
mod lsystem;
mod spaceship;
mod tree;
#[cfg(test)]
mod unrolled;

pub use city::{GRID, GridCity, LOT_STEP, SpaceFillingCity, grid_lot};
pub use facade::{ClassicFacade, ModernFacade};
pub use farm::{Apartments, Castle, Farm, Houses};
pub use lsystem::{MonopodialTree, SympodialTree};
pub use spaceship::{ShipState, Spaceship};
pub use tree::{TreeV1, TreeV2};

/// Registers the paper's generators under the names experiment files use:
/// `spaceship`, `tree_v1`, `tree_v2`, `space_filling_city`, `grid_city`,
/// the thesis's tree pair `monopodial_tree`, `sympodial_tree`, its
/// façades `classic_facade`, `modern_facade`, its `farm` and `castle`, and
/// its `houses` and `apartments`.
/// [`Registry::builtin`](crate::registry::Registry::builtin) calls it; a
/// user's generators register the same way.
pub fn register(registry: &mut crate::registry::Registry) {
    registry
        .register("spaceship", Spaceship)
        .register("tree_v1", TreeV1)
        .register("tree_v2", TreeV2)
        .register("space_filling_city", SpaceFillingCity)
        .register("grid_city", GridCity)
        .register("monopodial_tree", MonopodialTree)
        .register("sympodial_tree", SympodialTree)
        .register("classic_facade", ClassicFacade)
        .register("modern_facade", ModernFacade)
        .register("farm", Farm)
        .register("castle", Castle)
        .register("houses", Houses)
        .register("apartments", Apartments);
}
