//! Sample positions and reconstruction filters: the pure maths behind MSAA resolves,
//! supersampling patterns and temporal jitter, with CPU implementations that the shaders
//! mirror and the tests check.
//!
//! Positions are inside the unit pixel, (0,0) top-left, (1,1) bottom-right. The standard MSAA
//! positions are the Vulkan/Direct3D standard sample locations. The supersampling patterns are
//! the ones the MSAA article compares: a regular grid, a rotated grid (RGSS generalised to any
//! square count: the m x m lattice rotated so every sample has its own row and column), uniform
//! random, Poisson disk (best-candidate dart throwing, Mitchell 1991) and the Halton(2,3)
//! low-discrepancy sequence.

use glam::Vec2;

/// Standard MSAA sample positions for 1, 2, 4, 8 and 16 samples (`None` for other counts).
pub fn standard_msaa_positions(count: u32) -> Option<Vec<Vec2>> {
    // Offsets from the pixel centre in 1/16 pixel.
    let offsets: &[(i8, i8)] = match count {
        1 => &[(0, 0)],
        2 => &[(4, 4), (-4, -4)],
        4 => &[(-2, -6), (6, -2), (-6, 2), (2, 6)],
        8 => &[
            (1, -3),
            (-1, 3),
            (5, 1),
            (-3, -5),
            (-5, 5),
            (-7, -1),
            (3, 7),
            (7, -7),
        ],
        16 => &[
            (1, 1),
            (-1, -3),
            (-3, 2),
            (4, -1),
            (-5, -2),
            (2, 5),
            (5, 3),
            (3, -5),
            (-2, 6),
            (0, -7),
            (-4, -6),
            (-6, 4),
            (-8, 0),
            (7, -4),
            (6, 7),
            (-7, -8),
        ],
        _ => return None,
    };
    Some(
        offsets
            .iter()
            .map(|&(x, y)| Vec2::new(0.5 + f32::from(x) / 16.0, 0.5 + f32::from(y) / 16.0))
            .collect(),
    )
}

crate::named_enum! {
    /// A supersampling sample pattern.
    pub enum Pattern {
        /// m x m regular grid (the count is rounded to a square).
        Grid => "grid",
        /// m x m grid rotated so that each sample has its own row and column (RGSS for 4).
        RotatedGrid => "rgss",
        /// Uniform random positions.
        Random => "random",
        /// Poisson-disk positions (no two samples closer than a minimum distance).
        Poisson => "poisson",
        /// The Halton(2,3) sequence.
        Halton => "halton",
    }
}

impl Pattern {
    /// How many samples the pattern really uses when `requested` are asked for (grids need a
    /// square count).
    pub fn effective_count(self, requested: u32) -> u32 {
        match self {
            Self::Grid | Self::RotatedGrid => {
                let m = (requested.max(1) as f32).sqrt().round().max(1.0) as u32;
                m * m
            }
            _ => requested.max(1),
        }
    }

    /// The positions of `requested` samples (see [`Pattern::effective_count`]), deterministic.
    pub fn positions(self, requested: u32) -> Vec<Vec2> {
        let n = self.effective_count(requested);
        match self {
            Self::Grid => {
                let m = (n as f32).sqrt().round() as u32;
                (0..n)
                    .map(|i| {
                        Vec2::new(
                            ((i % m) as f32 + 0.5) / m as f32,
                            ((i / m) as f32 + 0.5) / m as f32,
                        )
                    })
                    .collect()
            }
            Self::RotatedGrid => {
                let m = (n as f32).sqrt().round() as u32;
                // Lattice spanned by (1, -m) and (m, 1) on the n x n sub-grid: x = i + m j and
                // y = j - m i (mod n) are both permutations of 0..n.
                (0..m)
                    .flat_map(|i| (0..m).map(move |j| (i, j)))
                    .map(|(i, j)| {
                        let x = i + m * j;
                        let y = (j + n * m - m * i) % n;
                        Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32)
                    })
                    .collect()
            }
            Self::Random => {
                let mut rng = SplitMix64(0x5eed_0001);
                (0..n)
                    .map(|_| Vec2::new(rng.next_f32(), rng.next_f32()))
                    .collect()
            }
            Self::Poisson => poisson_disk(n),
            Self::Halton => (1..=n)
                .map(|i| Vec2::new(halton(i, 2), halton(i, 3)))
                .collect(),
        }
    }
}

