//! The numerics of a gallery (thesis §3.4.3–3.4.4): k-means++ with a fixed
//! first seed under weighted distances, PCA to two dimensions, and the
//! radial order of points around a centre.

// Eight-dimensional arithmetic reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use rand::RngExt;

/// Weighted squared distance `Σ wₖ (aₖ − bₖ)²`.
#[must_use]
pub fn distance(w: &[f64; 8], a: &[f64; 8], b: &[f64; 8]) -> f64 {
    (0..8).map(|k| w[k] * (a[k] - b[k]) * (a[k] - b[k])).sum()
}

/// A k-means clustering.
#[derive(Clone, Debug, PartialEq)]
pub struct Clustering {
    /// Each point's cluster.
    pub assignment: Vec<usize>,
    /// The cluster centres.
    pub centers: Vec<[f64; 8]>,
}

/// k-means++ (Arthur and Vassilvitskii) with point `first` as the first
/// seed (the thesis seeds with the default model), further seeds drawn
/// with probability proportional to the squared distance to the nearest
/// seed, then Lloyd iterations until no point changes cluster (at most
/// 100). `k` is reduced to the number of distinct points. Deterministic
/// for a given `seed`.
#[must_use]
pub fn kmeans_pp(
    points: &[[f64; 8]],
    w: &[f64; 8],
    k: usize,
    first: usize,
    seed: u64,
) -> Clustering {
    if points.is_empty() {
        return Clustering {
            assignment: Vec::new(),
            centers: Vec::new(),
        };
    }
    let mut rng = shapegen_core::rng::stream(seed, &[0x6b6d_6561_6e73]);
    let mut centers = vec![points[first.min(points.len() - 1)]];
    let mut nearest: Vec<f64> = points.iter().map(|p| distance(w, p, &centers[0])).collect();
    while centers.len() < k {
        let total: f64 = nearest.iter().sum();
        if total <= 0.0 {
            break; // every point is already a centre
        }
        let mut u = rng.random::<f64>() * total;
        let mut pick = nearest.iter().rposition(|&d| d > 0.0).unwrap_or(0);
        for (i, &d) in nearest.iter().enumerate() {
            if d > 0.0 && u < d {
                pick = i;
                break;
            }
            u -= d;
        }
        centers.push(points[pick]);
        for (n, p) in nearest.iter_mut().zip(points) {
            *n = n.min(distance(w, p, &points[pick]));
        }
    }
    let closest = |p: &[f64; 8], centers: &[[f64; 8]]| {
        (0..centers.len())
            .min_by(|&a, &b| distance(w, p, &centers[a]).total_cmp(&distance(w, p, &centers[b])))
            .unwrap_or(0)
    };
    let mut assignment: Vec<usize> = points.iter().map(|p| closest(p, &centers)).collect();
    let mut converged = false;
    for _ in 0..100 {
        update_means(points, &assignment, &mut centers);
        let next: Vec<usize> = points.iter().map(|p| closest(p, &centers)).collect();
        converged = next == assignment;
        assignment = next;
        if converged {
            break;
        }
    }
    if !converged {
        // The centres must be the means of the assignment returned.
        update_means(points, &assignment, &mut centers);
    }
    Clustering {
        assignment,
        centers,
    }
}

/// Each centre becomes the mean of the points assigned to it (an empty
/// cluster keeps its centre).
fn update_means(points: &[[f64; 8]], assignment: &[usize], centers: &mut [[f64; 8]]) {
    let mut sums = vec![([0.0; 8], 0usize); centers.len()];
    for (p, &c) in points.iter().zip(assignment) {
        for k in 0..8 {
            sums[c].0[k] += p[k];
        }
        sums[c].1 += 1;
    }
    for (c, (s, n)) in centers.iter_mut().zip(&sums) {
        if *n > 0 {
            *c = s.map(|v| v / *n as f64);
        }
    }
}

