//! Two façades written with split rules (`split!`), after the façades of
//! Lienhard's thesis, Fig. A.2: a classical one (a storey of pillars and
//! window tiles under a ledge) and a modern one (storeys of plain window
//! tiles). Floors, tiles and windows carry the tags `floor`, `tile` and
//! `window`, so the two transform into each other split by split; walls
//! carry `wall`, the spacing a split transformation leaves out and puts back.

use crate::express::Scope;
use crate::generator;
use crate::glam::{Affine3A, Vec3};

/// Depth of a façade's wall.
const DEPTH: f32 = 0.3;

/// A window pane in `frame`, `width` and `height` of it, standing a little
/// in front of the frame's wall.
fn pane(frame: Scope, width: f32, height: f32) -> Affine3A {
    let mut p = frame;
    p.resize(Vec3::new(width, height, 1.2));
    p.instance()
}

generator! {
    /// A classical façade (thesis Fig. A.2, left): storeys of about 4.5 m
    /// under a ledge; each storey a split along x into twin pillars at the
    /// ends, five yellow window tiles and single pillars between them, wall
    /// between (thesis A.1: `{P, P, Yt, P, Yt, P, Yt, P, Yt, P, Yt, P, P}`
    /// without walls). The default model has one storey: `{Floor, Ledge}`.
    pub struct ClassicFacade;
    shapes: [wall, pillar, window, ledge];
    start: Facade;

    node Facade {
        tags { facade }
        params {
            width: f32 = uniform(13.0, 17.0),
            height: f32 = uniform(4.0, 10.0),
        }
        slots { floor: Floor = 1.0, ledge: Ledge = 1.0 }
        |mut scope| {
            scope.set_size(Vec3::new(width, height, DEPTH));
            scope.move_y(0.5 * height);
            split!(scope, y, [floor: repeat(4.5), ledge: 0.5]);
        }
    }

    node Floor {
        tags { floor }
        slots { pillar: Pillar = 1.0, tile: YellowTile = 1.0, wall: Wall = 1.0 }
        |scope| {
            split!(scope, x, [
                pillar: 0.5, pillar: 0.5, wall: rel(0.4),
                tile: 1.6, wall: rel(0.4), pillar: 0.5, wall: rel(0.4),
                tile: 1.6, wall: rel(0.4), pillar: 0.5, wall: rel(0.4),
                tile: 1.6, wall: rel(0.4), pillar: 0.5, wall: rel(0.4),
                tile: 1.6, wall: rel(0.4), pillar: 0.5, wall: rel(0.4),
                tile: 1.6, wall: rel(0.4), pillar: 0.5, pillar: 0.5,
            ]);
        }
    }

    /// A window tile: wall, a tall window, wall (a vertical split).
    node YellowTile {
        tags { tile }
        slots { window: Window = 1.0, wall: Wall = 1.0 }
        |scope| { split!(scope, y, [wall: rel(0.8), window: 2.4, wall: rel(0.6)]); }
    }

    node Pillar emits {
        tags { pillar }
        |mut scope| {
            scope.size.z *= 1.6;
            emit!(pillar, scope.instance());
        }
    }

    node Ledge emits {
        tags { ledge }
        |mut scope| {
            scope.size.z *= 2.0;
            emit!(ledge, scope.instance());
        }
    }

    /// A tall window pane in a frame of wall.
    node Window emits {
        tags { window }
        |scope| {
            emit!(wall, scope.instance());
            emit!(window, pane(scope, 0.8, 0.9));
        }
    }

    node Wall emits {
        tags { wall }
        |scope| { emit!(wall, scope.instance()); }
    }
}

generator! {
    /// A modern façade (thesis Fig. A.2, right): storeys of about 3.5 m,
    /// each a split along x into plain window tiles of about 2 m with a
    /// margin of wall at both ends (thesis A.1: `{Wt, Wt, Wt, Wt, Wt, Wt, Wt}`
    /// without walls). The default model has two storeys: `{Floor, Floor}`.
    pub struct ModernFacade;
    shapes: [wall, window];
    start: Facade;

    node Facade {
        tags { facade }
        params {
            width: f32 = uniform(13.0, 17.0),
            height: f32 = uniform(5.0, 9.0),
        }
        slots { floor: Floor = 1.0 }
        |mut scope| {
            scope.set_size(Vec3::new(width, height, DEPTH));
            scope.move_y(0.5 * height);
            split!(scope, y, [floor: repeat(3.5)]);
        }
    }

    node Floor {
        tags { floor }
        slots { tile: WindowTile = 1.0, wall: Wall = 1.0 }
        |scope| { split!(scope, x, [wall: rel(0.5), tile: repeat(2.0), wall: rel(0.5)]); }
    }

    /// A window tile: wall, a wide window, wall (a vertical split).
    node WindowTile {
        tags { tile }
        slots { window: Window = 1.0, wall: Wall = 1.0 }
        |scope| { split!(scope, y, [wall: rel(0.5), window: 2.0, wall: rel(0.6)]); }
    }

    /// A window pane in a frame of wall.
    node Window emits {
        tags { window }
        |scope| {
            emit!(wall, scope.instance());
            emit!(window, pane(scope, 0.85, 0.85));
        }
    }

    node Wall emits {
        tags { wall }
        |scope| { emit!(wall, scope.instance()); }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::express::{Generator, Instances};

    /// The shape names of a default façade's instances, in order.
    fn names<G: Generator>(g: &G) -> Vec<String> {
        let c = crate::ops::default_model(g.graph()).unwrap();
        let mut out = Instances::default();
        g.express(&c, &mut out);
        out.0
            .iter()
            .map(|i| g.shapes()[i.shape as usize].to_string())
            .collect()
    }

    #[test]
    fn the_default_facades_have_the_storeys_of_the_thesis() {
        let classic = names(&ClassicFacade);
        // One storey: twin pillars at both ends and four between, 5 windows, one ledge.
        assert_eq!(classic.iter().filter(|n| *n == "pillar").count(), 8);
        assert_eq!(classic.iter().filter(|n| *n == "window").count(), 5);
        assert_eq!(classic.iter().filter(|n| *n == "ledge").count(), 1);
        let modern = names(&ModernFacade);
        // Two storeys of seven windows.
        assert_eq!(modern.iter().filter(|n| *n == "window").count(), 14);
        assert_eq!(
            modern.iter().filter(|n| *n == "wall").count(),
            2 * (2 + 7 * 2 + 7)
        );
    }

    #[test]
    fn the_interpreter_splits_as_the_macro_does() {
        let g = ClassicFacade;
        let c = crate::ops::default_model(g.graph()).unwrap();
        let (mut a, mut b) = (Instances::default(), Instances::default());
        g.express(&c, &mut a);
        ClassicFacade::interpreter().express(&c, &mut b);
        assert_eq!(a, b);
        assert_eq!(
            ClassicFacade::spec().nodes[0].split,
            Some(crate::graph::Axis::Y)
        );
    }
}