/// Element `index` (from 1) of the van der Corput sequence in `base`: the Halton sequence's
/// coordinate for that base, in [0, 1).
pub fn halton(mut index: u32, base: u32) -> f32 {
    let mut result = 0.0f64;
    let mut f = 1.0f64;
    while index > 0 {
        f /= f64::from(base);
        result += f * f64::from(index % base);
        index /= base;
    }
    result as f32
}

/// A small deterministic generator (SplitMix64, Steele et al. 2014) so patterns never change
/// with a dependency's version.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Best-candidate Poisson-disk points in the unit square with toroidal distances, so the
/// pattern tiles without clumps across pixel borders.
fn poisson_disk(n: u32) -> Vec<Vec2> {
    let mut rng = SplitMix64(0x5eed_0002);
    let mut points: Vec<Vec2> = Vec::with_capacity(n as usize);
    let toroidal = |a: Vec2, b: Vec2| {
        let d = (a - b).abs();
        d.min(Vec2::ONE - d).length_squared()
    };
    for k in 0..n as usize {
        let candidates = 10 * (k + 1);
        let mut best = Vec2::ZERO;
        let mut best_distance = -1.0f32;
        for _ in 0..candidates {
            let c = Vec2::new(rng.next_f32(), rng.next_f32());
            let nearest = points
                .iter()
                .map(|&p| toroidal(p, c))
                .fold(f32::INFINITY, f32::min);
            if nearest > best_distance {
                best_distance = nearest;
                best = c;
            }
        }
        points.push(best);
    }
    points
}

crate::named_enum! {
    /// A reconstruction filter for resolves and accumulation.
    pub enum Filter {
        /// Box over the pixel (radius 0.5): plain averaging.
        Box => "box",
        /// Tent, radius 1.
        Tent => "tent",
        /// Gaussian with sigma 0.5, truncated at radius 1.5.
        Gaussian => "gaussian",
        /// Blackman-Harris window over radius 1.5.
        BlackmanHarris => "blackman-harris",
    }
}

impl Filter {
    /// Support radius in pixels.
    pub fn radius(self) -> f32 {
        match self {
            Self::Box => 0.5,
            Self::Tent => 1.0,
            Self::Gaussian | Self::BlackmanHarris => 1.5,
        }
    }

    /// 1D weight at distance `x` (pixels) from the pixel centre; the 2D filter is separable.
    pub fn weight_1d(self, x: f32) -> f32 {
        let ax = x.abs();
        let r = self.radius();
        if ax > r || (self == Self::Box && ax == r) {
            return 0.0;
        }
        match self {
            Self::Box => 1.0,
            Self::Tent => 1.0 - ax,
            Self::Gaussian => (-2.0 * x * x).exp(),
            Self::BlackmanHarris => {
                let t = 0.5 + 0.5 * x / r;
                let tau = std::f32::consts::TAU;
                0.35875 - 0.48829 * (tau * t).cos() + 0.14128 * (2.0 * tau * t).cos()
                    - 0.01168 * (3.0 * tau * t).cos()
            }
        }
    }
}

/// Number of sample slots per neighbour in a gather table (the most MSAA samples supported).
pub const GATHER_SLOTS: usize = 16;

/// Index of sample `s` of the neighbour at (`dx`, `dy`) (each in -1..=1) in a gather table.
pub fn gather_index(dx: i32, dy: i32, s: usize) -> usize {
    (((dy + 1) * 3 + (dx + 1)) as usize) * GATHER_SLOTS + s
}

/// Normalised weights for resolving samples at `positions` (in-pixel) of a pixel's 3x3
/// neighbourhood with a separable filter centred on the pixel: a table indexed by
/// [`gather_index`]. A 3x3 neighbourhood is enough for every filter here: a sample of a
/// neighbour two pixels away is at least 1.5 px from the centre.
pub fn gather_weights(filter: Filter, positions: &[Vec2]) -> Vec<f32> {
    let mut table = vec![0.0; 9 * GATHER_SLOTS];
    for dy in -1..=1 {
        for dx in -1..=1 {
            for (s, p) in positions.iter().enumerate().take(GATHER_SLOTS) {
                let d = Vec2::new(dx as f32, dy as f32) + *p - Vec2::splat(0.5);
                table[gather_index(dx, dy, s)] = filter.weight_1d(d.x) * filter.weight_1d(d.y);
            }
        }
    }
    normalise(table)
}

/// Weights of the box resolve as a gather table: each of the pixel's own `samples` samples
/// weighs 1 / samples (what the hardware resolve computes), for the custom resolve's
/// luminance-weighted box.
pub fn own_sample_weights(samples: u32) -> Vec<f32> {
    let n = (samples as usize).clamp(1, GATHER_SLOTS);
    let mut table = vec![0.0; 9 * GATHER_SLOTS];
    for s in 0..n {
        table[gather_index(0, 0, s)] = 1.0 / n as f32;
    }
    table
}