/// The first two principal components of `points` (each coordinate scaled
/// by `√wₖ` first, so the plane is that of the clustering distance), and
/// every point projected onto them.
#[must_use]
pub fn pca_2d(points: &[[f64; 8]], w: &[f64; 8]) -> Vec<[f64; 2]> {
    let n = points.len();
    if n == 0 {
        return Vec::new();
    }
    let scaled: Vec<[f64; 8]> = points
        .iter()
        .map(|p| std::array::from_fn(|k| p[k] * w[k].max(0.0).sqrt()))
        .collect();
    let mut mean = [0.0; 8];
    for p in &scaled {
        for k in 0..8 {
            mean[k] += p[k] / n as f64;
        }
    }
    let mut cov = [[0.0; 8]; 8];
    for p in &scaled {
        for i in 0..8 {
            for j in 0..8 {
                cov[i][j] += (p[i] - mean[i]) * (p[j] - mean[j]) / n as f64;
            }
        }
    }
    // Power iteration with deflation: two leading eigenvectors.
    let mut axes = [[0.0f64; 8]; 2];
    for a in 0..2 {
        let mut v: [f64; 8] = std::array::from_fn(|k| 1.0 + k as f64 * 0.37 + a as f64);
        for _ in 0..200 {
            let mut next = [0.0; 8];
            for i in 0..8 {
                next[i] = (0..8).map(|j| cov[i][j] * v[j]).sum();
            }
            for prev in axes.iter().take(a) {
                let d: f64 = (0..8).map(|k| next[k] * prev[k]).sum();
                for k in 0..8 {
                    next[k] -= d * prev[k];
                }
            }
            let len = next.iter().map(|x| x * x).sum::<f64>().sqrt();
            if len < 1e-300 {
                break;
            }
            v = next.map(|x| x / len);
        }
        axes[a] = v;
    }
    scaled
        .iter()
        .map(|p| {
            let c: [f64; 8] = std::array::from_fn(|k| p[k] - mean[k]);
            [0, 1].map(|a| (0..8).map(|k| c[k] * axes[a][k]).sum())
        })
        .collect()
}

/// `items` sorted by the angle of their point around `center`, clockwise
/// from straight up (as they are placed around the centre picture).
#[must_use]
pub fn radial_order(items: &[usize], points: &[[f64; 2]], center: [f64; 2]) -> Vec<usize> {
    let angle = |i: usize| {
        let (dx, dy) = (points[i][0] - center[0], points[i][1] - center[1]);
        // atan2(x, y): 0 straight up, growing clockwise.
        dx.atan2(dy).rem_euclid(std::f64::consts::TAU)
    };
    let mut out = items.to_vec();
    out.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)).then(a.cmp(&b)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four well-separated blobs are found as four clusters, whatever the seed.
    #[test]
    fn kmeans_finds_separated_blobs() {
        let mut rng = shapegen_core::rng::stream(1, &[]);
        let centres = [0.1, 0.4, 0.7, 0.95];
        let points: Vec<[f64; 8]> = (0..200)
            .map(|i| {
                let c = centres[i % 4];
                std::array::from_fn(|k| {
                    if k < 3 {
                        c + 0.01 * rng.random::<f64>()
                    } else {
                        0.5
                    }
                })
            })
            .collect();
        let w = [1.0; 8];
        for seed in 0..5 {
            let c = kmeans_pp(&points, &w, 4, 0, seed);
            for i in 0..points.len() {
                for j in 0..points.len() {
                    assert_eq!(
                        c.assignment[i] == c.assignment[j],
                        i % 4 == j % 4,
                        "seed {seed}"
                    );
                }
            }
            // The first seed's cluster holds point 0.
            assert_eq!(c.assignment[0], 0);
        }
        // More clusters than distinct points: as many clusters as points.
        let two = vec![[0.0; 8], [1.0; 8], [1.0; 8]];
        let c = kmeans_pp(&two, &w, 5, 0, 0);
        assert_eq!(c.centers.len(), 2);
    }

    /// Points on a line along attribute 2 project onto a line in the
    /// first component, with the second near zero.
    #[test]
    fn pca_finds_the_main_direction() {
        let points: Vec<[f64; 8]> = (0..50)
            .map(|i| {
                let t = f64::from(i) / 49.0;
                let mut p = [0.3; 8];
                p[2] = t;
                p[5] = 0.5 + 0.01 * (f64::from(i) * 1.7).sin();
                p
            })
            .collect();
        let proj = pca_2d(&points, &[1.0; 8]);
        let spread = |a: usize| {
            let (lo, hi) = proj
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p[a]), h.max(p[a]))
                });
            hi - lo
        };
        assert!((spread(0) - 1.0).abs() < 1e-4, "{}", spread(0));
        assert!(spread(1) < 0.03);
    }

    #[test]
    fn radial_order_goes_clockwise_from_the_top() {
        let points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];
        assert_eq!(
            radial_order(&[1, 2, 3, 4], &points, points[0]),
            vec![2, 1, 4, 3]
        );
    }
}
