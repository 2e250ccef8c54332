#!/usr/bin/env bash
# Issue #18's tree-volume goals are relative to the code of its filing (tree
# avoid ~120 evaluations/s, tree fill ~160/s, on the machine of that day):
# this times that code and today's on one machine, in one session,
# alternating, each pinned to one core, on the same 50 trees.
#
#   benches/tree_volume_since_18.sh [ROUNDS]     (default 3; about 2 min a round)
#
# It checks out the last commit before the first #18 change (3e5ade8^) into
# a temporary worktree, adds to it a bench that mirrors today's
# `tree_volume/(avoid_50_trees_150|fill_50_trees_100)` in benches/score.rs
# (same scenes, same trees: `random_individual` of tree v1 from stream 5,
# l0 150) and prints its trees' genes and the sum of their scores, then
# criterion's times for both builds. Both time models their scratch has
# not seen, not its first writes to memory: that code's scratch remembers
# no instances and is made afresh (untimed) for each iteration; today's
# forgets its instances before each one and keeps its memory. The same bench on today's code gave
# the same trees and sums, bit for bit (7,675 genes; 20.218020922 and
# -92.117574983): the voxelizer changed its speed, not its results.
# Needs ../shared/data (or $SHAPEGEN_DATA). Not run in CI.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
old=$(mktemp -d /tmp/shapegen-18-XXXXXX)
trap 'git worktree remove --force "$old" >/dev/null 2>&1 || true' EXIT
git worktree add --detach "$old" 3e5ade8^ >/dev/null
cat >"$old/benches/tv.rs" <<'EOF'
use std::path::PathBuf;
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use shapegen::express::Generator;
use shapegen::glam::Vec3;
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::TreeV1;
use shapegen::score::volume::{VolumeScene, VolumeTarget};
use shapegen::score::{Grid, Mesh, ShapeMeshes, VolumeFitness, VolumeScore};

fn data(rel: &str) -> PathBuf {
    std::env::var_os("SHAPEGEN_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"))
        .join(rel)
}

fn fitness(target: &str, n: u32, good: f64, bad: f64) -> VolumeFitness<TreeV1> {
    let grid = Grid::cube(Vec3::splat(-5.0), Vec3::splat(5.0), n).unwrap();
    let target = VolumeTarget {
        name: target.into(),
        mesh: Mesh::load_obj(&data(target)).unwrap(),
        fill: 1.0,
        outside: 0.0,
        inside: Default::default(),
    };
    let scene = VolumeScene::new(grid, &[target]).unwrap();
    let mut shapes = ShapeMeshes::builtin(&TreeV1).unwrap();
    let leaf = Mesh::load_obj(&data("paper/leaf_low_poly.obj")).unwrap();
    shapes.set("leaf", leaf.normalized()).unwrap();
    let score = VolumeScore::Normalized { w_good: good, w_bad: bad, w_length: 0.001, separate_overlap: None };
    let limits = Limits { max_depth: Some(8), min_len: 4, max_len: Some(300) };
    VolumeFitness::new(TreeV1, scene, &shapes, score).unwrap().with_limits(limits)
}

fn bench(c: &mut Criterion) {
    for (name, target, n, good, bad) in [
        ("avoid_50_trees_150", "paper/tree_avoid_2.obj", 150, -120.0, -1.0),
        ("fill_50_trees_100", "paper/target_tree.obj", 100, 2.0, 15.0),
    ] {
        let f = fitness(target, n, good, bad);
        let mut rng = stream(5, &[]);
        let trees: Vec<Chromosome> = (0..50)
            .map(|_| random_individual(TreeV1.graph(), &InitLength::Around { l0: 150 }, &mut rng).unwrap())
            .collect();
        let mut s = f.scratch();
        let sum: f64 = trees.iter().map(|m| f.evaluate(m, &mut s)).sum();
        let genes: usize = trees.iter().map(|m| m.len()).sum();
        eprintln!("{name}: {genes} genes, score sum {sum:.9}");
        let mut g = c.benchmark_group("score/tree_volume");
        g.throughput(Throughput::Elements(50));
        g.bench_function(name, |b| {
            b.iter_batched_ref(|| f.scratch(), |s| trees.iter().map(|m| f.evaluate(m, s)).sum::<f64>(), BatchSize::LargeInput)
        });
        g.finish();
    }
}
criterion_group!(benches, bench);
criterion_main!(benches);
EOF
printf '\n[[bench]]\nname = "tv"\nharness = false\n' >>"$old/Cargo.toml"
export SHAPEGEN_DATA=${SHAPEGEN_DATA:-$(pwd)/../shared/data}
# The bench's own executable (cargo also lists the package's binaries,
# in no fixed order).
bin() { cargo bench --no-run --message-format=json "$@" 2>/dev/null |
    grep '"kind":\["bench"\]' |
    sed -n 's/.*"executable":"\([^"]*\)".*/\1/p' | tail -n1; }
then_bin=$(cd "$old" && CARGO_TARGET_DIR="$old/target" bin --bench tv)
now_bin=$(bin --bench score)
filter='tree_volume/(avoid_50_trees_150|fill_50_trees_100)$'
for round in $(seq "$rounds"); do
    echo "== round $round: the code of #18's filing (3e5ade8^)"
    (cd "$old" && taskset -c 1 "$then_bin" --bench 2>&1 | grep -E 'genes|^score|time:')
    echo "== round $round: this checkout"
    taskset -c 1 "$now_bin" --bench "$filter" 2>&1 | grep -E '^score|time:'
done