/// Weights of the quincunx-style resolve (after NVIDIA's Quincunx, as the thesis describes it):
/// half the pixel's own samples, plus an eighth for each of the pixel's four corners, a corner
/// being the mean of the samples of the four pixels around it that lie in the quadrant touching
/// that corner.
pub fn quincunx_weights(positions: &[Vec2]) -> Vec<f32> {
    let n = positions.len().min(GATHER_SLOTS);
    let mut table = vec![0.0; 9 * GATHER_SLOTS];
    for s in 0..n {
        table[gather_index(0, 0, s)] += 0.5 / n as f32;
    }
    for corner in [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
    ] {
        let mut members = Vec::new();
        for dy in -1..=1 {
            for dx in -1..=1 {
                for (s, p) in positions.iter().enumerate().take(n) {
                    let d = (Vec2::new(dx as f32, dy as f32) + *p - corner).abs();
                    if d.x <= 0.5 && d.y <= 0.5 {
                        members.push(gather_index(dx, dy, s));
                    }
                }
            }
        }
        for &m in &members {
            table[m] += 0.125 / members.len() as f32;
        }
    }
    normalise(table)
}

fn normalise(mut table: Vec<f32>) -> Vec<f32> {
    let total: f32 = table.iter().sum();
    if total > 0.0 {
        table.iter_mut().for_each(|w| *w /= total);
    }
    table
}

/// Unnormalised weights of one jittered render (sample at `position` inside every pixel) for
/// the 3x3 neighbourhood of an output pixel, index (dy + 1) * 3 + (dx + 1).
fn neighbourhood_weights(filter: Filter, position: Vec2) -> [f32; 9] {
    let mut w = [0.0; 9];
    for dy in -1..=1 {
        for dx in -1..=1 {
            let d = Vec2::new(dx as f32, dy as f32) + position - Vec2::splat(0.5);
            w[((dy + 1) * 3 + (dx + 1)) as usize] = filter.weight_1d(d.x) * filter.weight_1d(d.y);
        }
    }
    w
}

