//! Mesh topology (welding, boundary chain) against map-based definitions,
//! on random meshes with repeated positions.

use std::collections::{BTreeMap, HashMap};

use glam::Vec3;
use proptest::prelude::*;
use shapegen_score::Mesh;

/// Random triangles over a few distinct positions, each position repeated
/// under several indices (as OBJ exporters write them).
fn mesh() -> impl Strategy<Value = Mesh> {
    (2usize..8, 1usize..30).prop_flat_map(|(distinct, tris)| {
        (
            prop::collection::vec((0..distinct, -2i8..3), distinct..4 * distinct),
            prop::collection::vec([0usize..64, 0usize..64, 0usize..64], tris),
        )
            .prop_map(|(vertices, triangles)| {
                let positions: Vec<Vec3> = vertices
                    .iter()
                    .map(|&(p, y)| Vec3::new(p as f32, f32::from(y), 0.5))
                    .collect();
                let n = positions.len();
                Mesh {
                    positions,
                    triangles: triangles
                        .iter()
                        .map(|t| t.map(|i| (i % n) as u32))
                        .collect(),
                }
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// `welded` maps each vertex to the first index at its exact position;
    /// `boundary_chain` is the net directed edge multiset, in edge order.
    #[test]
    fn welding_and_chain_match_their_definitions(mesh in mesh()) {
        let mut first: HashMap<[u32; 3], u32> = HashMap::new();
        let ids: Vec<u32> = (0..mesh.positions.len() as u32)
            .map(|i| *first.entry(mesh.positions[i as usize].to_array().map(f32::to_bits)).or_insert(i))
            .collect();
        prop_assert_eq!(mesh.welded(), ids.clone());
        let mut net = BTreeMap::<(u32, u32), i32>::new();
        for t in &mesh.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (a, b) = (ids[a as usize], ids[b as usize]);
                if a < b {
                    *net.entry((a, b)).or_default() += 1;
                } else if b < a {
                    *net.entry((b, a)).or_default() -= 1;
                }
            }
        }
        let mut chain = Vec::new();
        for ((a, b), m) in net {
            let edge = if m > 0 { [a, b] } else { [b, a] };
            chain.extend(std::iter::repeat_n(edge, m.unsigned_abs() as usize));
        }
        prop_assert_eq!(mesh.boundary_chain(), chain);
    }
}