/// Per-sample 3x3 weights for jittered accumulation, normalised so that the weights of all
/// samples together sum to one (every pixel sees the same pattern, so one normaliser serves
/// the whole image).
pub fn accumulation_weights(filter: Filter, positions: &[Vec2]) -> Vec<[f32; 9]> {
    let raw: Vec<[f32; 9]> = positions
        .iter()
        .map(|&p| neighbourhood_weights(filter, p))
        .collect();
    let total: f32 = raw.iter().flatten().sum();
    raw.into_iter()
        .map(|w| w.map(|x| if total > 0.0 { x / total } else { 0.0 }))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_positions_are_inside_and_centred() {
        for n in [1, 2, 4, 8, 16] {
            let p = standard_msaa_positions(n).unwrap();
            assert_eq!(p.len(), n as usize);
            let mean = p.iter().copied().sum::<Vec2>() / n as f32;
            assert!((mean - Vec2::splat(0.5)).length() < 0.07, "{n}: {mean}");
            assert!(
                p.iter()
                    .all(|q| q.cmpge(Vec2::ZERO).all() && q.cmplt(Vec2::ONE).all())
            );
        }
        assert_eq!(
            standard_msaa_positions(4).unwrap()[0],
            Vec2::new(0.375, 0.125)
        );
        assert!(standard_msaa_positions(3).is_none());
    }

    #[test]
    fn halton_matches_hand_values() {
        assert_eq!(halton(1, 2), 0.5);
        assert_eq!(halton(2, 2), 0.25);
        assert_eq!(halton(3, 2), 0.75);
        assert!((halton(1, 3) - 1.0 / 3.0).abs() < 1e-7);
        assert!((halton(2, 3) - 2.0 / 3.0).abs() < 1e-7);
        assert!((halton(4, 3) - 4.0 / 9.0).abs() < 1e-7);
    }

    #[test]
    fn rotated_grid_is_n_rooks_and_rgss_for_four() {
        for m in 1..=8u32 {
            let n = m * m;
            let p = Pattern::RotatedGrid.positions(n);
            let mut xs: Vec<u32> = p.iter().map(|q| (q.x * n as f32) as u32).collect();
            let mut ys: Vec<u32> = p.iter().map(|q| (q.y * n as f32) as u32).collect();
            xs.sort_unstable();
            ys.sort_unstable();
            assert_eq!(xs, (0..n).collect::<Vec<_>>(), "x of {n}");
            assert_eq!(ys, (0..n).collect::<Vec<_>>(), "y of {n}");
        }
        // RGSS: every row and column of the 4x4 sub-grid once, not on a diagonal.
        let p = Pattern::RotatedGrid.positions(4);
        assert!(p.iter().any(|q| (q.x - q.y).abs() > 0.2));
    }

    #[test]
    fn patterns_have_requested_counts_and_stay_in_pixel() {
        for pattern in [
            Pattern::Grid,
            Pattern::RotatedGrid,
            Pattern::Random,
            Pattern::Poisson,
            Pattern::Halton,
        ] {
            for n in [1, 4, 16, 64, 256] {
                let p = pattern.positions(n);
                assert_eq!(p.len() as u32, pattern.effective_count(n));
                assert!(
                    p.iter()
                        .all(|q| q.cmpge(Vec2::ZERO).all() && q.cmplt(Vec2::ONE).all()),
                    "{pattern:?}"
                );
            }
        }
        assert_eq!(Pattern::Grid.effective_count(10), 9);
        assert_eq!(Pattern::Halton.effective_count(10), 10);
    }

    #[test]
    fn poisson_keeps_samples_apart() {
        let p = Pattern::Poisson.positions(16);
        let random = Pattern::Random.positions(16);
        let min_distance = |pts: &[Vec2]| {
            let mut best = f32::INFINITY;
            for (i, a) in pts.iter().enumerate() {
                for b in &pts[i + 1..] {
                    best = best.min(a.distance(*b));
                }
            }
            best
        };
        assert!(min_distance(&p) > 0.12, "{}", min_distance(&p));
        assert!(min_distance(&p) > min_distance(&random));
    }

    #[test]
    fn filters_peak_at_centre_and_vanish_at_radius() {
        for f in [Filter::Tent, Filter::Gaussian, Filter::BlackmanHarris] {
            assert!(f.weight_1d(0.0) > f.weight_1d(0.5));
            assert!(f.weight_1d(f.radius() + 0.01) == 0.0);
            assert!((f.weight_1d(0.3) - f.weight_1d(-0.3)).abs() < 1e-6);
        }
        assert!(Filter::BlackmanHarris.weight_1d(1.5).abs() < 1e-4);
        assert_eq!(Filter::Box.weight_1d(0.49), 1.0);
        assert_eq!(Filter::Box.weight_1d(0.5), 0.0);
    }

    #[test]
    fn box_gather_is_the_plain_average() {
        let positions = standard_msaa_positions(4).unwrap();
        let table = gather_weights(Filter::Box, &positions);
        for s in 0..4 {
            assert!((table[gather_index(0, 0, s)] - 0.25).abs() < 1e-6);
        }
        assert!((table.iter().sum::<f32>() - 1.0).abs() < 1e-5);
    }

    #[test]
    fn wide_filters_reach_neighbours_and_sum_to_one() {
        let positions = standard_msaa_positions(4).unwrap();
        for f in [Filter::Tent, Filter::Gaussian, Filter::BlackmanHarris] {
            let table = gather_weights(f, &positions);
            assert!((table.iter().sum::<f32>() - 1.0).abs() < 1e-5);
            let own: f32 = (0..4).map(|s| table[gather_index(0, 0, s)]).sum();
            assert!(own < 1.0 && own > 0.3, "{f:?}: own weight {own}");
        }
    }

    #[test]
    fn quincunx_is_half_centre_and_eighth_per_corner() {
        let positions = standard_msaa_positions(4).unwrap();
        let table = quincunx_weights(&positions);
        let own_box: f32 = 0.5;
        assert!((table.iter().sum::<f32>() - 1.0).abs() < 1e-5);
        // Own samples get the centre half plus their share of the corners they touch.
        let own: f32 = (0..4).map(|s| table[gather_index(0, 0, s)]).sum();
        assert!(own > own_box && own < 1.0, "{own}");
        // Every diagonal neighbour contributes to exactly one corner.
        assert!((0..4).any(|s| table[gather_index(1, 1, s)] > 0.0));
    }

    #[test]
    fn accumulation_weights_of_a_box_grid_average_each_pixel() {
        let positions = Pattern::Grid.positions(16);
        let weights = accumulation_weights(Filter::Box, &positions);
        let own: f32 = weights.iter().map(|w| w[4]).sum();
        assert!((own - 1.0).abs() < 1e-5, "{own}");
        assert!(weights.iter().all(|w| (w[4] - 1.0 / 16.0).abs() < 1e-6));
    }
}
